#!/usr/bin/env bash
# Builds and runs the whole test suite: formatting, the release build with
# warnings as errors, the unit tests under AddressSanitizer +
# UndefinedBehaviorSanitizer, the mesh import fuzzer, then every test (unit,
# integration against the real server, the CLI, the viewer in Chromium, the
# glTF validator, Draco's decoder). CI runs exactly this.
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

echo "== sanitizer build (address, undefined): the unit tests"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFDEFORM_WERROR=ON \
  -DSURFDEFORM_SANITIZE=ON -DSURFDEFORM_BUILD_TESTS=ON -DSURFDEFORM_BUILD_BENCH=OFF > /dev/null
cmake --build build-asan -j "$jobs" --target surfdeform_unit_tests
echo "== unit tests under sanitizers"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  build-asan/tests/surfdeform_unit_tests --gtest_brief=1

echo "== mesh import fuzzer (libFuzzer, fixed seed, 100000 inputs)"
FUZZ_RUNS=100000 tests/fuzz/run.sh > build-fuzz.log 2>&1 || { tail -40 build-fuzz.log; exit 1; }
grep -E "stat::number_of_executed_units" build-fuzz.log

echo "== all tests (release)"
ctest --test-dir build --output-on-failure -j "$jobs"
