#!/usr/bin/env bash
# The two hosts side by side (docs/RESULTS.md, "Two hosts"): 512x512 frame
# time of the native host and of lavapipe for the far, mid and close views of
# the bumpy sphere (256^3) and the bunny (256^3 and 512^3), each the median of
# 3 frames of one renderer; an all-miss frame on both hosts; and OpenVDB's
# vdb_render of the bunny's level set at the same cameras at 1 and 16 samples
# per pixel (median of 3 runs). One run, one machine: compare the ratios.
#   scripts/bench_hosts.sh [SIZE [OUTDIR]]   default: 512, images to a temporary directory
# Needs the build (scripts/setup.sh); installs libcgal-demo (the bunny) and
# libopenvdb-tools (vdb_tool, vdb_render) if missing.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SVO="${SVO:-$ROOT/build/svo}"
SIZE="${1:-512}"

source "$ROOT/scripts/bench_common.sh"
need_packages libcgal-demo libopenvdb-tools

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
OUT="${2:-$WORK/images}"
mkdir -p "$OUT"
extract_bunny "$WORK"
OFF="$WORK/data/meshes/bunny00.off"

echo "Machine: $(nproc) cores, $(awk '/model name/ {sub(/.*: /, ""); print; exit}' /proc/cpuinfo); $("$SVO" devices | tr '\n' ' ' | sed 's/  */ /g')"
"$SVO" voxelize --scene bumpy-sphere --resolution 256 -o "$WORK/bumpy-sphere-256.svo" > /dev/null
"$SVO" voxelize "$OFF" --resolution 256 -o "$WORK/bunny-256.svo" > /dev/null
"$SVO" voxelize "$OFF" --resolution 512 -o "$WORK/bunny-512.svo" > /dev/null
vdb_tool -read "$WORK/bunny.obj" -mesh2ls dim=504 -write "$WORK/bunny.vdb" > /dev/null 2>&1

# ms of one render: median of 3 frames of one renderer (svo render --repeats 3).
frame_ms() {
  "$SVO" render "$@" --width "$SIZE" --height "$SIZE" --repeats 3 --json |
    python3 -c 'import json, sys; j = json.load(sys.stdin); print("%.0f %.1f" % (j["ms"], j["steps_per_pixel"]))'
}

echo
echo "| scene | view | native ms | lavapipe ms | lavapipe / native | steps per pixel |"
echo "|---|---|---|---|---|---|"
for scene in bumpy-sphere-256 bunny-256 bunny-512; do
  for view in far mid close; do
    read -r native steps < <(frame_ms "$WORK/$scene.svo" -o "$OUT/$scene-$view-native.exr" --view "$view" \
      --device native --save-camera "$WORK/$scene-$view.json")
    read -r lavapipe _ < <(frame_ms "$WORK/$scene.svo" -o "$OUT/$scene-$view-lavapipe.exr" --view "$view" --device llvmpipe)
    echo "| $scene | $view | $native | $lavapipe | $(python3 -c "print(f'{$lavapipe / $native:.2f}')") | $steps |"
  done
done

echo
echo "All-miss frame (the camera looks away from the domain) against the mid view, bumpy sphere 256^3:"
echo "| host | all-miss ms | mid ms | all-miss / mid |"
echo "|---|---|---|---|"
for device in native llvmpipe; do
  read -r miss _ < <(frame_ms "$WORK/bumpy-sphere-256.svo" -o "$OUT/miss-$device.exr" --camera 0,0,3,0,0,6,0,1,0,40 --device "$device")
  read -r mid _ < <(frame_ms "$WORK/bumpy-sphere-256.svo" -o "$OUT/mid-$device.exr" --view mid --device "$device")
  echo "| $device | $miss | $mid | $(python3 -c "print(f'{$miss / $mid:.3f}')") |"
done

echo
echo "OpenVDB vdb_render of the bunny level set (dim 504, diffuse shader, all cores), the cameras of bunny-256 and bunny-512"
echo "(median of 3 runs, ray tracing only):"
echo "| camera | view | 1 spp ms | 16 spp ms |"
echo "|---|---|---|---|"
for scene in bunny-256 bunny-512; do
  for view in far mid close; do
    read -r eye target up fov < <(python3 -c '
import json, sys
c = json.load(open(sys.argv[1]))
f = lambda v: ",".join(f"{x:.6g}" for x in v)
print(f(c["eye"]), f(c["target"]), f(c["up"]), c["fov"])' "$WORK/$scene-$view.json")
    row="| $scene | $view |"
    for spp in 1 16; do
      times=()
      for _ in 1 2 3; do
        times+=("$(vdb_render "$WORK/bunny.vdb" "$OUT/vdb-$scene-$view-$spp.png" -res "${SIZE}x${SIZE}" -translate "$eye" \
          -lookat "$target" -up "$up" -fov "$fov" -samples "$spp" -cpus 0 -v 2>&1 |
          awk '/ray-tracing/ {t=1} t && /completed in/ {sub(/.*completed in /, ""); printf "%.0f", $1 * 1000; exit}')")
      done
      row="$row $(printf '%s\n' "${times[@]}" | sort -n | sed -n 2p) |"
    done
    echo "$row"
  done
done
echo
echo "Images: $OUT"
