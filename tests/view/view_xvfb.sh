#!/bin/sh
# svo view under Xvfb: two short runs (far prefiltered; close view, mip mode,
# shadows), each must exit 0 with validation on and save a picture that is
# neither empty nor uniform.
# usage: view_xvfb.sh SVO IMAGE_CHECK OCTREE OUT_DIR
set -u
svo=$1 check=$2 octree=$3 dir=$4
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "xvfb-run not found (Debian package xvfb): skipped"
  exit 77
fi
run() {  # NAME ARGS...: render 3 frames into a 200 x 150 window at half scale
  name=$1
  shift
  shot="$dir/view_$name.png"
  rm -f "$shot"
  echo "+ xvfb-run -a svo view $octree --width 200 --height 150 --scale 0.5 --frames 3 --validate --screenshot $shot $*"
  xvfb-run -a -s "-screen 0 640x480x24" "$svo" view "$octree" --width 200 --height 150 --scale 0.5 --frames 3 \
    --validate --screenshot "$shot" "$@"
  status=$?
  if [ "$status" -ne 0 ]; then
    echo "svo view ($name) exited with $status"
    exit 1
  fi
  "$check" "$shot" 100 75 || exit 1
}
run far
run close --view close --mode mip --shadows
echo "OK"
