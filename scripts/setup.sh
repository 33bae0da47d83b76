#!/usr/bin/env bash
# Installs every Debian package motionfork needs, then configures and builds it (Release).
#   bash scripts/setup.sh            # packages + build into ./build
#   BUILD_DIR=out bash scripts/setup.sh
# Safe to re-run: installed packages are skipped, the build is incremental (ccache).
set -euo pipefail
cd "$(dirname "$0")/.."

# Why each package:
#   build-essential cmake ccache pkg-config   compiler, build system, compile cache
#   libtorch-dev        LibTorch 1.13 (CPU): networks, autograd (generator, prior, penalties)
#   libgloo-dev         the Gloo headers LibTorch's c10d ProcessGroupGloo includes (data-parallel
#                       training; the library itself is already a dependency of libtorch)
#   libopenblas-dev     fast BLAS for LibTorch (the reference BLAS is ~15x slower)
#   libeigen3-dev       small dense linear algebra in core (DCT, kinematics)
#   libglm-dev          vector maths for geometry checks
#   libyaml-cpp-dev     YAML configs
#   catch2              unit tests (Catch2 v2)
#   libcli11-dev        command-line parsing for the motionfork command
#   libarchive-dev      reads datasets straight out of .tar.xz/.zip archives, no unpacking
#   nlohmann-json3-dev  reads and writes prediction descriptions (JSON) without a hand-written parser
#   python3 python3-numpy   tools/videopose3d_to_motionfork.py (Human3.6M / HumanEva-I npz)
#   libcairo2-dev       draws the PNG/SVG strip figures of `motionfork render` (and decodes PNGs in its tests)
#   chromium            headless browser the render tests load the HTML viewer in (play, screenshot)
#   python3-dev pybind11-dev   the Python module `import motionfork` (python/): headers and the
#                       binding library that turns the C++ API into a module taking NumPy arrays
#   python3-pytest      runs the Python module's tests (tests/python/, from CTest)
#   python3-matplotlib  plots futures in examples/predict_and_plot.py
PACKAGES=(build-essential cmake ccache pkg-config libtorch-dev libgloo-dev libopenblas-dev libeigen3-dev
          libglm-dev libyaml-cpp-dev catch2 libcli11-dev libarchive-dev nlohmann-json3-dev python3 python3-numpy
          libcairo2-dev chromium python3-dev pybind11-dev python3-pytest python3-matplotlib)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

BUILD_DIR=${BUILD_DIR:-build}
JOBS=${JOBS:-$(nproc)}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j "$JOBS"
echo "setup: built $BUILD_DIR/apps/motionfork/motionfork and the Python module in $BUILD_DIR/python"
echo "setup: from Python: PYTHONPATH=$PWD/$BUILD_DIR/python python3 -c 'import motionfork'"
