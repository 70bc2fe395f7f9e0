#!/bin/sh
# A newcomer's first hour: the user flows of README.md and doc/getting-started.md, typed as the pages
# give them, each command's exit code checked and, for calibrate, its answer (the last line on
# stdout, 'status: ...').
#
#   sh test/tools/newcomer.sh BUILD_DIR SOURCE_DIR DATA_DIR WORK_DIR PART
#
# PART: sim     the simulated robot: describe, plan, simulate, calibrate (--fix too), read the
#               result, verify, export, compare; the eye-to-hand simulation
#       boards  the ChArUco and AprilTag boards of getting-started (rendered images; slow)
#       real    ../shared/data (DATA_DIR): import of both eye-in-hand sets and of the eye-to-hand
#               set, each followed by the calibrate command import suggests (its DIR filled in),
#               then the pages' own commands on them; skipped (exit 77) when DATA_DIR is absent
# The work directory is laid out like a checkout (build/ and modules/ linked, ../shared/data the
# data), so the commands run verbatim. Prints "newcomer-PART-ok" when every step went as expected.
set -u
BUILD=$(cd "$1" && pwd) SRC=$(cd "$2" && pwd) DATA=$3 WORK=$4 PART=$5
APP=build/bin/visp-selfcalib
fail() { echo "FAILED: $*"; exit 1; }

if [ "$PART" = real ] && [ ! -d "$DATA" ]; then
  echo "SKIPPED: the real data sets are not in $DATA (shared/data beside the repository)"
  exit 77
fi
rm -rf "$WORK" && mkdir -p "$WORK/checkout" "$WORK/shared" || fail "cannot create $WORK"
ln -s "$BUILD" "$WORK/checkout/build" && ln -s "$SRC/modules" "$WORK/checkout/modules" || fail "links"
[ -d "$DATA" ] && ln -s "$(cd "$DATA" && pwd)" "$WORK/shared/data"
cd "$WORK/checkout" || fail "cd"

# step EXIT STATUS COMMAND...: runs COMMAND (stdout in last.out, stderr in last.err), checks its exit
# code is EXIT and, when STATUS is not '-', that its last line on stdout starts with 'status: STATUS'.
n=0
step() {
  want=$1 status=$2; shift 2
  n=$((n + 1))
  "$@" > last.out 2> last.err
  got=$?
  last=$(tail -n 1 last.out)
  echo "[$n] exit $got: $*"
  [ "$status" = - ] || echo "    $last"
  if [ "$got" -ne "$want" ]; then
    tail -n 5 last.err
    fail "step $n: exit $got, expected $want: $*"
  fi
  if [ "$status" != - ]; then
    case "$last" in
      "status: $status"*) ;;
      *) fail "step $n: last line '$last', expected 'status: $status...': $*" ;;
    esac
  fi
}

# suggested FILE.yaml DIR: the calibrate command the last import printed ('next: ...'), DIR filled in.
suggested() {
  line=$(sed -n 's/^next: visp-selfcalib //p' last.out)
  [ -n "$line" ] || fail "import printed no 'next:' suggestion"
  echo "    suggested: visp-selfcalib $line" >&2
  echo "$line" | sed "s#--out DIR#--out $2#"
}

case "$PART" in
sim)
  # getting-started 1. Describe the robot
  step 0 - $APP info puma560
  cat > arm.yaml << 'EOF'
name: my-arm
convention: dh
joints:
  - {a: 0.0,    d: 0.0,     alpha: 1.5707963267948966,  min: -2.79, max: 2.79}
  - {a: 0.4318, d: 0.0,     alpha: 0.0,                 min: -3.93, max: 0.79}
  - {a: 0.0203, d: 0.15005, alpha: -1.5707963267948966, min: -0.79, max: 3.93}
  - {a: 0.0,    d: 0.4318,  alpha: 1.5707963267948966,  min: -1.92, max: 2.97}
  - {a: 0.0,    d: 0.0,     alpha: -1.5707963267948966, min: -1.75, max: 1.75}
  - {a: 0.0,    d: 0.0,     alpha: 0.0,                 min: -4.64, max: 4.64}
eMc: [0, 0.06, 0.08, 0, 0, 0]
EOF
  step 0 - $APP info arm.yaml
  step 0 - $APP info modules/selfcalib/test/io/data/ur5.urdf
  echo "0 1.5708 -1.5708 0 0 0" > q.txt
  step 0 - $APP predict arm.yaml q.txt
  # 2. Plan, 3. simulate (acquire is the slow flow: docs-run-getting-started-slow)
  step 0 - $APP plan plan.txt --poses 15 --held-out 10
  step 0 - $APP simulate ds.yaml --poses 25 --seed 1
  [ -s ds-truth.yaml ] || fail "simulate wrote no ds-truth.yaml"
  # 5. Calibrate; --fix
  step 0 ok $APP calibrate ds.yaml --out result
  step 0 ok $APP calibrate ds.yaml --out fixed --fix 'j6.*'
  # 6. Read the result
  grep -E '^(status|method):' result/results.yaml > head.txt || fail "results.yaml has no status"
  step 0 - build/bin/selfcalib-yaml-check result/results.yaml status eq ok cross_validation.measured eq 5
  step 0 - build/bin/selfcalib-yaml-check fixed/results.yaml status eq ok estimated_set.fixed_by_user size 6
  # 7. Verify, export, compare
  step 0 - $APP verify result/model.yaml ds.yaml
  step 0 - $APP export result/model.yaml --urdf robot.urdf
  step 0 - $APP export result/model.yaml --dh table.yaml
  step 0 - $APP compare result ds-truth.yaml
  # 4. Eye-to-hand on the simulated robot
  step 0 - $APP simulate e2h-sim.yaml --camera-mount world --pose-sd 0.002
  step 0 ok $APP calibrate e2h-sim.yaml --out e2h-sim-result --method hand-eye --board chessboard:5x6:0.02 --board-geometry
  step 0 - build/bin/selfcalib-yaml-check e2h-sim-result/results.yaml status eq ok bMc.pose size 6 eMo.pose size 6
  ;;
boards)
  step 0 - $APP simulate charuco.yaml --images --target charuco
  step 0 ok $APP calibrate charuco.yaml --out charuco-result --board charuco:7x5:0.02:0.015:DICT_6X6_250
  step 0 - $APP simulate at.yaml --images --target apriltags
  step 0 ok $APP calibrate at.yaml --out at-result --board apriltag-bundle:tags.yaml
  ;;
real)
  # README "Calibrate a real robot" and getting-started 4: the Franka eye-in-hand set, then the
  # command import suggests, which is the README's.
  step 0 - $APP import ../shared/data/visp-franka-eye-in-hand --out franka.yaml
  cmd=$(suggested franka.yaml franka-result)
  step 0 ok $APP $cmd
  step 0 - build/bin/selfcalib-yaml-check franka-result/results.yaml status eq ok method eq hand-eye
  # The industrial_calibration set: the suggestion uses its circle grid and, its intrinsics being
  # nominal values, estimates the principal point and the distortion.
  step 0 - $APP import ../shared/data/industrial-calibration-10x10 --out ic.yaml
  [ -s ic-robot.yaml ] || fail "import wrote no ic-robot.yaml"
  cmd=$(suggested ic.yaml ic-result)
  step 0 ok $APP $cmd
  step 0 - build/bin/selfcalib-yaml-check ic-result/results.yaml status eq ok method eq hand-eye camera.px range 520 560
  # The eye-to-hand set: the suggestion (import names the tag it sees: its id and geometry, so eMo
  # too and the tag's corners as the yardstick), then getting-started's command, the same.
  step 0 - $APP import ../shared/data/visp-franka-eye-to-hand --out e2h.yaml
  cmd=$(suggested e2h.yaml e2h-suggested)
  step 0 ok $APP $cmd
  step 0 - build/bin/selfcalib-yaml-check e2h-suggested/results.yaml status eq ok eMo.pose size 6
  step 0 ok $APP calibrate e2h.yaml --out e2h-out --method hand-eye --board apriltag:36h11:0.048:10 --board-geometry
  step 0 - build/bin/selfcalib-yaml-check e2h-out/results.yaml status eq ok bMc.pose size 6 eMo.pose size 6
  ;;
*)
  fail "unknown part '$PART' (sim, boards or real)"
  ;;
esac
echo "newcomer-$PART-ok"
