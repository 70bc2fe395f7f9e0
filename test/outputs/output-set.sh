#!/bin/sh
# Tests of calibrate's output set (README "No data loss"): output-set.sh APP WORK_DIR CASE
#   quote       a ' and a $(...) in --out: no shell runs them (gnuplot is started without a shell)
#   concurrent  two calibrations into one --out: the second refused (exit 1), the first's set intact
#               (the first is paused while it holds the lock, the second runs meanwhile)
#   kill        kill -9 at 17 moments of a run with --force (dense in its second half, where it
#               writes): the earlier set or the new one, never a mix; no temporaries after the next run
#   simulate-kill  simulate --images --force killed while it renders (caught holding the lock of its
#               new image directory, seen in /proc/locks): the earlier dataset and its images intact;
#               the next run leaves no temporaries and removes the earlier run's images
#   full-disk   a full file system (tmpfs in a private mount namespace; skipped, exit 77, without
#               the rights): simulate --images and calibrate fail with "No space left on device",
#               exit 1, the earlier set intact, no dataset pointing at missing images
set -u
APP="$1"; WORK="$2"; CASE="$3"
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAILED: $*"; exit 1; }
# The simulated joints are exact and stated so: the output set is the subject, not the robot's error.
J="--joint-sd 0"
"$APP" simulate ds.yaml --poses 12 --seed 5 > /dev/null 2>&1 || fail "simulate"
# The set's files (report.md holds wall times: compared without its stage-times table).
files="model.yaml model.urdf camera.xml results.yaml report/residuals.dat report/trajectory.dat"
same_set() { # same_set DIR REF: every file of DIR equals REF's
  for f in $files; do cmp -s "$1/$f" "$2/$f" || return 1; done
  [ -s "$1/report/report.md" ] || return 1
  sed '/^## Stage times/,/^## [^S]/d' "$1/report/report.md" > /tmp/same_set.$$.a
  sed '/^## Stage times/,/^## [^S]/d' "$2/report/report.md" > /tmp/same_set.$$.b
  cmp -s /tmp/same_set.$$.a /tmp/same_set.$$.b; r=$?; rm -f /tmp/same_set.$$.a /tmp/same_set.$$.b; return $r
}

case "$CASE" in
quote)
  d="it's \$(touch PWNED) \`touch PWNED2\`"
  mkdir "$d" || fail mkdir
  "$APP" calibrate ds.yaml $J --out "$d/out" --calibration 10 > log.txt 2>&1 || { cat log.txt; fail "calibrate"; }
  [ -e PWNED ] || [ -e PWNED2 ] || [ -e "$d/PWNED" ] && fail "a shell ran a command from --out"
  grep -q "figures drawn with gnuplot" log.txt || { cat log.txt; fail "figures"; }
  test -s "$d/out/report/residuals.png" || fail "no figure"
  echo "quote-ok"
  ;;
concurrent)
  "$APP" calibrate ds.yaml $J --out ref --calibration 10 > /dev/null 2>&1 || fail "reference run"
  # The first run is paused (SIGSTOP) at a moment it holds the lock on out, seen in /proc/locks
  # without taking it; the second runs while it is paused, then the first goes on: the order holds
  # under any load. A first run that ends before it is caught holding the lock is run again.
  [ -r /proc/locks ] || { echo "SKIPPED: no /proc/locks"; exit 77; }
  holds_lock() { # holds_lock PID: PID holds the flock of .out.lock (no lock taken to find out)
    ino=$(stat -c %i .out.lock 2> /dev/null) || return 1
    grep -q "^[0-9]*: FLOCK  *ADVISORY  *WRITE $1 [0-9a-f]*:[0-9a-f]*:$ino " /proc/locks
  }
  running() { # running PID: not ended (an ended child not yet waited for is a zombie, Z)
    st=$(sed 's/^.*) //' /proc/$1/stat 2> /dev/null | cut -c1) && [ -n "$st" ] && [ "$st" != Z ]
  }
  caught=no
  for attempt in 1 2 3 4 5 6 7 8 9 10; do
    rm -rf out
    "$APP" calibrate ds.yaml $J --out out --calibration 10 > a.log 2>&1 &
    pid=$!
    while running $pid; do # (polled every 10 ms; the order comes from the pause)
      if holds_lock $pid; then
        kill -STOP $pid
        # paused: it cannot release the lock now; make sure it had not just done so
        if holds_lock $pid; then caught=yes; break; fi
        kill -CONT $pid
      fi
      sleep 0.01
    done
    [ $caught = yes ] && break
    wait $pid || { cat a.log; fail "first run (attempt $attempt) exit $?"; }
  done
  [ $caught = yes ] || fail "the first run was never caught holding the lock (10 runs)"
  "$APP" calibrate ds.yaml $J --out out --calibration 11 --force > b.log 2>&1
  b=$?
  kill -CONT $pid
  wait $pid; a=$?
  [ $a -eq 0 ] || { cat a.log; fail "first run exit $a"; }
  [ $b -eq 1 ] || { cat b.log; fail "second run exit $b, expected 1"; }
  grep -q "is being written by another run" b.log || { cat b.log; fail "message"; }
  same_set out ref || fail "the first run's set is not intact"
  ls -a | grep -q '\.tmp-\|\.lock' && fail "temporaries left: $(ls -a)"
  echo "concurrent-ok"
  ;;
kill)
  "$APP" calibrate ds.yaml $J --out old --calibration 10 > /dev/null 2>&1 || fail "old"
  t0=$(date +%s%N)
  "$APP" calibrate ds.yaml $J --out new --calibration 11 > /dev/null 2>&1 || fail "new"
  ms=$(( ($(date +%s%N) - t0) / 1000000 )) # a run's duration: the kills sweep its second half densely
  cmp -s old/results.yaml new/results.yaml && fail "old and new sets should differ"
  cp -r old out
  delays="0.05 0.3"
  for k in 8 10 11 12 13 14 15 16 17 18 19 20 21 22 24; do
    delays="$delays $(awk -v ms=$ms -v k=$k 'BEGIN { printf "%.3f", ms * k / 20000 }')"
  done
  # The sleeps choose the moments of the kills, they order nothing: whenever a kill lands (a loaded
  # machine shifts them), the set must be the earlier one or the new one.
  for delay in $delays; do
    "$APP" calibrate ds.yaml $J --out out --calibration 11 --force > /dev/null 2>&1 &
    pid=$!
    sleep $delay
    kill -9 $pid 2> /dev/null
    wait $pid 2> /dev/null
    if same_set out old; then state=old; elif same_set out new; then state=new; else fail "a mixed set after a kill at $delay s"; fi
    echo "killed at $delay s: $state set"
    rm -rf out && cp -r old out
  done
  "$APP" calibrate ds.yaml $J --out out --calibration 11 --force > /dev/null 2>&1 || fail "run after the kills"
  same_set out new || fail "the run after the kills"
  ls -a | grep -q '\.tmp-\|\.lock' && fail "temporaries left: $(ls -a)"
  echo "kill-ok"
  ;;
simulate-kill)
  [ -r /proc/locks ] || { echo "SKIPPED: no /proc/locks"; exit 77; }
  mkdir sim && cd sim || fail "mkdir"
  "$APP" simulate ds.yaml --poses 4 --seed 5 --images > /dev/null 2>&1 || fail "the earlier run"
  cp ds.yaml ../earlier.yaml && old_dir=$(ls -d ds-images-*) && cp -r "$old_dir" ../earlier-images
  rendering() { # rendering PID: PID holds the lock of a new image directory (no lock taken to find out)
    for l in .ds-images-*.lock; do
      ino=$(stat -c %i "$l" 2> /dev/null) || continue
      grep -q "^[0-9]*: FLOCK  *ADVISORY  *WRITE $1 [0-9a-f]*:[0-9a-f]*:$ino " /proc/locks && return 0
    done
    return 1
  }
  running() { st=$(sed 's/^.*) //' /proc/$1/stat 2> /dev/null | cut -c1) && [ -n "$st" ] && [ "$st" != Z ]; }
  caught=no
  for attempt in 1 2 3 4 5 6 7 8 9 10; do
    "$APP" simulate ds.yaml --poses 6 --seed 6 --images --force > /dev/null 2>&1 &
    pid=$!
    while running $pid; do # (polled every 10 ms; the order comes from the lock seen held)
      if rendering $pid; then kill -9 $pid; caught=yes; break; fi
      sleep 0.01
    done
    wait $pid 2> /dev/null
    [ $caught = yes ] && break
    # the run ended before it was caught: it replaced the set; start again from the earlier one
    rm -rf ds-images-* && cp ../earlier.yaml ds.yaml && cp -r ../earlier-images "$old_dir"
  done
  [ $caught = yes ] || fail "simulate was never caught rendering (10 runs)"
  cmp -s ds.yaml ../earlier.yaml || fail "the earlier dataset changed"
  diff -r "$old_dir" ../earlier-images > /dev/null || fail "the earlier images changed"
  "$APP" simulate ds.yaml --poses 3 --seed 7 --images --force > /dev/null 2>&1 || fail "the run after the kill"
  [ -e "$old_dir" ] && fail "the earlier run's images were not removed"
  ls -a | grep -q '\.tmp-\|\.lock' && fail "temporaries left: $(ls -a)"
  [ "$(ls -d ds-images-* | wc -l)" -eq 1 ] || fail "image directories: $(ls -d ds-images-*)"
  for f in $(sed -n 's/^ *image: //p' ds.yaml); do [ -s "$f" ] || fail "the dataset points at a missing image $f"; done
  echo "simulate-kill-ok"
  ;;
full-disk)
  command -v unshare > /dev/null || { echo "SKIPPED: no unshare"; exit 77; }
  unshare -m sh -c 'mkdir -p disk && mount -t tmpfs -o size=64k tmpfs disk' 2> /dev/null || {
    echo "SKIPPED: cannot mount a tmpfs (needs root and a mount namespace)"; exit 77; }
  unshare -m sh -c '
    fail() { echo "FAILED: $*"; exit 1; }
    APP="$1"; files="$2"
    same_set() { for f in $files; do cmp -s "$1/$f" "$2/$f" || return 1; done; }
    mkdir -p disk && mount -t tmpfs -o size=3m tmpfs disk || exit 1
    "$APP" calibrate ds.yaml --joint-sd 0 --out disk/out --calibration 10 > /dev/null 2>&1 || fail "first run"
    cp -r disk/out earlier
    # fill the disk, then calibrate again: refused with the reason, the earlier set intact
    dd if=/dev/zero of=disk/filler bs=64k > /dev/null 2>&1
    "$APP" calibrate ds.yaml --joint-sd 0 --out disk/out --calibration 6 --force > log.txt 2>&1
    rc=$?; cat log.txt | grep "error"
    [ $rc -eq 1 ] || fail "calibrate on a full disk: exit $rc"
    grep -q "No space left on device" log.txt || fail "no errno text"
    same_set disk/out earlier || fail "the earlier set changed"
    cmp -s disk/out/report/report.md earlier/report/report.md || fail "the earlier report changed"
    ls -a disk | grep -q "\.tmp-\|\.lock" && fail "temporaries left: $(ls -a disk)"
    # simulate --images on a nearly full disk: the error, and no dataset pointing at missing images
    truncate -s -300K disk/filler # room for one image of about 180 kB, not four
    mkdir -p disk/sim
    "$APP" simulate disk/sim/ds.yaml --poses 4 --images > log.txt 2>&1
    rc=$?; cat log.txt | grep "error"
    [ $rc -eq 1 ] || fail "simulate --images on a full disk: exit $rc"
    grep -q "No space left on device" log.txt || fail "no errno text"
    grep -q "^wrote" log.txt && fail "simulate said wrote"
    [ -e disk/sim/ds.yaml ] && fail "a dataset was written"
    [ -z "$(ls -A disk/sim)" ] || fail "left in disk/sim: $(ls -A disk/sim)"
    echo "full-disk-ok"
  ' sh "$APP" "$files"
  ;;
*) fail "unknown case $CASE" ;;
esac
