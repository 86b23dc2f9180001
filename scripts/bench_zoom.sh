#!/usr/bin/env bash
# Deep zoom (docs/RESULTS.md, issue 6): the per-frame cost of svo flythrough
# along two deep-zoom paths (towards the surface point at the far view's
# centre, and towards the silhouette), the paper's cost table picked from
# them, and the temporal-coherence and colour-shift figures of svo bench zoom
# against the ground truth.
#   scripts/bench_zoom.sh OUTDIR [SOURCE OPTIONS...]
# SOURCE OPTIONS name the surface for both svo voxelize and the ground truth
# (default: --scene bumpy-sphere); add e.g. --detail-octaves 4
# --detail-amplitude A once the voxelizer and svo reference take them.
# Environment (defaults): SVO (build/svo), RESOLUTION (512), FRAMES (60),
# SIZE (512), ZOOM (1000), REPEATS (3: median GPU time per frame),
# COHERENCE_FRAMES (24), COHERENCE_SIZE (128), SPP (64), KEEP_SVO (unset:
# voxelize again even when OUTDIR/octree.svo exists).
# With 11 detail octaves the ground truth costs ~4x more per ray: the RESULTS
# run used SPP=16 COHERENCE_FRAMES=16 and FRAMES=20 REPEATS=1 there.
# Writes OUTDIR/octree.svo, OUTDIR/centre/ and OUTDIR/silhouette/ (frames,
# frames.csv, strip.png), OUTDIR/coherence/ (table.md, coherence.csv, .json,
# strip.png) and OUTDIR/summary.md.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SVO="${SVO:-$ROOT/build/svo}"
if [ $# -lt 1 ]; then
  echo "usage: $0 OUTDIR [SOURCE OPTIONS...] (default source: --scene bumpy-sphere)" >&2
  exit 1
fi
OUT="$1"
shift
SOURCE=("$@")
[ ${#SOURCE[@]} -eq 0 ] && SOURCE=(--scene bumpy-sphere)
RESOLUTION="${RESOLUTION:-512}"
FRAMES="${FRAMES:-60}"
SIZE="${SIZE:-512}"
ZOOM="${ZOOM:-1000}"
REPEATS="${REPEATS:-3}"
COHERENCE_FRAMES="${COHERENCE_FRAMES:-24}"
COHERENCE_SIZE="${COHERENCE_SIZE:-128}"
SPP="${SPP:-64}"
mkdir -p "$OUT"

echo "Machine: $(nproc) cores, $(awk '/model name/ {sub(/.*: /, ""); print; exit}' /proc/cpuinfo)"
if [ -z "${KEEP_SVO:-}" ] || [ ! -s "$OUT/octree.svo" ]; then
  echo "+ svo voxelize ${SOURCE[*]} --resolution $RESOLUTION -o $OUT/octree.svo"
  "$SVO" voxelize "${SOURCE[@]}" --resolution "$RESOLUTION" -o "$OUT/octree.svo"
fi
for aim in centre silhouette; do
  echo "+ svo flythrough $OUT/octree.svo -o $OUT/$aim --aim $aim --frames $FRAMES --zoom $ZOOM --width $SIZE --height $SIZE --repeats $REPEATS --json"
  "$SVO" flythrough "$OUT/octree.svo" -o "$OUT/$aim" --aim "$aim" --frames "$FRAMES" --zoom "$ZOOM" \
    --width "$SIZE" --height "$SIZE" --repeats "$REPEATS" --json > "$OUT/$aim.json"
done
echo "+ svo bench zoom $OUT/octree.svo ${SOURCE[*]} -o $OUT/coherence --frames $COHERENCE_FRAMES --zoom $ZOOM --width $COHERENCE_SIZE --height $COHERENCE_SIZE --spp $SPP"
"$SVO" bench zoom "$OUT/octree.svo" "${SOURCE[@]}" -o "$OUT/coherence" --frames "$COHERENCE_FRAMES" --zoom "$ZOOM" \
  --width "$COHERENCE_SIZE" --height "$COHERENCE_SIZE" --spp "$SPP" > /dev/null

python3 - "$OUT" <<'PY' | tee "$OUT/summary.md"
import csv, json, os, sys
out = sys.argv[1]
def rows(aim):
    with open(os.path.join(out, aim, "frames.csv")) as f:
        return list(csv.DictReader(f))
paths = {aim: rows(aim) for aim in ("centre", "silhouette")}
meta = json.load(open(os.path.join(out, "centre.json")))
pixels = meta["width"] * meta["height"]
print(f"Octree {out}/octree.svo: {os.path.getsize(os.path.join(out, 'octree.svo')):,} bytes (the same file for every "
      f"frame), finest level {meta['finest_level']}; {len(paths['centre'])} frames {meta['width']}x{meta['height']}, "
      f"zoom {meta['zoom']:.0f}; device {meta['device']}.\n")
def nearest(rs, zoom):
    return min(rs, key=lambda r: abs(float(r["zoom"]) / zoom - 1))
print("| view | path | frame | zoom | silhouettes in view | ms | us per pixel | us per covered pixel | steps per pixel | levels (min-max) | level at the target |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for name, zoom in (("far", 1), ("mid", 3), ("close", 30), ("closer", 1000)):
    for aim in ("centre", "silhouette"):
        r = nearest(paths[aim], zoom)
        covered = int(r["covered_pixels"])
        silh = "yes" if 0 < covered < pixels else "no"
        lv = f"{float(r['level_min']):.1f}-{float(r['level_max']):.1f}" if r["level_min"] else "-"
        upc = f"{float(r['us_per_covered_pixel']):.2f}" if r["us_per_covered_pixel"] else "-"
        print(f"| {name} | {aim} | {r['frame']} | {float(r['zoom']):.3g} | {silh} ({covered:,} covered) | "
              f"{float(r['ms']):.0f} | {float(r['us_per_pixel']):.2f} | {upc} | {float(r['steps_per_pixel']):.1f} | "
              f"{lv} | {float(r['level_target']):.1f} |")
print()
print("| path | us per covered pixel: min (frame) | max (frame) | max / min | us per pixel: max / min |")
print("|---|---|---|---|---|")
for aim, rs in paths.items():
    c = [(float(r["us_per_covered_pixel"]), r["frame"]) for r in rs if r["us_per_covered_pixel"]]
    p = [float(r["us_per_pixel"]) for r in rs]
    lo, hi = min(c), max(c)
    print(f"| {aim} | {lo[0]:.2f} ({lo[1]}) | {hi[0]:.2f} ({hi[1]}) | {hi[0] / lo[0]:.2f} | {max(p) / min(p):.2f} |")
print()
print(open(os.path.join(out, "coherence", "table.md")).read())
PY
