#!/usr/bin/env bash
# Issue 17's headline on any host: adaptive against forward shading at equal
# relMSE, from plain `svo render` command lines, so that a lent GPU (through
# the svo-render bundle, scripts/gpu-figures.sh) and the native host run the
# same frames. The sweep is `svo bench bandwidth`'s part 1 (forward at 8-128
# spp; adaptive at tau 10, 30, 100 with Eq. 9's bound and 0.003, 0.01, 0.03
# with the measured variance) on the bunny and the elephant at 256^3, far
# view, 512x512, forest map, diffuse and glossy materials.
#
#   scripts/adaptive-sweep.sh prepare DIR        octrees and materials into DIR
#   scripts/adaptive-sweep.sh run SVO DIR OUT EXT [RENDER-ARGS...]
#        renders every frame of the sweep: OUT/NAME.EXT and OUT/NAME.json
#        (svo render --json); SVO is `svo` or the bundle's `svo-render`
#   scripts/adaptive-sweep.sh truth SVO DIR OUT  the references (svo reference, 64 spp)
#   scripts/adaptive-sweep.sh table OUT [--png-reference OUT_PNG] [HOST_OUT ...]
#        relMSE of OUT's EXR frames against the references (svo compare), then
#        per host (the frames of `run ... png` on each host: native, a GPU) the
#        speed-up at equal relMSE, and whether the hosts' PNGs agree
#        (scripts/adaptive_sweep_table.py)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCENES=(bunny elephant)
MATERIALS=(diffuse glossy)
SPP=(8 16 32 64 128)
BOUND=(10 30 100)
MEASURED=(0.003 0.01 0.03)
REPEATS="${SWEEP_REPEATS:-3}"

# frames: NAME ARGS..., one per line
frames() {
  local dir=$1 s m
  for s in "${SCENES[@]}"; do
    for m in "${MATERIALS[@]}"; do
      local common="$dir/$s.svo --view far --width 512 --height 512 --env $dir/env.exr --material $dir/$m.json"
      for n in "${SPP[@]}"; do echo "$s-$m-forward-$n $common --shading forward --spp $n"; done
      for t in "${BOUND[@]}"; do echo "$s-$m-bound-$t $common --shading adaptive --adaptive-variance bound --adaptive-tau $t"; done
      for t in "${MEASURED[@]}"; do echo "$s-$m-measured-$t $common --shading adaptive --adaptive-variance measured --adaptive-tau $t"; done
    done
  done
}

case "${1:-}" in
  prepare)
    dir=$2
    mkdir -p "$dir"
    svo="${SVO:-$ROOT/build/svo}"
    for s in "${SCENES[@]}"; do
      tar -xzOf /usr/share/doc/libcgal-dev/data.tar.gz "data/meshes/${s/bunny/bunny00}.off" > "$dir/$s.off"
      "$svo" voxelize "$dir/$s.off" --resolution 256 -o "$dir/$s.svo" > /dev/null
    done
    # bench_material() in tools/cmd_bench_bandwidth.cpp
    echo '{"brdf": "lambert", "diffuse": [0.8, 0.8, 0.8]}' > "$dir/diffuse.json"
    echo '{"brdf": "ggx", "roughness": 0.25, "diffuse": [0.5, 0.5, 0.5], "f0": [0.04, 0.04, 0.04]}' > "$dir/glossy.json"
    cp /usr/share/blender/datafiles/studiolights/world/forest.exr "$dir/env.exr"
    ;;
  run)
    svo=$2 dir=$3 out=$4 ext=$5
    shift 5
    mkdir -p "$out"
    frames "$dir" | while read -r name args; do
      # shellcheck disable=SC2086
      "$svo" render $args --repeats "$REPEATS" --json -o "$out/$name.$ext" "$@" > "$out/$name.json" < /dev/null \
        || echo "$name failed" >&2
    done
    ;;
  truth)
    svo=$2 dir=$3 out=$4
    mkdir -p "$out"
    for s in "${SCENES[@]}"; do
      for m in "${MATERIALS[@]}"; do
        "$svo" reference "$dir/$s.off" --octree "$dir/$s.svo" --view far --width 512 --height 512 --env "$dir/env.exr" \
          --material "$dir/$m.json" --spp 64 -o "$out/$s-$m-truth.exr" > /dev/null
      done
    done
    ;;
  table)
    out=$2
    shift 2
    svo="${SVO:-$ROOT/build/svo}"
    for f in "$out"/*-forward-*.exr "$out"/*-bound-*.exr "$out"/*-measured-*.exr; do
      name=$(basename "$f" .exr)
      "$svo" compare "$f" "$out/$(echo "$name" | cut -d- -f1-2)-truth.exr" --json > "$out/$name.compare.json"
    done
    /usr/bin/python3 "$ROOT/scripts/adaptive_sweep_table.py" "$out" "$@"
    ;;
  *)
    sed -n '2,/^set -euo/p' "$0" | sed '$d' >&2
    exit 2
    ;;
esac
