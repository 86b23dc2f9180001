#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine for svo and builds it (Release, -j2).
# Idempotent: packages already present are not reinstalled, and a configured
# build tree is reused. Run as root (or with sudo available).
#   scripts/setup.sh            install packages, configure, build into build/
#   BUILD_DIR=out scripts/setup.sh   the same into another folder
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# ccache: paths under the checkout count as relative, and the build folder
# does not enter the hash, so that a fresh clone elsewhere reuses the cache.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"

# Debian packages, one reason each.
PACKAGES=(
  cmake ninja-build g++ ccache pkg-config  # build
  libglm-dev                               # vector math shared by C++ and GLSL
  libvulkan-dev glslang-tools              # Vulkan loader and headers, GLSL -> SPIR-V
  mesa-vulkan-drivers                      # lavapipe, the CPU Vulkan device
  vulkan-validationlayers                  # Khronos validation, on in the tests
  libcli11-dev nlohmann-json3-dev          # command line, JSON output
  libxxhash-dev                            # XXH64 checksums of the .svo file
  libopenvdb-dev libboost-iostreams-dev    # mesh -> narrow-band signed distance (voxelizer only)
  libopenvdb-tools                         # vdb_tool: the .vdb round trips through OpenVDB's own tool (cli.io_vdb_*)
  zlib1g-dev                               # needed by FindOpenVDB.cmake
  libopenmesh-dev                          # OBJ, PLY, OFF, STL input
  libtinygltf-dev                          # glTF 2.0 input (.gltf, .glb); images decoded by OpenImageIO
  libopenimageio-dev                       # images read (textures, environment maps, svo compare)
  libopenexr-dev libpng-dev libjpeg-dev    # images written (EXR, PNG, JPEG), and read by svo-render
  libtbb-dev                               # parallel loops
  libfftw3-dev                             # windowed-FFT reference bandwidth (render/bandwidth.h)
  libglfw3-dev                             # the window of svo view
  libembree-dev                            # meshes ray traced for svo reference (ground truth)
  xvfb xauth xdotool                       # xvfb-run, keys: the viewer's tests without a display
  libgtest-dev libgmock-dev                # tests
  libcgal-demo                             # the Stanford bunny (bunny00.off) of the far-view accuracy test
  blender-data                             # eight CC0 HDR environment maps (studiolights/world/*.exr)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    SUDO="sudo"
  fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S "$ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" -j2
echo "setup: built $BUILD_DIR/svo"
