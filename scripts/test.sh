#!/usr/bin/env bash
# Builds and runs the whole test suite: formatting, the release build with
# warnings as errors, all tests, then the unit tests again under
# AddressSanitizer + UndefinedBehaviorSanitizer. CI runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

jobs=$(nproc)

echo "== clang-format"
mapfile -t sources < <(git ls-files -co --exclude-standard '*.cpp' '*.hpp')
clang-format --dry-run -Werror "${sources[@]}"

echo "== release build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSURFDEFORM_WERROR=ON \
  -DSURFDEFORM_BUILD_TESTS=ON -DSURFDEFORM_BUILD_BENCH=ON > /dev/null
cmake --build build -j "$jobs"

echo "== sanitizer build (address, undefined)"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFDEFORM_WERROR=ON \
  -DSURFDEFORM_SANITIZE=ON -DSURFDEFORM_BUILD_TESTS=ON -DSURFDEFORM_BUILD_BENCH=OFF > /dev/null
cmake --build build-asan -j "$jobs"
echo "== unit tests under sanitizers"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j "$jobs"

echo "== mesh import fuzzer (libFuzzer, fixed seed, 100000 inputs)"
FUZZ_RUNS=100000 tests/fuzz/run.sh > build-fuzz.log 2>&1 || { tail -40 build-fuzz.log; exit 1; }
grep -E "stat::number_of_executed_units" build-fuzz.log

echo "== all tests (release)"
ctest --test-dir build --output-on-failure -j "$jobs"
