#!/usr/bin/env bash
# Every mesh of libcgal-demo (data/meshes/*.off, .ply, .stl) as a user would
# try it: `svo voxelize` at RESOLUTION^3 (default 128), `svo render --view
# far` at SIZE x SIZE (default 256), against `svo reference --spp SPP`
# (default 16) at the same camera, compared by `svo compare --json`. One CSV
# row a mesh (OUT_DIR/sweep.csv): how svo drew its surface (svo info), PSNR,
# relMSE, pixels off by more than 0.25 away from silhouettes, specks, the
# 99.9th percentile and the largest error, or the first line of the error
# of a step that failed. Every mesh's frame, reference and camera are kept
# (OUT_DIR/MESH-svo.exr, MESH-reference.exr, MESH-camera.json); its octree not.
#   scripts/mesh-sweep.sh SVO OUT_DIR [MESH...]     MESH: a name without the extension
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,10p' "$0"; exit 1; }
svo=$(realpath "$1") out=$2
shift 2
res=${RESOLUTION:-128} size=${SIZE:-256} spp=${SPP:-16}
archive=/usr/share/doc/libcgal-demo/data.tar.gz
mkdir -p "$out"
cd "$out"
[ -d data/meshes ] || tar xzf "$archive" data/meshes
meshes=("$@")
if ((${#meshes[@]} == 0)); then
  for f in data/meshes/*.off data/meshes/*.ply data/meshes/*.stl; do meshes+=("$(basename "$f")"); done
fi
echo "mesh,surface,psnr,relmse,pixels_off,specks,p999,max_error,failed" > sweep.csv
n=0
for name in "${meshes[@]}"; do
  n=$((n + 1))
  m=data/meshes/$name
  [ -f "$m" ] || m=$(ls data/meshes/"$name".* | head -1 || true)
  stem=$(basename "$m")
  printf '\r[%d/%d] %-40s' "$n" "${#meshes[@]}" "$stem" >&2
  failed=""
  if ! "$svo" voxelize "$m" -o "$stem.svo" --resolution "$res" > log.txt 2>&1; then
    failed="voxelize: $(grep -m1 'svo:' log.txt || head -1 log.txt)"
  elif ! "$svo" render "$stem.svo" --view far --width "$size" --height "$size" -o "$stem-svo.exr" --json > frame.json 2> log.txt; then
    failed="render: $(head -1 log.txt)"
  else
    python3 -c 'import json, sys; json.dump(json.load(open("frame.json"))["camera"], sys.stdout)' > "$stem-camera.json"
    if ! "$svo" reference "$m" --octree "$stem.svo" --camera-file "$stem-camera.json" --width "$size" --height "$size" \
      --spp "$spp" -o "$stem-reference.exr" > /dev/null 2> log.txt; then
      failed="reference: $(head -1 log.txt)"
    elif ! "$svo" compare "$stem-svo.exr" "$stem-reference.exr" --json > compare.json 2> log.txt; then
      failed="compare: $(head -1 log.txt)"
    fi
  fi
  surface=$("$svo" info "$stem.svo" 2> /dev/null | sed -n 's/^surface *//p' | head -1 || true)
  python3 - "$stem" "$surface" "$failed" >> sweep.csv << 'PY'
import csv, json, sys
stem, surface, failed = sys.argv[1:4]
row = [stem, surface]
if failed:
    row += [""] * 6 + [failed]
else:
    c = json.load(open("compare.json"))
    row += ["%.2f" % c["psnr"], "%.5f" % c["relmse"], c["outliers"], c["specks"], "%.3f" % c["p999_error"],
            "%.3f" % c["max_error"], ""]
csv.writer(sys.stdout).writerow(row)
PY
  rm -f "$stem.svo"
done
echo >&2
python3 - << 'PY'
import csv, statistics
rows = list(csv.DictReader(open("sweep.csv")))
done = [r for r in rows if not r["failed"]]
print(f"{len(rows)} meshes, {len(done)} measured, {len(rows) - len(done)} failed")
for kind, test in (("closed (solid)", lambda r: "solid" in r["surface"]), ("open (two-sided)", lambda r: "solid" not in r["surface"])):
    group = [r for r in done if test(r)]
    if not group:
        continue
    psnr = statistics.median(float(r["psnr"]) for r in group)
    off = sum(int(r["pixels_off"]) > 100 for r in group)
    specks = sum(int(r["specks"]) for r in group)
    print(f"{kind}: {len(group)}, median PSNR {psnr:.1f} dB, {off} with more than 100 pixels off, {specks} specks in all")
for r in rows:
    if r["failed"]:
        print(f"failed: {r['mesh']}: {r['failed']}")
PY
