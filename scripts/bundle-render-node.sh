#!/usr/bin/env bash
# Gathers svo-render (the renderer alone: tools/main_render.cpp) and the
# shared libraries a render node may lack into one folder that travels
# (issue 23): a machine lent for GPU figures, a render farm's node.
#   scripts/bundle-render-node.sh [DIR]          default DIR: build/render-node
#   scripts/bundle-render-node.sh --check [DIR]  then also run it in a clean
#                                                Debian 12 root (debootstrap)
# DIR holds:
#   svo-render        the launcher: runs bin/svo-render with DIR/lib first in
#                     the library path; on a node whose glibc is older than
#                     the files need, through the bundle's own glibc (its
#                     dynamic loader with --library-path); SVO_BUNDLED_GLIBC=1
#                     forces that
#   bin/svo-render    the executable; its shaders are compiled into it (SPIR-V arrays)
#   lib/              every library it links, the Vulkan loader included
#                     (libvulkan.so.1); the Vulkan driver is the node's own
#                     (NVIDIA's, or Mesa's lavapipe), found through its ICD files
#   lib/glibc/        the C library (libc, libm, the dynamic loader), used
#                     only where the node's is too old
#   MANIFEST.txt      the libraries with their Debian packages, sizes, and the
#                     newest glibc symbol version the files need
# The bundle must stay under 40 MiB. --check makes (once, cached in
# build/node-root) a minimal Debian 12 root with debootstrap, without any of
# the build's packages, and there: (1) renders natively and compares the
# bytes with `svo render`'s image; (2) installs Mesa's Vulkan drivers only,
# renders on lavapipe and compares with `svo render --device llvmpipe`.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
CHECK=0
if [ "${1:-}" = --check ]; then CHECK=1; shift; fi
OUT="${1:-$BUILD_DIR/render-node}"
LIMIT_MIB=40

[ -x "$BUILD_DIR/svo-render" ] || cmake --build "$BUILD_DIR" -j2 --target svo-render svo
rm -rf "$OUT"
mkdir -p "$OUT/bin" "$OUT/lib/glibc"
cp "$BUILD_DIR/svo-render" "$OUT/bin/"
strip --strip-unneeded "$OUT/bin/svo-render"

# The closure from ldd; the C library apart (the node's own is used where
# it is new enough: its GPU driver was built against it).
{
  echo "svo-render bundle, made $(date -u +%Y-%m-%dT%H:%MZ) on $(. /etc/os-release && echo "$PRETTY_NAME")"
  echo "library  package  bytes"
} > "$OUT/MANIFEST.txt"
ldd "$BUILD_DIR/svo-render" | awk '/=> \//{print $3}' | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so.* | libm.so.* | libdl.so.* | libpthread.so.* | librt.so.*) dest="$OUT/lib/glibc" ;;
    *) dest="$OUT/lib" ;;
  esac
  cp -L "$lib" "$dest/"
  pkg=$( (dpkg -S "$lib" || dpkg -S "$(readlink -f "$lib")") 2> /dev/null | head -1 | cut -d: -f1 || true)
  echo "${dest#"$OUT"/}/$(basename "$lib")  ${pkg:-?}  $(stat -c %s "$dest/$(basename "$lib")")" >> "$OUT/MANIFEST.txt"
done
loader=$(ldd "$BUILD_DIR/svo-render" | awk '/ld-linux/{print $1}')
cp -L "$loader" "$OUT/lib/glibc/ld-linux.so"
glibc=$(objdump -T "$OUT/bin/svo-render" "$OUT"/lib/*.so* | grep -o 'GLIBC_[0-9.]*' | sort -V -u | tail -1)
glibc=${glibc#GLIBC_}
echo "needs glibc $glibc or newer, else runs on lib/glibc ($(ldd --version | head -1))" >> "$OUT/MANIFEST.txt"

cat > "$OUT/svo-render" <<EOF
#!/bin/sh
# svo-render from its bundle: the bundle's libraries first; the bundle's
# glibc too where the node's is older than $glibc (or SVO_BUNDLED_GLIBC=1).
here=\$(cd "\$(dirname "\$0")" && pwd)
have=\$(getconf GNU_LIBC_VERSION 2> /dev/null | cut -d' ' -f2)
oldest=\$(printf '%s\\n%s\\n' "$glibc" "\${have:-0}" | sort -V | head -1)
if [ "\${SVO_BUNDLED_GLIBC:-0}" != 1 ] && [ "\$oldest" = "$glibc" ]; then
  LD_LIBRARY_PATH="\$here/lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}" exec "\$here/bin/svo-render" "\$@"
fi
exec "\$here/lib/glibc/ld-linux.so" --library-path "\$here/lib:\$here/lib/glibc\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}" \\
  "\$here/bin/svo-render" "\$@"
EOF
chmod +x "$OUT/svo-render"

bytes=$(du -sb "$OUT" | cut -f1)
echo "bundle: $OUT: $(find "$OUT/lib" -type f | wc -l) libraries, $((bytes / 1024 / 1024)) MiB ($bytes bytes), glibc $glibc"
if ((bytes >= LIMIT_MIB * 1024 * 1024)); then
  echo "bundle: larger than $LIMIT_MIB MiB" >&2
  exit 1
fi
"$OUT/svo-render" --version > /dev/null
SVO_BUNDLED_GLIBC=1 "$OUT/svo-render" --version > /dev/null

((CHECK)) || exit 0

# A clean Debian 12 root: minbase (libc, libstdc++, apt), none of the
# build's packages. Made once; later checks reuse it.
NODE_ROOT="$BUILD_DIR/node-root"
if [ ! -x "$NODE_ROOT/bin/sh" ] || [ ! -f "$NODE_ROOT/.svo-ready" ]; then
  command -v debootstrap > /dev/null || {
    source "$ROOT/scripts/bench_common.sh"
    need_packages debootstrap
  }
  rm -rf "$NODE_ROOT"
  echo "bundle: debootstrap --variant=minbase bookworm $NODE_ROOT (a few minutes, once)"
  debootstrap --variant=minbase bookworm "$NODE_ROOT" http://deb.debian.org/debian > "$BUILD_DIR/node-root.log" 2>&1 ||
    { tail -5 "$BUILD_DIR/node-root.log" >&2; exit 1; }
  touch "$NODE_ROOT/.svo-ready"
fi
for p in libvulkan1 libtbb12 libopenexr-3-1-30 libpng16-16 libjpeg62-turbo libfftw3-single3; do
  if chroot "$NODE_ROOT" dpkg-query -W -f='${Status}\n' "$p" 2>/dev/null | grep -q "ok installed"; then
    echo "bundle: the clean root has $p installed; the check needs a root without it" >&2
    exit 1
  fi
done

# Lavapipe: the node brings its own Vulkan driver. Mesa's goes into a copy
# of the clean root (cached as node-root-mesa), from the same Debian sources
# as this machine's, so that both run the same lavapipe.
MESA_ROOT="$BUILD_DIR/node-root-mesa"
if [ ! -f "$MESA_ROOT/.svo-ready" ]; then
  echo "bundle: a copy of the clean root with mesa-vulkan-drivers (lavapipe) only"
  rm -rf "$MESA_ROOT"
  cp -a "$NODE_ROOT" "$MESA_ROOT"
  if ls /etc/apt/sources.list.d/*.sources > /dev/null 2>&1; then
    rm -f "$MESA_ROOT/etc/apt/sources.list"
    cp /etc/apt/sources.list.d/*.sources "$MESA_ROOT/etc/apt/sources.list.d/"
  fi
  chroot "$MESA_ROOT" sh -c 'DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
    apt-get install -y -qq --no-install-recommends mesa-vulkan-drivers' > "$BUILD_DIR/node-root-mesa.log" 2>&1 ||
    { tail -5 "$BUILD_DIR/node-root-mesa.log" >&2; exit 1; }
  touch "$MESA_ROOT/.svo-ready"
fi
# /proc in the roots (TBB and the Vulkan loader read it), unmounted on exit.
mounted=()
mount_proc() {
  if mount -t proc proc "$1/proc" 2> /dev/null; then mounted+=("$1/proc"); fi
}
trap 'for m in "${mounted[@]}"; do umount "$m" || true; done' EXIT
mount_proc "$NODE_ROOT"

WORK="$NODE_ROOT/node"
rm -rf "$WORK"
cp -r "$OUT" "$WORK"
"$BUILD_DIR/svo" voxelize --scene bumpy-sphere --detail-octaves 2 --resolution 64 -o "$WORK/sphere.svo" > /dev/null
args=(--view mid --width 96 --height 64 --shadows)
"$BUILD_DIR/svo" render "$WORK/sphere.svo" -o "$WORK/svo-native.png" --cpu "${args[@]}" > /dev/null
"$BUILD_DIR/svo" render "$WORK/sphere.svo" -o "$WORK/svo-lavapipe.png" --device llvmpipe "${args[@]}" > /dev/null

echo "bundle: in the clean root: native"
chroot "$NODE_ROOT" /node/svo-render render /node/sphere.svo -o /node/node-native.png --cpu "${args[@]}"
cmp "$WORK/svo-native.png" "$WORK/node-native.png"
chroot "$NODE_ROOT" env SVO_BUNDLED_GLIBC=1 /node/svo-render render /node/sphere.svo -o /node/node-native-glibc.png \
  --cpu "${args[@]}" > /dev/null
cmp "$WORK/svo-native.png" "$WORK/node-native-glibc.png"
echo "bundle: native image byte-identical to svo render's (with the node's glibc and with the bundle's)"

echo "bundle: mesa-vulkan-drivers $(chroot "$MESA_ROOT" dpkg-query -W -f='${Version}' mesa-vulkan-drivers) in the root," \
  "$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers) here"
rm -rf "$MESA_ROOT/node"
cp -r "$WORK" "$MESA_ROOT/node"
NODE_ROOT="$MESA_ROOT"
WORK="$MESA_ROOT/node"
mount_proc "$NODE_ROOT"
echo "bundle: in the clean root: lavapipe"
chroot "$NODE_ROOT" /node/svo-render devices
chroot "$NODE_ROOT" /node/svo-render render /node/sphere.svo -o /node/node-lavapipe.png --device llvmpipe "${args[@]}"
cmp "$WORK/svo-lavapipe.png" "$WORK/node-lavapipe.png"
chroot "$NODE_ROOT" env SVO_BUNDLED_GLIBC=1 /node/svo-render render /node/sphere.svo -o /node/node-lavapipe-glibc.png \
  --device llvmpipe "${args[@]}" > /dev/null
cmp "$WORK/svo-lavapipe.png" "$WORK/node-lavapipe-glibc.png"
echo "bundle: lavapipe image byte-identical to svo render's (with the node's glibc and with the bundle's)"
