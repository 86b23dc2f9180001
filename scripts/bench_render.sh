#!/usr/bin/env bash
# Cone tracer cost per view, mode and shadows, for the bumpy sphere and the
# Stanford bunny, and OpenVDB's vdb_render of the same bunny level set with
# the same camera at 1 and 4 samples per pixel, in the same run
# (docs/RESULTS.md, issue 4).
#   scripts/bench_render.sh [RESOLUTION [SIZE [OUTDIR]]]   default: 512 512, images to a temporary directory
# Needs the build (scripts/setup.sh); installs libcgal-demo (the bunny) and
# libopenvdb-tools (vdb_tool, vdb_render) if missing.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SVO="${SVO:-$ROOT/build/svo}"
RES="${1:-512}"
SIZE="${2:-512}"

source "$ROOT/scripts/bench_common.sh"
need_packages libcgal-demo libopenvdb-tools

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
OUT="${3:-$WORK/images}"
mkdir -p "$OUT"
extract_bunny "$WORK"
OFF="$WORK/data/meshes/bunny00.off"

echo "Machine: $(nproc) cores, $(awk '/model name/ {sub(/.*: /, ""); print; exit}' /proc/cpuinfo); device: $("$SVO" devices --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["devices"][0]["name"])')"
"$SVO" voxelize --scene bumpy-sphere --resolution "$RES" -o "$WORK/bumpy-sphere.svo" > /dev/null
"$SVO" voxelize "$OFF" --resolution "$RES" -o "$WORK/bunny.svo" > /dev/null
vdb_tool -read "$WORK/bunny.obj" -mesh2ls dim=$((RES - 8)) -write "$WORK/bunny.vdb" > /dev/null 2>&1

echo
echo "| scene | view | mode | shadows | ms | us per covered pixel | us per pixel | steps per pixel | covered pixels |"
echo "|---|---|---|---|---|---|---|---|---|"
for scene in bumpy-sphere bunny; do
  for view in far mid close; do
    for mode in prefiltered nearest alpha mip; do
      for shadows in no yes; do
        flag=(); [ "$shadows" = yes ] && flag=(--shadows)
        "$SVO" render "$WORK/$scene.svo" -o "$OUT/$scene-$view-$mode-$shadows.png" --view "$view" --mode "$mode" \
          --width "$SIZE" --height "$SIZE" "${flag[@]}" --json --save-camera "$WORK/$scene-$view.json" > "$WORK/r.json"
        python3 - "$scene" "$view" "$mode" "$shadows" "$WORK/r.json" <<'PY'
import json, sys
scene, view, mode, shadows, path = sys.argv[1:]
j = json.load(open(path))
us = j["us_per_pixel"]
per = j["ms"] * 1000 / (j["width"] * j["height"])
print(f"| {scene} | {view} | {mode} | {shadows} | {j['ms']:.0f} | {us:.2f} | {per:.2f} | {j['steps_per_pixel']:.1f} | {j['covered_pixels']:,} |" if us is not None
      else f"| {scene} | {view} | {mode} | {shadows} | {j['ms']:.0f} | - | {per:.2f} | {j['steps_per_pixel']:.1f} | 0 |")
PY
      done
    done
  done
done

echo
echo "OpenVDB vdb_render of the bunny level set (dim $((RES - 8)), diffuse shader, all cores), same cameras:"
echo "| view | samples per pixel | ms (ray tracing only) |"
echo "|---|---|---|"
for view in far mid close; do
  read -r eye target up fov < <(python3 -c '
import json, sys
c = json.load(open(sys.argv[1]))
f = lambda v: ",".join(f"{x:.6g}" for x in v)
print(f(c["eye"]), f(c["target"]), f(c["up"]), c["fov"])' "$WORK/bunny-$view.json")
  for spp in 1 4; do
    ms=$(vdb_render "$WORK/bunny.vdb" "$OUT/vdb-bunny-$view-$spp.png" -res "${SIZE}x${SIZE}" -translate "$eye" \
      -lookat "$target" -up "$up" -fov "$fov" -samples "$spp" -cpus 0 -v 2>&1 |
      awk '/ray-tracing/ {t=1} t && /completed in/ {sub(/.*completed in /, ""); printf "%.0f", $1 * 1000; exit}')
    echo "| $view | $spp | $ms |"
  done
done
echo
echo "Images: $OUT"
