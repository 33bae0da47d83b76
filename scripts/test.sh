#!/usr/bin/env bash
# Builds (installing packages if needed) and runs the whole test suite through CTest.
# Real-data tests read ../shared/data/bandai; without it they skip, under CI=true they fail.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Test-only packages (not needed to use motionfork, so setup.sh leaves them out), installed here so
# that CI runs their tests: Blender, to import our BVH files in a real animation tool; clang-format,
# to hold every C++ file to the repository's .clang-format.
for p in blender clang-format; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    echo "test: installing $p (test-only)"
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "$p"
  fi
done
BUILD_DIR=${BUILD_DIR:-build}
# Tests must not depend on a user's cache; give them their own.
export MOTIONFORK_CACHE_DIR="$PWD/$BUILD_DIR/test-cache"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
