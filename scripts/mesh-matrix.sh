#!/usr/bin/env bash
# Issue 20's table: libcgal-demo meshes at 256^3 and 512^3, far, mid and a
# defocused view (the far camera through a lens of radius 0.041 and focus
# 1.23 eye distances), 512x512, each rendered by two svo executables
# (before and after a change) against one `svo reference --spp 64`, as a
# Markdown row each: relMSE, PSNR, pixels off by more than 0.25 away from
# silhouettes, the 99.9th percentile error and specks (svo compare --json).
#   scripts/mesh-matrix.sh BEFORE_SVO AFTER_SVO OUT_DIR MESH...   e.g. bunny00 armadillo lion
# RESOLUTIONS="256 512" by default. The reference uses AFTER's octree and camera.
set -euo pipefail
[ $# -ge 4 ] || { sed -n '2,10p' "$0"; exit 1; }
before=$(realpath "$1") after=$(realpath "$2") out=$3
shift 3
mkdir -p "$out"
cd "$out"
archive=/usr/share/doc/libcgal-dev/data.tar.gz
for mesh in "$@"; do
  tar xzf "$archive" "data/meshes/$mesh.off"
  m="data/meshes/$mesh.off"
  for res in ${RESOLUTIONS:-256 512}; do
    "$before" voxelize "$m" -o before.svo --resolution "$res" > /dev/null 2>&1
    "$after" voxelize "$m" -o after.svo --resolution "$res" > /dev/null 2>&1
    for view in far mid dof; do
      base="$mesh-$res-$view"
      preset=$view
      [ "$view" = dof ] && preset=far
      "$after" render after.svo --view "$preset" -o preset.exr --json > frame.json
      python3 - "$view" > "camera-$base.json" <<'PY'
import json, math, sys
c = json.load(open("frame.json"))["camera"]
if sys.argv[1] == "dof":
    d = math.dist(c["eye"], c["target"])
    c["aperture"], c["focus"] = 0.041 * d, 1.23 * d
print(json.dumps(c))
PY
      "$after" reference "$m" --octree after.svo --camera-file "camera-$base.json" --spp 64 -o "reference-$base.exr" > /dev/null
      "$before" render before.svo --camera-file "camera-$base.json" -o "before-$base.exr" > /dev/null
      "$after" render after.svo --camera-file "camera-$base.json" -o "after-$base.exr" > /dev/null
      for w in before after; do "$after" compare "$w-$base.exr" "reference-$base.exr" --json > "compare-$w-$base.json"; done
      python3 - "$mesh" "$res" "$view" <<'PY'
import json, sys
mesh, res, view = sys.argv[1:]
b, a = (json.load(open("compare-%s-%s-%s-%s.json" % (w, mesh, res, view))) for w in ("before", "after"))
print("| %s | %s | %s | %.4g / %.4g | %.2f / %.2f | %d / %d | %.3f / %.3f | %d / %d |" % (
    mesh, res, view, b["relmse"], a["relmse"], b["psnr"], a["psnr"], b["outliers"], a["outliers"],
    b["p999_error"], a["p999_error"], b["specks"], a["specks"]), flush=True)
PY
    done
  done
done
rm -f before.svo after.svo preset.exr frame.json
