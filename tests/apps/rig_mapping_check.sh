#!/bin/sh
# A BVH whose joints carry Mixamo's names ("mixamorig:LeftUpLeg") predicts, checks and scores
# with the shipped Bandai model exactly as its Bandai-named twin, saying how it mapped the joints;
# a rig no convention explains is refused with a pointer to --joint-map.
# Usage: rig_mapping_check.sh MOTIONFORK SOURCE_DIR WORK_DIR
# Checks are one command a line: under set -e a failure before the last command of "a && b", or
# of a "! cmd", would not stop the script.
set -eu
mf=$1; src=$2; work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$mf" synth walk -o bandai.bvh --frames 60 >/dev/null
sed -e 's/JOINT Hips$/JOINT mixamorig:Hips/; s/ROOT Hips$/ROOT mixamorig:Hips/' \
    -e 's/UpperLeg_\([LR]\)$/mixamorig:\1UpLeg/; s/LowerLeg_\([LR]\)$/mixamorig:\1Leg/' \
    -e 's/Foot_\([LR]\)$/mixamorig:\1Foot/; s/JOINT Spine$/JOINT mixamorig:Spine1/' \
    -e 's/JOINT Chest$/JOINT mixamorig:Spine2/; s/JOINT Neck$/JOINT mixamorig:Neck/' \
    -e 's/JOINT Head$/JOINT mixamorig:Head/; s/UpperArm_\([LR]\)$/mixamorig:\1Arm/' \
    -e 's/LowerArm_\([LR]\)$/mixamorig:\1ForeArm/; s/Hand_\([LR]\)$/mixamorig:\1Hand/' \
    -e 's/mixamorig:L\([A-Z]\)/mixamorig:Left\1/; s/mixamorig:R\([A-Z]\)/mixamorig:Right\1/' \
    bandai.bvh > mixamo.bvh
grep -q "JOINT mixamorig:LeftUpLeg" mixamo.bvh
if grep -q "_L$" mixamo.bvh; then echo "a Bandai name is left in mixamo.bvh"; exit 1; fi
"$mf" predict --model "$src/models/bandai" bandai.bvh -o a -k 4 --seed 3 >/dev/null 2>&1
"$mf" predict --model "$src/models/bandai" mixamo.bvh -o b -k 4 --seed 3 >out.txt 2>&1
cat out.txt
grep -q "read as the mixamo rig onto skeleton 'bandai'" out.txt
cmp a.npy b.npy
echo "futures identical to the Bandai-named twin's"
"$mf" check mixamo.bvh --constraints bandai >check.txt 2>&1
grep -q "mixamo rig" check.txt
"$mf" prior score --model "$src/models/prior-bandai" mixamo.bvh >score.txt 2>&1
"$mf" prior score --model "$src/models/prior-bandai" bandai.bvh >score_a.txt 2>&1
grep "mean" score.txt | head -1
[ "$(grep -m1 "mean" score.txt | sed 's/.*mean//')" = "$(grep -m1 "mean" score_a.txt | sed 's/.*mean//')" ]
echo "check and prior score read it too"
sed 's/mixamorig:LeftLeg/mixamorig:KneeThing/' mixamo.bvh > odd.bvh
if "$mf" predict --model "$src/models/bandai" odd.bvh -o c -k 2 >odd.txt 2>&1; then
  echo "an unexplained rig was accepted"; exit 1
fi
cat odd.txt
grep -q "left_knee ('LeftLeg')" odd.txt
grep -q -- "--joint-map FILE" odd.txt
# Left and right labels exchanged: warned and exchanged back (the same futures); --strict refuses.
sed -e 's/_L$/_TMP/; s/_R$/_L/; s/_TMP$/_R/' bandai.bvh > mirrored.bvh
"$mf" predict --model "$src/models/bandai" mirrored.bvh -o m -k 4 --seed 3 >mirrored.txt 2>&1
grep -q "^warning: mirrored.bvh: the left/right labels disagree with the body" mirrored.txt
cmp a.npy m.npy
echo "mirrored labels exchanged back: the same futures"
if "$mf" predict --model "$src/models/bandai" mirrored.bvh -o s -k 2 --strict >strict.txt 2>&1; then
  echo "--strict accepted a doubtful history"; exit 1
fi
grep -q -- "--strict: refused" strict.txt
[ ! -e s.npy ]
# eval --clips reads the Mixamo twin as the Bandai-named file: the same figures.
"$mf" synth walk -o long.bvh --frames 120 >/dev/null
mkdir -p clips_bandai clips_mixamo
cp long.bvh clips_bandai/walk.bvh
sed -e 's/JOINT Hips$/JOINT mixamorig:Hips/; s/ROOT Hips$/ROOT mixamorig:Hips/' \
    -e 's/UpperLeg_\([LR]\)$/mixamorig:\1UpLeg/; s/LowerLeg_\([LR]\)$/mixamorig:\1Leg/' \
    -e 's/Foot_\([LR]\)$/mixamorig:\1Foot/; s/JOINT Spine$/JOINT mixamorig:Spine1/' \
    -e 's/JOINT Chest$/JOINT mixamorig:Spine2/; s/JOINT Neck$/JOINT mixamorig:Neck/' \
    -e 's/JOINT Head$/JOINT mixamorig:Head/; s/UpperArm_\([LR]\)$/mixamorig:\1Arm/' \
    -e 's/LowerArm_\([LR]\)$/mixamorig:\1ForeArm/; s/Hand_\([LR]\)$/mixamorig:\1Hand/' \
    -e 's/mixamorig:L\([A-Z]\)/mixamorig:Left\1/; s/mixamorig:R\([A-Z]\)/mixamorig:Right\1/' \
    long.bvh > clips_mixamo/walk.bvh
"$mf" eval --baseline zero-velocity --protocol bandai --clips clips_bandai -k 2 >eval_a.txt 2>&1
"$mf" eval --baseline zero-velocity --protocol bandai --clips clips_mixamo -k 2 >eval_b.txt 2>&1
grep -q "^all  *4 " eval_a.txt  # the figures line: 4 windows of the clip
if [ "$(grep "^all " eval_a.txt)" != "$(grep "^all " eval_b.txt)" ]; then
  echo "eval --clips read the Mixamo twin differently"; exit 1
fi
grep "^all " eval_b.txt
echo "eval --clips: the same figures"
# The gate: a wrong --unit or --left-right forced is warned, no future is valid, --strict refuses.
"$mf" predict --model "$src/models/bandai" bandai.bvh -o u -k 3 --unit mm >unit.txt 2>&1
grep "far from what the model knows: scale: " unit.txt
grep -q "0 of 3 futures valid" unit.txt
python3 -c "import json, sys; s = json.load(open('u.json'))['samples']; sys.exit(0 if s and all('history' in x['failed'] and not x['valid'] for x in s) else 1)"
grep -q '"scale: the body measures' u.json
"$mf" predict --model "$src/models/bandai" mirrored.bvh -o l -k 3 --left-right as-labelled \
  >labels.txt 2>&1
grep "far from what the model knows: left/right: " labels.txt
if "$mf" predict --model "$src/models/bandai" bandai.bvh -o v -k 2 --unit mm --strict \
  >strict_unit.txt 2>&1; then
  echo "--strict accepted a history the gate doubts"; exit 1
fi
grep -q "is far from what the model knows; scale: .*(--strict: refused)" strict_unit.txt
[ ! -e v.npy ]
# --strict with several files: the doubted one refuses the run before any file is written.
if "$mf" predict --model "$src/models/bandai" bandai.bvh mirrored.bvh -o both -k 2 \
  --left-right as-labelled --strict >strict_many.txt 2>&1; then
  echo "--strict accepted a doubted history among several"; exit 1
fi
grep -q "mirrored.bvh: the history .* (--strict: refused)" strict_many.txt
if [ -e both/bandai.npy ]; then echo "--strict left a file written"; exit 1; fi
# As recorded: every judge passes, the gate says so.
grep -q "history: no doubt" out.txt
echo "all rig checks passed"
