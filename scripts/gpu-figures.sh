#!/usr/bin/env bash
# GPU figures on a lent device (issue 23), in one prepared command.
#
# Here, on the build machine (a few minutes, once):
#   scripts/gpu-figures.sh --prepare
# gathers into build/gpu-figures/, xz-compressed, the svo-render bundle
# (scripts/bundle-render-node.sh), the octrees (the bumpy sphere at 256^3
# with 6 detail octaves and the Stanford bunny at GPU_FIGURES_RES, default
# 512), a small sphere for the agreement check, a light-field luminaire and
# an environment map. The folder is what the device's `run` carries
# (`carry: ["build/gpu-figures"]`; with the working tree it must stay under
# the 64 MiB a call carries).
#
# On the device (or here, to check the script: GPU_FIGURES_DEVICE=llvmpipe
# GPU_FIGURES_SIZE=128 GPU_FIGURES_REPEATS=2):
#   scripts/gpu-figures.sh [OUT]         default OUT: $OUT, else build/gpu-figures/out
# The lent H200 (2026-12-04) lacked libglvnd, without which NVIDIA's Vulkan
# driver (libGLX_nvidia.so.0) loads but creates no instance ("Found no
# drivers"). Bring Debian's GL loaders (/work/.library/device/README.md):
# here `apt-get download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1
# libglx0 libgles2` into .gl/ (ignored), then a `run` with carry
# [".gl", "build/gpu-figures"] and the command
#   for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig;
#   GPU_FIGURES_REQUIRE=discrete GPU_FIGURES_DEADLINE=300 scripts/gpu-figures.sh /tmp/gf
# followed by packing /tmp/gf into at most 8 files under $OUT (tar).
# GPU_FIGURES_REQUIRE=discrete skips every step after the device list when
# no discrete GPU is listed, keeping the loader's messages instead.
# runs, each step under a time limit and all of them within 420 s
# (GPU_FIGURES_DEADLINE; later steps are skipped and listed as such): the device list; `selftest` (the shared math on the device
# against the C++ build); the agreement check (the small sphere rendered on
# the device and natively, compared pixel by pixel); then frames of
# GPU_FIGURES_SIZE^2 (default 1024) of the far, mid and close views of both
# octrees, GPU_FIGURES_REPEATS (default 20) each on one renderer, the median
# GPU time; then the shading passes on the sphere's mid view (forward with
# the environment, the lobe-aware filter and its normal-aware baseline,
# bandwidth-adaptive, a light-field luminaire sampled as Lu et al. and
# uniformly). Writes OUT/gpu-figures.json (one object: machine, device,
# selftest, agreement, frames, passes) and each step's output beside it.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DIR="${GPU_FIGURES_DIR:-$ROOT/build/gpu-figures}"

# A call to the device carries at most 64 MiB with the working tree (about
# 10 MiB): the inputs travel xz-compressed. A bumpy sphere at 512^3 is
# 231 MB (66 MB compressed) and does not fit; the sphere is the demo's scene
# (256^3 with 6 detail octaves, 49 MB, 16 MB compressed), the bunny 512^3
# (112 MB, 30 MB compressed).
LIMIT_BYTES=$((60 * 1024 * 1024))
if [ "${1:-}" = --prepare ]; then
  BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
  RES="${GPU_FIGURES_RES:-512}"
  rm -rf "$DIR"
  mkdir -p "$DIR"
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  "$ROOT/scripts/bundle-render-node.sh" "$tmp/node" > /dev/null
  tar -C "$tmp" -cf - node | xz -T2 -6 > "$DIR/node.tar.xz"
  svo="$BUILD_DIR/svo"
  tar -xzOf /usr/share/doc/libcgal-dev/data.tar.gz data/meshes/bunny00.off > "$tmp/bunny00.off"
  echo "gpu-figures: voxelizing (a few minutes on 2 cores)"
  "$svo" voxelize --scene bumpy-sphere --detail-octaves 6 --resolution 256 -o "$tmp/sphere.svo" > /dev/null
  "$svo" voxelize "$tmp/bunny00.off" --resolution "$RES" -o "$tmp/bunny.svo" > /dev/null
  "$svo" voxelize --scene bumpy-sphere --resolution 64 -o "$tmp/small.svo" > /dev/null
  "$svo" luminaire make headlight --resolution 64 -o "$tmp/headlight.lfl" > /dev/null
  for f in sphere.svo bunny.svo small.svo headlight.lfl; do xz -T2 -6 -c "$tmp/$f" > "$DIR/$f.xz"; done
  cp /usr/share/blender/datafiles/studiolights/world/forest.exr "$DIR/env.exr"
  cp "$ROOT/scripts/montage.py" "$DIR/"
  bytes=$(du -sb "$DIR" | cut -f1)
  tree=$(git -C "$ROOT" ls-files -z | (cd "$ROOT" && xargs -0 du -cb) | tail -1 | cut -f1)
  echo "gpu-figures: $DIR: $((bytes / 1024 / 1024)) MiB, with the working tree $(((bytes + tree) / 1024 / 1024)) MiB;" \
    "run there with carry [\"build/gpu-figures\"]"
  if ((bytes + tree > LIMIT_BYTES)); then
    echo "gpu-figures: more than 60 MiB with the working tree: a device call may not carry it" >&2
    exit 1
  fi
  exit 0
fi

OUT_DIR="${1:-${OUT:-$DIR/out}}"
mkdir -p "$OUT_DIR"
[ -f "$DIR/node.tar.xz" ] || { echo "gpu-figures: $DIR/node.tar.xz missing: run scripts/gpu-figures.sh --prepare first" >&2; exit 1; }
# The inputs unpacked into a work folder (xz, else Python's lzma).
WORK="${GPU_FIGURES_WORK:-${TMPDIR:-/tmp}/svo-gpu-figures}"
rm -rf "$WORK"
mkdir -p "$WORK"
unxz() {
  if command -v xz > /dev/null; then xz -dc "$1"; else python3 -c 'import lzma, shutil, sys; shutil.copyfileobj(lzma.open(sys.argv[1]), sys.stdout.buffer)' "$1"; fi
}
unxz "$DIR/node.tar.xz" | tar -C "$WORK" -xf -
# GPU_FIGURES_SYSTEM_VULKAN=1: the node's own Vulkan loader instead of the
# bundle's (a driver may need the loader it was installed with).
[ -n "${GPU_FIGURES_SYSTEM_VULKAN:-}" ] && rm -f "$WORK/node/lib/libvulkan.so.1"
for f in sphere.svo bunny.svo small.svo headlight.lfl; do unxz "$DIR/$f.xz" > "$WORK/$f"; done
cp "$DIR/env.exr" "$DIR/montage.py" "$WORK/"
N="$WORK/node/svo-render"
SIZE="${GPU_FIGURES_SIZE:-1024}"
REPEATS="${GPU_FIGURES_REPEATS:-20}"
DEVICE="${GPU_FIGURES_DEVICE:-}"
dev=()
[ -n "$DEVICE" ] && dev=(--device "$DEVICE")
log="$OUT_DIR/steps.txt"
: > "$log"
# step NAME SECONDS CMD...: runs CMD under a time limit, its stdout into
# OUT/NAME.out, a line in steps.txt; never stops the script.
# Steps past GPU_FIGURES_DEADLINE seconds (default 420: the whole within 8
# minutes on the device, unpacking included) are skipped and say so.
DEADLINE="${GPU_FIGURES_DEADLINE:-420}"
step() {
  local name=$1 limit=$2
  shift 2
  local left=$((DEADLINE - SECONDS))
  if ((left <= 5)); then
    echo "$name skipped (past the ${DEADLINE} s deadline)" | tee -a "$log"
    return
  fi
  ((limit > left)) && limit=$left
  local start rc=0
  start=$(date +%s%N)
  timeout "$limit" "$@" > "$OUT_DIR/$name.out" 2> "$OUT_DIR/$name.err" || rc=$?
  echo "$name rc=$rc $(( ($(date +%s%N) - start) / 1000000 )) ms" | tee -a "$log"
}

step devices 60 "$N" devices
# GPU_FIGURES_REQUIRE=discrete (the device call sets it): without such a
# device in the list, the loader's account of why is kept and every later
# step is skipped, so that no device time goes on native frames.
if [ -n "${GPU_FIGURES_REQUIRE:-}" ] && ! grep -q "($GPU_FIGURES_REQUIRE," "$OUT_DIR/devices.out"; then
  echo "no $GPU_FIGURES_REQUIRE Vulkan device listed: the loader's messages are in devices-debug.err" | tee -a "$log"
  step devices-debug 30 env VK_LOADER_DEBUG=error,warn,info "$N" devices
  DEADLINE=0
fi
step selftest 120 "$N" selftest "${dev[@]}" --json
# Agreement: the same frame on the device and natively.
step agree-device 60 "$N" render "$WORK/small.svo" -o "$OUT_DIR/agree-device.png" --view mid --width 256 --height 256 \
  --shadows "${dev[@]}" --json
step agree-native 60 "$N" render "$WORK/small.svo" -o "$OUT_DIR/agree-native.png" --view mid --width 256 --height 256 \
  --shadows --cpu --json
for scene in sphere bunny; do
  for view in far mid close; do
    step "frame-$scene-$view" 90 "$N" render "$WORK/$scene.svo" -o "$OUT_DIR/frame-$scene-$view.png" --view "$view" \
      --width "$SIZE" --height "$SIZE" --repeats "$REPEATS" "${dev[@]}" --json
  done
done
common=(render "$WORK/sphere.svo" --view mid --width "$SIZE" --height "$SIZE" --repeats "$REPEATS" "${dev[@]}" --json)
step pass-shadows 90 "$N" "${common[@]}" -o "$OUT_DIR/pass-shadows.png" --shadows
step pass-forward 90 "$N" "${common[@]}" -o "$OUT_DIR/pass-forward.png" --env "$WORK/env.exr" --spp 16
step pass-lobe-filter 90 "$N" "${common[@]}" -o "$OUT_DIR/pass-lobe-filter.png" --env "$WORK/env.exr" --spp 4 \
  --shading forward --filter lobe --upsample 2
step pass-normal-filter 90 "$N" "${common[@]}" -o "$OUT_DIR/pass-normal-filter.png" --env "$WORK/env.exr" --spp 4 \
  --shading forward --filter normal --upsample 2
step pass-adaptive 90 "$N" "${common[@]}" -o "$OUT_DIR/pass-adaptive.png" --env "$WORK/env.exr" --shading adaptive
step pass-luminaire 90 "$N" "${common[@]}" -o "$OUT_DIR/pass-luminaire.png" --luminaire "$WORK/headlight.lfl"
step pass-luminaire-uniform 90 "$N" "${common[@]}" -o "$OUT_DIR/pass-luminaire-uniform.png" --luminaire "$WORK/headlight.lfl" \
  --sampler uniform

# One JSON of the figures.
python3 - "$OUT_DIR" "$WORK" "$SIZE" "$REPEATS" << 'EOF'
import json, os, platform, sys
out, d, size, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
sys.path.insert(0, d)
from montage import read_png

def load(name):
    try:
        text = open(os.path.join(out, name + ".out")).read().strip()
        return json.loads(text.splitlines()[-1]) if text else None
    except (OSError, ValueError, IndexError):
        return None

def error(name):
    try:
        return open(os.path.join(out, name + ".err")).read().strip()[-400:] or None
    except OSError:
        return None

def frame(name):
    j = load(name)
    if not j:
        return {"error": error(name)}
    ms = j.get("ms")
    return {"ms": ms, "fps": 1000.0 / ms if ms else None, "wall_ms": j.get("wall_ms"), "warm_wall_ms": j.get("warm_wall_ms"),
            "us_per_pixel": j.get("us_per_pixel"), "steps_per_pixel": j.get("steps_per_pixel"),
            "covered_pixels": j.get("covered_pixels"), "device": j.get("device"), "passes": j.get("passes")}

result = {"machine": {"host": platform.node(), "cpu": platform.processor() or platform.machine()},
          "size": size, "repeats": repeats,
          "devices": open(os.path.join(out, "devices.out")).read() if os.path.exists(os.path.join(out, "devices.out")) else None,
          "selftest": load("selftest") or {"error": error("selftest")},
          "steps": open(os.path.join(out, "steps.txt")).read().splitlines()}
try:
    w, h, ch, a = read_png(os.path.join(out, "agree-device.png"))
    _, _, _, b = read_png(os.path.join(out, "agree-native.png"))
    diffs = [abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb)]
    result["agreement"] = {"pixels": w * h, "max_8bit_difference": max(diffs),
                           "values_off_by_more_than_2": sum(1 for v in diffs if v > 2),
                           "device": (load("agree-device") or {}).get("device")}
except (OSError, SystemExit, ValueError) as e:
    result["agreement"] = {"error": str(e)}
result["frames"] = {f"{s}-{v}": frame(f"frame-{s}-{v}") for s in ("sphere", "bunny") for v in ("far", "mid", "close")}
result["passes"] = {p: frame(f"pass-{p}") for p in ("shadows", "forward", "lobe-filter", "normal-filter", "adaptive", "luminaire",
                                                         "luminaire-uniform")}
json.dump(result, open(os.path.join(out, "gpu-figures.json"), "w"), indent=1)
print(json.dumps({k: {kk: vv.get("fps") for kk, vv in result[k].items()} for k in ("frames", "passes")}))
print("agreement:", json.dumps(result["agreement"]))
EOF
echo "gpu-figures: $OUT_DIR/gpu-figures.json"
