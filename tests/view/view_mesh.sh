#!/bin/sh
# svo view MESH under Xvfb (labels: cli, view): a mesh (an OFF cube) is
# voxelized first, with a progress bar on a terminal (script(1) gives it one)
# and a summary line, then shown; the exit screenshot must hold the cube at
# the window's size. A file that is neither an octree nor a mesh is refused
# with one line naming the accepted types (no display needed).
# Skipped (exit 77) where xvfb-run or script is not installed.
# usage: view_mesh.sh SVO IMAGE_CHECK OUT_DIR
set -u
svo=$1 check=$2 dir=$3
work="$dir/view_mesh"
rm -rf "$work"
mkdir -p "$work" || exit 1

printf 'not a mesh\n' >"$work/notes.txt"
echo "+ svo view $work/notes.txt"
message=$(env -u DISPLAY -u WAYLAND_DISPLAY "$svo" view "$work/notes.txt" 2>&1)
status=$?
echo "$message"
[ $status -eq 1 ] || { echo "exit $status, expected 1"; exit 1; }
[ "$message" = "svo: view: $work/notes.txt: not a file svo view opens (an octree: .svo; voxelized first: a mesh, .obj, .ply, .off, .stl, .gltf, .glb, or an OpenVDB level set, .vdb)" ] ||
  { echo "unexpected message"; exit 1; }

for tool in xvfb-run script; do
  if ! command -v $tool >/dev/null 2>&1; then
    echo "$tool not found (Debian packages xvfb, bsdutils): skipped"
    exit 77
  fi
done
cat >"$work/cube.off" <<'EOF'
OFF
8 6 0
-1 -1 -1
1 -1 -1
1 1 -1
-1 1 -1
-1 -1 1
1 -1 1
1 1 1
-1 1 1
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 2 3 7 6
4 1 2 6 5
4 0 4 7 3
EOF
shot="$work/cube.png"
command="'$svo' view '$work/cube.off' --resolution 32 --width 200 --height 150 --scale 0.5 --frames 2 --validate --screenshot '$shot'"
echo "+ xvfb-run -a script -qec \"$command\" /dev/null"
xvfb-run -a -s "-screen 0 640x480x24" script -qec "$command" /dev/null >"$work/output.txt" 2>&1
status=$?
tr '\r' '\n' <"$work/output.txt"
[ $status -eq 0 ] || { echo "svo view exited with $status"; exit 1; }
grep -q "voxelize \[#* *\] *[0-9]*%" "$work/output.txt" || { echo "no progress bar"; exit 1; }
grep -q "cube.off: voxelized at 32^3 in " "$work/output.txt" || { echo "no summary line"; exit 1; }
"$check" "$shot" 200 150 || exit 1
echo "OK"
