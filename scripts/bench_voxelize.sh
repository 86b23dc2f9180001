#!/usr/bin/env bash
# Voxelizer cost against OpenVDB's own mesh-to-level-set conversion of the
# same mesh at the same voxel size, in the same run (docs/RESULTS.md).
#   scripts/bench_voxelize.sh [RESOLUTION...]      default: 512 1024
# Needs the build (scripts/setup.sh); installs libcgal-demo (the Stanford
# bunny), libopenvdb-tools (vdb_tool) and time if missing.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SVO="${SVO:-$ROOT/build/svo}"
RESOLUTIONS=("$@")
[ ${#RESOLUTIONS[@]} -eq 0 ] && RESOLUTIONS=(512 1024)

source "$ROOT/scripts/bench_common.sh"
need_packages libcgal-demo libopenvdb-tools time

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
extract_bunny "$WORK"
OFF="$WORK/data/meshes/bunny00.off"

# The same mesh with vertex colours, smooth functions of position: one that
# varies fast (it correlates with height inside coarse voxels, so a_s is
# stored too) and one that varies slowly (colour alone).
colour_ply() {  # FREQUENCY OUT
  awk -v f="$1" 'NF==0{next} /^OFF/{next} !h{nv=$1; nf=$2; h=1;
       print "ply\nformat ascii 1.0\nelement vertex " nv "\nproperty float x\nproperty float y\nproperty float z";
       print "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face " nf;
       print "property list uchar int vertex_indices\nend_header"; next}
     nv>0{r=int(127+100*sin(f*$1)); g=int(127+100*sin(f*$2)); b=int(127+100*sin(f*$3));
          print $1,$2,$3,r,g,b; nv--; next}
     nf>0{print 3,$2,$3,$4; nf--}' "$OFF" > "$2"
}
colour_ply 40 "$WORK/bunny_colour_fast.ply"
colour_ply 4 "$WORK/bunny_colour_slow.ply"

rss_mb() { awk '/Maximum resident set size/ {printf "%.0f", $6/1024}' "$1"; }
wall_s() { awk -F': ' '/Elapsed \(wall clock\)/ {n=split($2,t,":"); s=0; for(i=1;i<=n;i++) s=s*60+t[i]; printf "%.2f", s}' "$1"; }

echo "| resolution | svo voxelize s | peak MiB | voxels | bytes/voxel | vdb_tool mesh2ls s | peak MiB | time ratio |"
echo "|---|---|---|---|---|---|---|---|"
for r in "${RESOLUTIONS[@]}"; do
  /usr/bin/time -v "$SVO" voxelize "$OFF" --resolution "$r" -o "$WORK/bunny.svo" --json > "$WORK/svo.json" 2> "$WORK/svo.time"
  # Our lattice spans resolution voxels with a margin of 4 on each side: the
  # mesh's largest dimension is resolution - 8 voxels.
  /usr/bin/time -v vdb_tool -read "$WORK/bunny.obj" -mesh2ls dim=$((r - 8)) -write "$WORK/bunny.vdb" > /dev/null 2> "$WORK/vdb.time"
  python3 - "$r" "$WORK/svo.json" "$(wall_s "$WORK/svo.time")" "$(rss_mb "$WORK/svo.time")" \
    "$(wall_s "$WORK/vdb.time")" "$(rss_mb "$WORK/vdb.time")" <<'PY'
import json, sys
r, path, svo_s, svo_mb, vdb_s, vdb_mb = sys.argv[1:]
j = json.load(open(path))
print(f"| {r} | {float(svo_s):.2f} | {svo_mb} | {j['voxels']:,} | {j['bytes_per_voxel']:.2f} | {float(vdb_s):.2f} | {vdb_mb} | {float(svo_s)/float(vdb_s):.2f} |")
PY
done

echo
echo "With vertex colours, by brick size, at ${RESOLUTIONS[0]}:"
echo "| colour | brick | channels | bricks | voxels | bytes | bytes/voxel | seconds |"
echo "|---|---|---|---|---|---|---|---|"
for variant in fast slow; do
  for b in 8 16; do
    "$SVO" voxelize "$WORK/bunny_colour_$variant.ply" --resolution "${RESOLUTIONS[0]}" --brick "$b" -o "$WORK/c.svo" --json > "$WORK/c.json"
    python3 - "$variant" "$b" "$WORK/c.json" <<'PY'
import json, sys
variant, b, path = sys.argv[1:]
j = json.load(open(path))
print(f"| {variant} | {b} | {' '.join(j['channels'])} | {j['bricks']:,} | {j['voxels']:,} | {j['bytes']/2**20:.0f} MiB | {j['bytes_per_voxel']:.2f} | {j['seconds']:.2f} |")
PY
  done
done
