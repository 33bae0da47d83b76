#!/usr/bin/env bash
# Builds (installing packages if needed) and runs the whole test suite through CTest.
# Real-data tests read ../shared/data/bandai; without it they skip, under CI=true they fail.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
# Tests must not depend on a user's cache; give them their own.
export MOTIONFORK_CACHE_DIR="$PWD/$BUILD_DIR/test-cache"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
