#!/usr/bin/env bash
# Builds the tests with AddressSanitizer and UndefinedBehaviorSanitizer and runs them (about 15 min
# on 2 cores, the planner's slowest test alone far longer): cmake/sanitize.sh [BUILD_DIR]   (default
# build-asan). Not part of the default test run. Each test may take up to an hour instrumented.
set -euo pipefail
SRC="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="${1:-build-asan}"
# Every UB check aborts, except nonnull-attribute, which stays recoverable so that ubsan.supp can
# suppress it (suppressions only apply to recoverable checks).
# Eigen allocates differently when it sees __SANITIZE_ADDRESS__ (Memory.h); Ceres's prebuilt Eigen
# code does not, and the two would free each other's blocks: keep Eigen's usual scheme.
FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined -fsanitize-recover=nonnull-attribute"
FLAGS="$FLAGS -DEIGEN_MALLOC_ALREADY_ALIGNED=1"
cmake -S "$SRC" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$FLAGS" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DVISP_SELFCALIB_BUILD_BENCHMARKS=OFF \
  -DSELFCALIB_TEST_TIMEOUT=3600
cmake --build "$BUILD" -j2
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SRC/cmake/ubsan.supp"
export LSAN_OPTIONS="suppressions=$SRC/cmake/lsan.supp"
# install-and-consume links the installed (sanitized) static library into a plain consumer project,
# which then lacks the sanitizer runtime: it tests the packaging, not the code, and is left out.
ctest --test-dir "$BUILD" --output-on-failure -j2 -E install-and-consume
