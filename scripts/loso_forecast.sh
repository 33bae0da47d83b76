#!/usr/bin/env bash
# Issue 28's leave-one-style-out for the forecaster (Bandai): one training style left out of
# training and forecast as the test set, the model against nearest neighbours on it.
#   bash scripts/loso_forecast.sh STYLE OUT [EPOCHS] [WORKERS] [CONFIG]
#     STYLE    a training style of split.tsv (active, angry, ..., youthful; never elderly, the test)
#     OUT      a scratch folder: OUT/split.tsv, OUT/model/ (the bundle), OUT/model.json, OUT/nn.json
#     EPOCHS   the Bandai recipe's length (default: the config's 120; fewer scale its schedule)
#     WORKERS  training processes (default 2)
#     CONFIG   the generator config, a name or path (default bandai; e.g.
#              configs/models/recipes/bandai_augmented.yaml)
# Reads $BANDAI_DIR (default ../shared/data/bandai); runs from the repository, built. Resumes an
# interrupted training when run again; an existing JSON is kept.
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,12p "$0" >&2; exit 2; }
STYLE=$1 OUT=$2 EPOCHS=${3:-} WORKERS=${4:-2} CONFIG=${5:-bandai}
cd "$(dirname "$0")/.."
M=${BUILD_DIR:-build}/apps/motionfork/motionfork
D=${BANDAI_DIR:-../shared/data/bandai}
[ -x "$M" ] || { echo "loso_forecast: build first (bash scripts/setup.sh): no $M" >&2; exit 2; }
[ -f "$D/split.tsv" ] || { echo "loso_forecast: no $D/split.tsv" >&2; exit 2; }
[ "$STYLE" != elderly ] || { echo "loso_forecast: elderly is the test style, not a training one" >&2; exit 2; }
mkdir -p "$OUT"
# The test clips dropped; the left-out style's training clips become the test split.
awk -F'\t' -v s="_${STYLE}_" 'NR == 1 { print; next }
  $1 == "train" { if (index($2, s)) { print "test\t" $2; n++ } else print }
  END { if (!n) { print "loso_forecast: no training clip of that style" > "/dev/stderr"; exit 3 } }' \
  "$D/split.tsv" > "$OUT/split.tsv.tmp" || { rm -f "$OUT/split.tsv.tmp"; exit 3; }
mv "$OUT/split.tsv.tmp" "$OUT/split.tsv"
echo "$STYLE: $(grep -c '^test' "$OUT/split.tsv") clips left out"
"$M" train --config "$CONFIG" --data "$D" --split "$OUT/split.tsv" --out "$OUT/model" \
  ${EPOCHS:+--epochs "$EPOCHS"} --nproc-per-node "$WORKERS"
for who in model nn; do
  [ -s "$OUT/$who.json" ] && continue
  if [ $who = model ]; then args=(--model "$OUT/model"); else args=(--baseline nearest-neighbours); fi
  "$M" eval "${args[@]}" --protocol bandai --data "$D" --split "$OUT/split.tsv" -k 50 \
    --json "$OUT/$who.json" > "$OUT/$who.txt"   # the JSON is written whole or not at all
  tail -n 12 "$OUT/$who.txt"
done
