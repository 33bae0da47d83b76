#!/usr/bin/env bash
# First run: set everything up, then predict futures with the shipped Bandai model and draw them.
#   bash scripts/quickstart.sh                 # built-in history (a synthetic walk the project makes)
#   bash scripts/quickstart.sh my_motion.bvh   # your own history (.bvh, .npy or .csv; its last
#                                              # 0.5 s is the history; Bandai 22- or 17-joint skeleton)
# Outputs go to build/demo/ (DEMO_DIR=... to change); the paths are printed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
MF=$BUILD_DIR/apps/motionfork/motionfork
MODEL=${MOTIONFORK_MODEL:-models/bandai}
DEMO=${DEMO_DIR:-$BUILD_DIR/demo}
mkdir -p "$DEMO"

step() { echo; echo "== $*"; }

if [ $# -ge 1 ]; then
  HISTORY=$1
  [ -f "$HISTORY" ] || { echo "quickstart: no such file: $HISTORY" >&2; exit 2; }
else
  HISTORY=$DEMO/history.csv
  step "motionfork synth walk: a built-in history (simple gait model, no dataset involved)"
  "$MF" synth walk --frames 30 -o "$HISTORY"
fi

step "motionfork predict: 50 futures of the last 0.5 s of $HISTORY"
"$MF" predict "$HISTORY" --model "$MODEL" -k 50 --seed 0 -o "$DEMO/futures"

step "motionfork predict --fix legs: the same legs in all 50 futures, varied upper bodies"
"$MF" predict "$HISTORY" --model "$MODEL" -k 50 --seed 0 --fix legs -o "$DEMO/same-legs"

step "motionfork check: angle ranges of the history itself"
# Exit status 1 means some frame is outside a range: a finding, not a failure.
"$MF" check "$HISTORY" --constraints "$MODEL/constraints.yaml" --skeleton bandai --worst 3 ||
  { rc=$?; [ "$rc" -eq 1 ] || exit "$rc"; }

step "motionfork render: pictures"
"$MF" render "$DEMO/futures.json" --count 5 -o "$DEMO/futures.png"
"$MF" render "$DEMO/futures.json" --overlay --count 50 -o "$DEMO/futures-overlay.png"
"$MF" render "$DEMO/same-legs.json" --count 5 -o "$DEMO/same-legs.png"
"$MF" render "$DEMO/futures.json" -o "$DEMO/futures.html"

step "motionfork export: future 0 as BVH (open it in Blender, Maya, MotionBuilder)"
"$MF" export "$DEMO/futures.json" --sample 0 -o "$DEMO/future_00.bvh"

step "motionfork predict --impute: the left forearm and hand lost in the history, filled by the HG-VAE, then forecast"
"$MF" predict "$HISTORY" --model "$MODEL" -k 50 --seed 0 --impute "$MODEL/hgvae" \
  --mask joints:LowerArm_L,Hand_L -o "$DEMO/imputed"

step "motionfork denoise: the history with 4 cm of noise added, cleaned by the Motion-DVAE, then forecast"
"$MF" denoise "$HISTORY" --model "$MODEL/dvae" --skeleton bandai --add-noise gaussian:0.04 \
  -o "$DEMO/denoised.csv"
"$MF" predict "$DEMO/denoised.csv" --model "$MODEL" -k 50 --seed 0 -o "$DEMO/denoised-futures"

echo
echo "quickstart: done. Results in $DEMO:"
for f in futures.npy futures.json same-legs.npy same-legs.json futures.png futures-overlay.png \
         same-legs.png futures.html future_00.bvh imputed.npy imputed.json denoised.csv \
         denoised-futures.npy denoised-futures.json; do
  echo "  $DEMO/$f"
done
echo "Open the .png files in an image viewer and futures.html in a browser (it plays offline)."
