#!/usr/bin/env bash
# Image-based lighting, the baseline curve of the shading modules
# (docs/RESULTS.md, "Image-based lighting"): the bumpy sphere and the bunny
# (256^3) under two blender-data maps with three materials (a MERL-format
# file exported from an analytic fit, GGX, Lambert); the forward pass at
# 16, 64 and 256 samples per pixel on the native host and on lavapipe (frame
# time: the median of 3 frames, the trace pass included; the forward pass's
# own time beside it), and relMSE of the native frame against `svo reference`
# (1024 samples per pixel, the exact geometry) at the mid view. One run, one
# machine: compare the ratios.
#   scripts/bench_lighting.sh [SIZE [OUTDIR]]   default: 256, images to a temporary directory
# Needs the build (scripts/setup.sh); installs libcgal-demo (the bunny) and
# blender-data (the maps) if missing.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SVO="${SVO:-$ROOT/build/svo}"
SIZE="${1:-256}"
REF_SPP="${REF_SPP:-1024}"
VIEW="${VIEW:-mid}"

source "$ROOT/scripts/bench_common.sh"
need_packages libcgal-demo blender-data

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
OUT="${2:-$WORK/images}"
mkdir -p "$OUT"
extract_bunny "$WORK"
OFF="$WORK/data/meshes/bunny00.off"
MAPS=/usr/share/blender/datafiles/studiolights/world

echo "Machine: $(nproc) cores, $(awk '/model name/ {sub(/.*: /, ""); print; exit}' /proc/cpuinfo); $("$SVO" devices | tr '\n' ' ' | sed 's/  */ /g')"
"$SVO" voxelize --scene bumpy-sphere --resolution 256 -o "$WORK/bumpy-sphere.svo" > /dev/null
"$SVO" voxelize "$OFF" --resolution 256 -o "$WORK/bunny.svo" > /dev/null

# The materials: red plastic exported to MERL's format (a measured-looking
# table: diffuse red under a sharp clear coat), copper (GGX), white Lambert.
cat > "$WORK/red-plastic-fit.json" << 'JSON'
{"name": "red-plastic-fit", "brdf": "ggx", "roughness": 0.08, "f0": 0.05, "diffuse": [0.45, 0.06, 0.04]}
JSON
"$SVO" material "$WORK/red-plastic-fit.json" --export-merl "$WORK/red-plastic.binary" > /dev/null
echo '{"name": "red-plastic-merl", "brdf": "merl", "file": "red-plastic.binary"}' > "$WORK/merl.json"
echo '{"name": "copper", "brdf": "ggx", "roughness": 0.2, "f0": [0.95, 0.64, 0.54], "diffuse": 0.02}' > "$WORK/ggx.json"
echo '{"name": "white", "brdf": "lambert", "colour": [0.8, 0.8, 0.8]}' > "$WORK/lambert.json"

# "frame_ms forward_ms" of one render: median of 3 frames of one renderer.
frame_ms() {
  "$SVO" render "$@" --width "$SIZE" --height "$SIZE" --repeats 3 --json 2> /dev/null |
    python3 -c '
import json, sys
j = json.load(sys.stdin)
fwd = [p["ms"] for p in j["passes"] if p["name"] == "forward"]
print("%.0f %.0f" % (j["ms"], fwd[0] if fwd else -1))'
}
relmse() { "$SVO" compare "$1" "$2" --json | python3 -c 'import json, sys; print("%.5f" % json.load(sys.stdin)["relmse"])'; }

echo
echo "| scene | map | material | spp | native ms (forward) | lavapipe ms (forward) | relMSE vs reference |"
echo "|---|---|---|---|---|---|---|"
for scene in bumpy-sphere bunny; do
  if [ "$scene" = bunny ]; then source_args=("$OFF"); else source_args=(--scene bumpy-sphere); fi
  for map in forest sunset; do
    for material in merl ggx lambert; do
      light=(--env "$MAPS/$map.exr" --material "$WORK/$material.json" --view "$VIEW")
      ref="$OUT/$scene-$map-$material-reference.exr"
      "$SVO" reference "${source_args[@]}" --octree "$WORK/$scene.svo" "${light[@]}" --width "$SIZE" --height "$SIZE" \
        --spp "$REF_SPP" -o "$ref" > /dev/null 2>&1
      for spp in 16 64 256; do
        img="$OUT/$scene-$map-$material-$spp"
        read -r native native_fwd < <(frame_ms "$WORK/$scene.svo" -o "$img-native.exr" "${light[@]}" --spp "$spp" \
          --device native)
        read -r lavapipe lavapipe_fwd < <(frame_ms "$WORK/$scene.svo" -o "$img-lavapipe.exr" "${light[@]}" \
          --spp "$spp" --device llvmpipe)
        echo "| $scene | $map | $material | $spp | $native ($native_fwd) | $lavapipe ($lavapipe_fwd) |" \
          "$(relmse "$img-native.exr" "$ref") |"
      done
    done
  done
done
