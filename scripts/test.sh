#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs the whole test suite with CTest, twice:
# the Release build in build/, then an AddressSanitizer + UndefinedBehaviorSanitizer
# build in build-asan/ (any report fails the test). Extra arguments go to ctest,
# e.g. scripts/test.sh -L numerics. SVO_SKIP_SANITIZE=1 skips the second pass.
# Between the two, without extra arguments, the render node's bundle is
# checked in a clean Debian 12 root (scripts/bundle-render-node.sh --check).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# ccache: paths under the checkout count as relative, and the build folder
# does not enter the hash, so that a fresh clone elsewhere reuses the cache.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
"$ROOT/scripts/setup.sh"
(cd "$BUILD_DIR" && ctest -j2 --output-on-failure --timeout 600 "$@")

# The render node's bundle (issue 23): gathered, then run in a clean Debian
# 12 root made with debootstrap (as root: chroot), natively and on lavapipe,
# its images byte-identical to svo render's. SVO_SKIP_BUNDLE=1 skips it.
if [ "${SVO_SKIP_BUNDLE:-0}" != 1 ] && [ $# = 0 ]; then
  if [ "$(id -u)" = 0 ]; then
    BUILD_DIR="$BUILD_DIR" "$ROOT/scripts/bundle-render-node.sh" --check
  else
    echo "test: the render node's bundle check needs root (chroot); skipped"
  fi
fi

if [ "${SVO_SKIP_SANITIZE:-0}" != 1 ]; then
  ASAN_DIR="$ROOT/build-asan"
  if [ ! -f "$ASAN_DIR/build.ninja" ]; then
    # -O1 with line tables only: it compiles faster than -O2 -g on 2 cores,
    # and reports still name the lines.
    cmake -S "$ROOT" -B "$ASAN_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSVO_SANITIZE=ON \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
  fi
  cmake --build "$ASAN_DIR" -j2
  echo "test: the same suite under AddressSanitizer + UndefinedBehaviorSanitizer"
  (cd "$ASAN_DIR" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS="suppressions=$ROOT/tests/lsan.supp" \
    UBSAN_OPTIONS=print_stacktrace=1 \
     ctest -j2 --output-on-failure --timeout 900 "$@")
fi
