#!/bin/sh
# The robot's error measured by default on real arms: ViSP's Franka eye-in-hand set (chessboard) and
# the industrial_calibration set (circle grid), their robot_error lines removed, calibrated with no
# robot-error option (the board option only: the scenes have no texture). Each run is ok and every
# component of eMc is within 3 of its own sd of the board reference (the data README's: ViSP's
# published eMc for the Franka set, the board-mode hand-eye for the industrial one): the measured
# robot error widens the sd to cover what the flange poses' error does to eMc.
# Usage: default-robot-error-real.sh APP YAML_CHECK DATA_DIR WORK_DIR
APP=$1 YCHK=$2 DATA=$3 W=$4
for d in visp-franka-eye-in-hand industrial-calibration-10x10; do
  [ -d "$DATA/$d" ] || { echo "SKIPPED: no real data: $DATA/$d is absent"; exit 77; }
done
rm -rf "$W" && mkdir -p "$W" && cd "$W" || exit 1

# within3sd DIR REF: status ok and |eMc_i - REF_i| <= 3 sd_i for the 6 components.
within3sd() {
  set -- "$1" $2 $(sed -n '/^eMc:/{n;p}' "$1/results.yaml" | grep -o -- '-\{0,1\}[0-9][0-9.e+-]*')
  dir=$1
  shift
  checks=""
  for i in 0 1 2 3 4 5; do
    eval "ref=\${$((i + 1))} s=\${$((i + 13))}"
    checks="$checks eMc.pose.$i range $(awk -v v=$ref -v s=$s 'BEGIN{printf "%.9g %.9g", v-3*s, v+3*s}')"
  done
  $YCHK "$dir/results.yaml" status eq ok $checks
}

$APP import "$DATA/visp-franka-eye-in-hand" --out imported-franka.yaml > /dev/null 2>&1 || exit 1
grep -v '^robot_error:' imported-franka.yaml > franka.yaml
$APP import "$DATA/industrial-calibration-10x10" --out imported-ic.yaml > /dev/null 2>&1 || exit 1
grep -v '^robot_error:' imported-ic.yaml > ic.yaml
grep -q robot_error franka.yaml ic.yaml && exit 1
$APP calibrate franka.yaml --out franka --board chessboard:9x6:0.0236 --folds 0 > franka.log 2>&1
echo "franka exit=$?"
within3sd franka '0.0577 -0.0339 -0.0423 0.002 0.0095 1.5817' || { cat franka.log; exit 1; }
$APP calibrate ic.yaml --out ic --board modified-circles:10x10:0.0254 --folds 0 > ic.log 2>&1
echo "ic exit=$?"
within3sd ic '-0.0789 0.0314 0.0646 0.0414 -0.0325 -1.5695' || { cat ic.log; exit 1; }
echo default-robot-error-real-ok
