#!/usr/bin/env bash
# Builds and runs the whole test suite: formatting, the release build with
# warnings as errors, the unit tests under AddressSanitizer +
# UndefinedBehaviorSanitizer and the integration, CLI and failover tests against
# the sanitized server, the fuzzers, then every test (unit,
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

echo "== sanitizer build (address, undefined): the unit tests, the server, the CLI"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFDEFORM_WERROR=ON \
  -DSURFDEFORM_SANITIZE=ON -DSURFDEFORM_BUILD_TESTS=ON -DSURFDEFORM_BUILD_BENCH=OFF > /dev/null
cmake --build build-asan -j "$jobs" --target surfdeform_unit_tests surfdeform-server \
  surfdeform-server-faults surfdeform_integration_tests surfdeform no_orphans
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
echo "== unit tests under sanitizers"
build-asan/tests/surfdeform_unit_tests --gtest_brief=1
# docs/RELIABILITY.md, "Sanitizers": the integration tests, the curl
# examples, the CLI and the replica failover against the sanitized server
# (a sanitizer report aborts the server, and the test that talked to it fails).
echo "== integration, CLI and failover tests against the sanitized server"
ctest --test-dir build-asan --output-on-failure -j "$jobs" \
  -R '^(Server|SlowClients|Faults|FaultPoints|Disconnects|BoundedMemory)|CurlExamples|CliAgainst'
# Sanitized replicas are some ten times slower: a request nginx retries on a
# survivor waits for a slot longer than the 5 s default.
SURFDEFORM_QUEUE_TIMEOUT_MS=60000 ctest --test-dir build-asan --output-on-failure \
  -R ReplicaFailover
unset ASAN_OPTIONS UBSAN_OPTIONS

echo "== fuzzers (libFuzzer, fixed seed: mesh import, request JSON, HTTP connections)"
FUZZ_RUNS=${FUZZ_RUNS:-30000} tests/fuzz/run.sh > build-fuzz.log 2>&1 || {
  tail -40 build-fuzz.log
  exit 1
}
grep -E "^== fuzzing|stat::number_of_executed_units" build-fuzz.log

echo "== all tests (release)"
ctest --test-dir build --output-on-failure -j "$jobs"
