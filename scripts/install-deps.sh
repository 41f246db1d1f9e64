#!/usr/bin/env bash
# Installs every build and test dependency from Debian's packages. Idempotent: packages
# already present are left alone. Runs apt-get through sudo when not root.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  clang                                  # the sanitizer suite and the fuzz targets (libFuzzer)
  libglm-dev libeigen3-dev libembree-dev
  libopenimageio-dev openimageio-tools   # the OIIO CMake export references its tools
  libpng-dev libjpeg-dev                 # PNG and JPEG reading with our own error handlers
  zlib1g-dev                             # the gzip layer of .spz models
  libtinygltf-dev libglfw3-dev libtbb-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev
  python3                                # scenes/generate (scene assets), bench/history.py
  gnuplot-nox                            # splat-eval's charts (run as a subprocess)
  ffmpeg                                 # splat-render --video encodes through it (ffprobe in its tests)
  colmap                                 # splat-process: structure from motion (its command-line tools)
  libopenmpi-dev openmpi-bin             # data-parallel training over MPI ranks (mpirun)
  libimgui-dev libgl-dev                 # splat-viewer's overlay (Dear ImGui) and OpenGL 2
  xvfb xauth libgl1-mesa-dri             # the viewer's test: a virtual display, Mesa's software GL
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
