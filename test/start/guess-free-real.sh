#!/bin/sh
# The calibration of the real sets does not depend on the guesses (f self-calibrated, robot_error
# removed): the Franka eye-in-hand set with its chessboard and the industrial_calibration set with
# its circle grid, each calibrated (hand-eye) from a focal guess of 0.5x the reference with an eMc
# guess 90 deg off, and from 2x with the reference eMc: the same focal length and eMc within 0.1 of
# their sd, both ok, the Franka f within 1 % of ViSP's calibration.
# Usage: guess-free-real.sh APP YAML_CHECK DATA_DIR WORK_DIR
APP=$1 YCHK=$2 DATA=$3 W=$4
for d in visp-franka-eye-in-hand industrial-calibration-10x10; do
  [ -d "$DATA/$d" ] || { echo "SKIPPED: no real data: $DATA/$d is absent"; exit 77; }
done
rm -rf "$W" && mkdir -p "$W" && cd "$W" || exit 1

# model FILE EMC: a one-joint hand-eye model with that eMc (the controller poses carry the arm).
model() {
  printf 'name: hand-eye\nconvention: dh\njoints:\n  - {a: 0, d: 0, alpha: 0, theta_offset: 0, min: -3.2, max: 3.2}\neMc: [%s]\n' "$2" > "$1"
}
# dataset IN OUT F_GUESS ROBOT: IN without robot_error, with that focal guess and robot.
dataset() {
  grep -v '^robot_error:' "$1" | sed -e "s/f_guess: [0-9.]*/f_guess: $3/" -e "s|^robot: .*|robot: $4|" > "$2"
}
# same A B: B's focal length and eMc within 0.1 of A's sd of A's.
same() {
  set -- "$1" "$2" $(sed -n 's/^camera: {px: \([^,]*\),.*px_sd: \([^}]*\)}.*/\1 \2/p' "$1/results.yaml") \
    $(sed -n '/^eMc:/{n;p}' "$1/results.yaml" | grep -o -- '-\{0,1\}[0-9][0-9.e+-]*')
  a=$1 b=$2 px=$3 sd=$4
  shift 4
  checks="camera.px range $(awk -v v=$px -v s=$sd 'BEGIN{printf "%.9g %.9g", v-0.1*s, v+0.1*s}')"
  for i in 0 1 2 3 4 5; do
    eval "v=\${$((i + 1))} s=\${$((i + 7))}"
    checks="$checks eMc.pose.$i range $(awk -v v=$v -v s=$s 'BEGIN{printf "%.9g %.9g", v-0.1*s, v+0.1*s}')"
  done
  $YCHK "$b/results.yaml" status eq ok $checks
}

$APP import "$DATA/visp-franka-eye-in-hand" --out franka.yaml --intrinsics guess > /dev/null 2>&1 || exit 1
model franka-right.yaml '0.0577, -0.0339, -0.0423, 0.002, 0.0095, 1.5817'
dataset franka.yaml fa.yaml 303.8 panda          # the preset's eMc (0, 0, 0.05, 0, 0, 0): 90.6 deg off
dataset franka.yaml fb.yaml 1215.2 franka-right.yaml
for x in fa fb; do
  $APP calibrate $x.yaml --out $x --method hand-eye --board chessboard:9x6:0.0236 --folds 0 > $x.log 2>&1
  echo "$x exit=$?"
done
$YCHK fa/results.yaml status eq ok camera.px range 601.5 613.7 eMc.pose.0 range 0.0547 0.0607 eMc.pose.1 range -0.0369 -0.0309 eMc.pose.2 range -0.0453 -0.0393 eMc.pose.5 range 1.5767 1.5867 && same fa fb || exit 1

$APP import "$DATA/industrial-calibration-10x10" --out ic.yaml > /dev/null 2>&1 || exit 1
model ic-right.yaml '-0.0789, 0.0314, 0.0646, 0.0414, -0.0325, -1.5695'
model ic-turned.yaml '-0.0789, 0.0314, 0.0646, 1.2484, -1.2404, -1.1900'  # the reference turned 90 deg about x
dataset ic.yaml ia.yaml 270.7 ic-turned.yaml
dataset ic.yaml ib.yaml 1082.6 ic-right.yaml
for x in ia ib; do
  $APP calibrate $x.yaml --out $x --method hand-eye --board modified-circles:10x10:0.0254 --folds 0 > $x.log 2>&1
  echo "$x exit=$?"
done
$YCHK ia/results.yaml status eq ok camera.px range 526 558 eMc.pose.0 range -0.110 -0.050 eMc.pose.1 range 0.010 0.050 && same ia ib || exit 1
grep -h -o "eMc started from [^;]*; f started at [^;]*" fa/results.yaml ia/results.yaml
echo guess-free-ok
