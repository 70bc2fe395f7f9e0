#!/usr/bin/env bash
# Fuzzes the robot-model and dataset YAML parsers with libFuzzer (clang, AddressSanitizer and
# UndefinedBehaviorSanitizer) for a bounded time: cmake/fuzz.sh [SECONDS_PER_TARGET] [BUILD_DIR]
# (defaults 300 and build-fuzz). Not part of the default test run. Installs clang and its runtime
# (Debian's clang, libclang-rt-14-dev) when missing. Starts from the seeds in test/fuzz/corpus/;
# what it learns goes to BUILD_DIR/corpus/, a crashing input to BUILD_DIR/crashes/ (then the script
# fails): add such an input to the parser tests (test-io, test-kinematics) as a regression test.
set -euo pipefail
SRC="$(cd "$(dirname "$0")/.." && pwd)"
SECONDS_PER_TARGET="${1:-300}"
BUILD="${2:-build-fuzz}"
"$SRC/cmake/install-deps.sh"
if ! command -v clang++ > /dev/null || ! dpkg -s libclang-rt-14-dev > /dev/null 2>&1; then
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get install -y --no-install-recommends clang libclang-rt-14-dev
fi
# The library gets coverage instrumentation (fuzzer-no-link); the targets link libFuzzer's main.
# EIGEN_MALLOC_ALREADY_ALIGNED: see cmake/sanitize.sh (Eigen changes its allocation under ASan).
FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer"
# As in cmake/sanitize.sh: UB is fatal, except the one ViSP report that cmake/ubsan.supp suppresses.
FLAGS="$FLAGS -fno-sanitize-recover=undefined -fsanitize-recover=nonnull-attribute"
FLAGS="$FLAGS -DEIGEN_MALLOC_ALREADY_ALIGNED=1"
cmake -S "$SRC" -B "$BUILD" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="$FLAGS" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DVISP_SELFCALIB_BUILD_FUZZERS=ON -DVISP_SELFCALIB_BUILD_TESTS=OFF -DVISP_SELFCALIB_BUILD_TUTORIALS=OFF \
  -DVISP_SELFCALIB_BUILD_APPS=OFF -DVISP_SELFCALIB_BUILD_BENCHMARKS=OFF
cmake --build "$BUILD" -j2 --target fuzz-robot-model fuzz-dataset
export ASAN_OPTIONS="detect_leaks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SRC/cmake/ubsan.supp"
status=0
for target in robot-model dataset; do
  mkdir -p "$BUILD/corpus/$target" "$BUILD/crashes/$target"
  echo "fuzz-$target: ${SECONDS_PER_TARGET} s"
  if ! "$BUILD/bin/fuzz-$target" -max_total_time="$SECONDS_PER_TARGET" -max_len=4096 -timeout=10 \
      -dict="$SRC/test/fuzz/yaml.dict" -artifact_prefix="$BUILD/crashes/$target/" -print_final_stats=1 \
      "$BUILD/corpus/$target" "$SRC/test/fuzz/corpus/$target" 2> "$BUILD/fuzz-$target.log"; then
    status=1
    echo "fuzz-$target found a failure: see $BUILD/fuzz-$target.log and $BUILD/crashes/$target/"
  fi
  grep -E "^stat::number_of_executed_units|^stat::new_units_added" "$BUILD/fuzz-$target.log" || true
done
exit $status
