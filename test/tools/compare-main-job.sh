#!/bin/sh
# compare against the main job: the main job's set-up through the tool (plan 15 + 10 held-out poses,
# simulate on them, calibrate on the first 15), then compare --joints on the 10 held-out poses,
# which measures the main job's "relative pose error" (c_0 M c_k from the first held-out pose to
# each other, mean) against the simulated truth. The main job itself runs on the same scenario
# (seed 1, --acquisition points); its verification lines are turned into YAML.
#   - nominal: the same quantity on the same poses and truth: compare's figure equals the main
#     job's to the printed precision (0.001 mm, 0.001 mrad);
#   - calibrated: two calibrations of the same scenario (the main job fixes the pixel sd, calibrate
#     measures it; other noise draws): each at the noise level, at least 5 times below nominal,
#     and within 0.5 mm / 0.5 mrad of each other.
#   sh test/tools/compare-main-job.sh APP TUTORIAL YAML_CHECK WORK_DIR    (prints compare-main-job-ok)
set -u
APP="$1"; TUTORIAL="$2"; YCHK="$3"; WORK="$4"
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAILED: $*"; exit 1; }

"$APP" plan plan.txt --poses 15 --held-out 10 > /dev/null 2>&1 || fail "plan"
"$APP" simulate ds.yaml --joints plan.txt > /dev/null 2>&1 || fail "simulate"
"$APP" calibrate ds.yaml --out res --holdout 10 > /dev/null 2>&1 || fail "calibrate"
tail -n 10 plan.txt > held.txt
"$APP" compare res ds-truth.yaml --joints held.txt --yaml cmp.yaml || fail "compare"

"$TUTORIAL" -c -d --acquisition points --report none --results main.yaml > main.txt 2> /dev/null || fail "the main job"
# "   relative pose error, mean [mm]       2.425       0.434" -> main-mm.yaml: [2.425, 0.434]
sed -n 's/^ *relative pose error, mean \[mm\] *\([^ ]*\) *\([^ ]*\)$/[\1, \2]/p' main.txt > main-mm.yaml
sed -n 's/^ *relative pose error, mean \[mrad\] *\([^ ]*\) *\([^ ]*\)$/[\1, \2]/p' main.txt > main-mrad.yaml
"$YCHK" main.yaml protocol.calibration_views eq 15 protocol.held_out_views eq 10 || fail "the main job verified on other poses"
"$YCHK" main-mm.yaml 0 range 0.1 100 1 exists && "$YCHK" main-mrad.yaml 0 range 0.1 100 1 exists || fail "main job figures"

# bounds COLUMN FILE TOL SCALE: "LO HI" around the main job's figure (mm or mrad) in m or rad
bounds() { tr -d '[],' < "$2" | awk -v c="$1" -v t="$3" '{ v = $(c + 1) / 1000; printf "%.9f %.9f", v - t, v + t }'; }
# nominal: equal to the printed precision (half a unit of 0.001 mm / mrad, and the rounding)
"$YCHK" cmp.yaml from_first.configurations eq 10 \
  from_first.nominal.mean_m range $(bounds 0 main-mm.yaml 0.0000006) \
  from_first.nominal.mean_rad range $(bounds 0 main-mrad.yaml 0.0000006) || fail "nominal differs from the main job's"
# calibrated: the noise level of both calibrations, and close to each other
"$YCHK" cmp.yaml from_first.calibrated.mean_m range $(bounds 1 main-mm.yaml 0.0005) \
  from_first.calibrated.mean_rad range $(bounds 1 main-mrad.yaml 0.0005) || fail "calibrated far from the main job's"
nom_m=$(tr -d '[],' < main-mm.yaml | awk '{ print $1 / 1000 / 5 }')
nom_r=$(tr -d '[],' < main-mrad.yaml | awk '{ print $1 / 1000 / 5 }')
"$YCHK" cmp.yaml from_first.calibrated.mean_m range 0 "$nom_m" from_first.calibrated.mean_rad range 0 "$nom_r" || fail "not 5 times below nominal"
"$YCHK" main-mm.yaml 1 range 0 "$(echo "$nom_m * 1000" | bc -l)" || fail "the main job's calibrated error is not 5 times below nominal"
echo "compare-main-job-ok"
