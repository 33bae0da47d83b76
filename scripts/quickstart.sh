#!/usr/bin/env bash
# First run: set everything up, then show what motionfork does on real motion capture.
# (Until the first model ships, the main job is a data summary: one clip, then the Bandai set.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
MF=${BUILD_DIR:-build}/apps/motionfork/motionfork
DATA=${MOTIONFORK_BANDAI:-../shared/data/bandai}
if [ ! -d "$DATA" ]; then
  echo "quickstart: no Bandai data at $DATA (set MOTIONFORK_BANDAI=/path/to/folder with the archives)" >&2
  exit 2
fi
DEMO=${BUILD_DIR:-build}/demo
mkdir -p "$DEMO"
CLIP=dataset-1_walk_normal_001.bvh
if [ ! -f "$DEMO/$CLIP" ]; then
  tar -xJf "$DATA/bandai-1.tar.xz" -C "$DEMO" --strip-components=2 --wildcards "*/data/$CLIP"
fi
echo; echo "== motionfork info $DEMO/$CLIP"
"$MF" info "$DEMO/$CLIP"
echo; echo "== motionfork convert (22-joint BVH -> 17-joint Bandai protocol skeleton, .npy)"
"$MF" convert "$DEMO/$CLIP" "$DEMO/walk.npy" --skeleton bandai
"$MF" info "$DEMO/walk.npy" --skeleton bandai
echo; echo "== motionfork dataset stats --protocol bandai --data $DATA"
"$MF" dataset stats --protocol bandai --data "$DATA"
