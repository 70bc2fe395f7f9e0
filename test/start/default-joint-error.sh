#!/bin/sh
# The bundle method's robot error measured by default on a dataset written as a user writes one from
# a real arm's recording: joint readings off by JOINT_DEG (Gaussian, every joint of every
# calibration view), each calibration view's image off by a small model residual (a per-view camera
# rotation of MODEL_MRAD about its x and y axes, what no kinematic parameter explains: the image
# points shifted by f times it), and no robot_error key. Three runs on the first CAL views:
#   default  calibrate with no robot-error option: its robot error modelled and measured;
#   told     calibrate --joint-sd TRUE: the joint readings' true level stated;
#   trusted  calibrate --joint-sd 0;
# each compared (visp-selfcalib compare) with the true robot on the held-out views' true joints.
# Prints the measured joint sd over the true one and the held-out error of the three runs (the
# mean position error of the relative poses from the first held-out view, mm); fails unless the
# default run is ok with its robot error measured (or doubtful by the workspace check alone, when the
# truth confirms that its model is worse than the nominal one over the joint limits), the joint sd
# within 25 % of the truth and the held-out error within 1.3x the told run's.
# Usage: default-joint-error.sh APP YAML_CHECK WORK_DIR SEED [JOINT_DEG MODEL_MRAD POSES CAL]
APP=$1 YCHK=$2 W=$3 SEED=$4 JOINT_DEG=${5:-0.03} MODEL_MRAD=${6:-0.05} POSES=${7:-25} CAL=${8:-15}
rm -rf "$W" && mkdir -p "$W" && cd "$W" || exit 1
$APP simulate sim.yaml --poses "$POSES" --seed "$SEED" > /dev/null 2>&1 || { echo "simulate failed"; exit 1; }
grep -q robot_error sim.yaml && { echo "simulate wrote a robot_error"; exit 1; }
# The held-out views' true joints (one configuration per line), then the calibration views with
# their readings and images perturbed (awk's seeded generator, Box-Muller normals).
sed -n 's/^ *- joints: \[\(.*\)\]$/\1/p' sim.yaml | tr -d , | tail -n +$((CAL + 1)) > heldout.txt
awk -v seed="$SEED" -v cal="$CAL" -v jsd="$JOINT_DEG" -v msd="$MODEL_MRAD" '
  function normal() { return sqrt(-2 * log(1 - rand())) * cos(6.283185307179586 * rand()) }
  BEGIN { srand(1000 + seed); view = 0; keep = 1; pi = 3.141592653589793 }
  /^poses:/ { print; next }
  /^  - joints: \[/ {
    ++view
    if (view > cal) { keep = 0; next }
    line = $0; sub(/^  - joints: \[/, "", line); sub(/\]$/, "", line)
    n = split(line, q, ", ")
    out = "  - joints: ["
    for (i = 1; i <= n; ++i) out = out sprintf("%.17g", q[i] + normal() * jsd * pi / 180) (i < n ? ", " : "")
    print out "]"
    # The model residual: 1500 px times a rotation (rad) about the camera x and y axes.
    du = 1500 * normal() * msd * 1e-3; dv = 1500 * normal() * msd * 1e-3
    next
  }
  /^[a-z_]+:/ { keep = 1; print; next }
  !keep { next }
  /^      - \[/ {
    line = $0; sub(/^      - \[/, "", line); sub(/\]$/, "", line)
    split(line, p, ", ")
    printf "      - [%s, %.17g, %.17g]\n", p[1], p[2] + du, p[3] + dv
    next
  }
  { print }' sim.yaml > ds.yaml
[ "$(grep -c '^  - joints:' ds.yaml)" -eq "$CAL" ] || { echo "ds.yaml: not $CAL views"; exit 1; }
grep -q robot_error ds.yaml && exit 1
TRUE=$(awk -v d="$JOINT_DEG" 'BEGIN { printf "%.6g", d * 3.141592653589793 / 180 }')
# The default and told runs: ok, or doubtful by the workspace check alone (exit 3), which the truth
# must then confirm (below): over the joint limits the model is worse than the nominal one.
for r in default told; do
  o=""; [ $r = told ] && o="--joint-sd $TRUE"
  $APP calibrate ds.yaml --out $r --folds 0 $o > $r.log 2>&1
  rc=$?
  if [ $rc -eq 3 ] && [ -f $r/results.yaml ] && grep -q '^status: doubtful' $r/results.yaml; then
    doubts=$(sed -n 's/^ *- {code: \([^,]*\), severity: doubt.*/\1/p' $r/results.yaml | sort -u | tr '\n' ' ')
    [ "$doubts" = "workspace-worse-than-nominal " ] || { echo "$r: doubts $doubts"; cat $r.log; exit 1; }
    echo "$r: doubtful by the workspace check"
  elif [ $rc -ne 0 ]; then cat $r.log; exit 1; fi
done
# Trusted, the readings' error is left out: doubtful (exit 3) is its expected answer.
$APP calibrate ds.yaml --out trusted --folds 0 --joint-sd 0 > trusted.log 2>&1
[ -f trusted/results.yaml ] || { cat trusted.log; exit 1; }
for r in default told trusted; do
  $APP compare $r sim-truth.yaml --joints heldout.txt --yaml $r-c.yaml > /dev/null 2>&1 || { echo "compare $r failed"; exit 1; }
done
# The held-out error: the mean position error of the relative poses from the first held-out view.
rms() { sed -n '/^from_first:/,$p' "$1-c.yaml" | sed -n 's/^ *calibrated: {mean_m: \([^,]*\),.*/\1/p' | head -1; }
measured=$(grep -o ' joint_sd: \[[^],]*' default/results.yaml | head -1 | sed 's/.*\[//')
awk -v s="$SEED" -v m="$measured" -v t="$TRUE" -v d="$(rms default)" -v k="$(rms told)" -v u="$(rms trusted)" 'BEGIN {
  printf "seed %s: joint sd measured/true %.3f, held-out error default %.3f mm, told the true level %.3f mm, trusted %.3f mm, default/told %.3f\n",
         s, m / t, 1e3 * d, 1e3 * k, 1e3 * u, d / k
  if (!(d > 0 && k > 0 && u > 0)) exit 1
  if (d / k > 1.3) { print "held-out error above 1.3x the told run'"'"'s"; exit 1 }
}' || exit 1
# A workspace doubt is right only when the model is worse than the nominal one there (compare's
# random pairs over the joint limits, position or rotation).
for r in default told; do
  grep -q '^status: doubtful' $r/results.yaml || continue
  awk '/^random_pairs:/ { f = 1 } f && /calibrated:/ { match($0, /rms_m: [^,]*/); ct = substr($0, RSTART + 7, RLENGTH - 7);
         match($0, /rms_rad: [^,]*/); cr = substr($0, RSTART + 9, RLENGTH - 9) }
       f && /nominal:/ { match($0, /rms_m: [^,]*/); nt = substr($0, RSTART + 7, RLENGTH - 7);
         match($0, /rms_rad: [^,]*/); nr = substr($0, RSTART + 9, RLENGTH - 9); f = 0 }
       END { printf "'$r': doubtful, over the workspace %.2f mm / %.2f mrad against the nominal %.2f / %.2f\n", 1e3 * ct, 1e3 * cr, 1e3 * nt, 1e3 * nr
             exit !(ct + 0 > nt + 0 || cr + 0 > nr + 0) }' $r-c.yaml || { echo "$r: doubtful, yet better than nominal over the workspace"; exit 1; }
done
# The default run: ok or doubtful as above, the robot error measured, its joint sd within 25 % of the truth.
$YCHK default/results.yaml method eq bundle bundle_adjustment.robot_error eq measured \
  bundle_adjustment.joint_sd.0 range $(awk -v t="$TRUE" 'BEGIN { printf "%.6g %.6g", 0.75 * t, 1.25 * t }') || exit 1
echo default-joint-error-ok
