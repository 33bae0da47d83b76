#!/usr/bin/env bash
# A BVH file motionfork writes, imported by Blender's own importer (headless), gives back our joint
# positions within 1 mm. Usage: blender_bvh_check.sh MOTIONFORK_BINARY SOURCE_DIR WORK_DIR
# Skips without Blender (fails under CI=true: scripts/test.sh installs it).
set -euo pipefail
MF=$1 SRC=$2 WORK=$3
if ! command -v blender >/dev/null; then
  if [ "${CI:-}" = true ]; then echo "CI=true but blender is not installed"; exit 1; fi
  echo "SKIPPED: blender not installed (sudo apt-get install blender)"; exit 0
fi
rm -rf "$WORK" && mkdir -p "$WORK"
"$MF" --cache-dir none synth walk --frames 60 -o "$WORK/walk.csv"
"$MF" --cache-dir none convert "$WORK/walk.csv" "$WORK/walk.bvh" --skeleton bandai
blender -b --factory-startup --python "$SRC/tools/blender_check_bvh.py" -- "$WORK/walk.bvh" "$WORK/walk.csv" \
  --tolerance-mm 1 2>&1 | grep "blender_check_bvh"
