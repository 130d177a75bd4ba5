#!/usr/bin/env bash
# Builds and runs the whole test suite: formatting (clang-format; ESLint and
# Prettier for the JavaScript); the release build (GCC)
# with warnings as errors; one clang build under AddressSanitizer +
# UndefinedBehaviorSanitizer for the unit tests, the integration, CLI and
# failover tests against the sanitized server, and the fuzzers; a
# ThreadSanitizer build for the concurrency tests; then every test against
# the release build (unit, integration against the real server, the CLI, the
# viewer in Chromium and Firefox, the glTF validator, Draco's decoder). CI
# runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

jobs=$(nproc)
# Each stage's start, in minutes and seconds since this script began.
stage() { printf '== %s (at %dm%02ds)\n' "$*" $((SECONDS / 60)) $((SECONDS % 60)); }

stage "clang-format"
mapfile -t sources < <(git ls-files -co --exclude-standard '*.cpp' '*.hpp')
clang-format --dry-run -Werror "${sources[@]}"
stage "ESLint and Prettier (the viewer, the JavaScript tests and benchmarks)"
bash scripts/lint_js.sh

stage "release build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSURFDEFORM_WERROR=ON \
  -DSURFDEFORM_BUILD_TESTS=ON -DSURFDEFORM_BUILD_BENCH=ON > /dev/null
cmake --build build -j "$jobs"

# One clang build for the sanitizers and the fuzzers (docs/RELIABILITY.md,
# "Sanitizers"): clang-14 compiles this code under ASan + UBSan some three
# times faster than GCC 12 does. Line tables only, for them and for the
# ThreadSanitizer build: reports still name file and line, and the builds
# compile some 15% faster than with full debug information.
san_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG")
stage "sanitizer build (clang-14; address, undefined, libFuzzer): tests, server, CLI, fuzzers"
CC=clang-14 CXX=clang++-14 cmake -S . -B build-san -G Ninja "${san_flags[@]}" \
  -DSURFDEFORM_WERROR=ON -DSURFDEFORM_SANITIZE=ON -DSURFDEFORM_FUZZ=ON \
  -DSURFDEFORM_BUILD_TESTS=ON -DSURFDEFORM_BUILD_BENCH=OFF > /dev/null
cmake --build build-san -j "$jobs" --target surfdeform_unit_tests surfdeform-server \
  surfdeform-server-faults surfdeform_integration_tests surfdeform no_orphans \
  import_fuzzer params_fuzzer http_fuzzer estimate_fuzzer memory_fuzzer font_fuzzer
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
# Third-party leaks, each named and explained in the file.
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan_suppressions.txt"
stage "unit tests under sanitizers"
ctest --test-dir build-san --output-on-failure -j "$jobs" -L unit
# The integration tests, the curl examples, the CLI, request smuggling behind
# nginx and the replica failover against the sanitized server (a sanitizer report aborts the server, and the
# test that talked to it fails).
stage "integration, CLI and failover tests against the sanitized server"
ctest --test-dir build-san --output-on-failure -j "$jobs" \
  -R '^(Server|SlowClients|SlowReaders|Faults|FaultPoints|Disconnects|BoundedMemory)|CurlExamples|CliAgainst|SmugglingBehindNginx'
# Sanitized replicas are some ten times slower: a request nginx retries on a
# survivor waits for a slot longer than the 5 s default.
SURFDEFORM_QUEUE_TIMEOUT_MS=60000 ctest --test-dir build-san --output-on-failure \
  -R ReplicaFailover
unset ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS

stage "fuzzers (libFuzzer, fixed seed: mesh import, request JSON, HTTP connections, request cost, fonts)"
FUZZ_BUILD_DIR=build-san FUZZ_RUNS=${FUZZ_RUNS:-30000} tests/fuzz/run.sh > build-fuzz.log 2>&1 || {
  tail -40 build-fuzz.log
  exit 1
}
grep -E "^== fuzzing|stat::number_of_executed_units" build-fuzz.log

# ThreadSanitizer on the concurrent parts: the single-flight cache and its
# hammer test, admission, the breaker, the service, the shared tier, the
# animation's flattening, and the
# server's concurrency, shutdown, metrics, slow-client and fault tests. Address
# randomization off (setarch -R): clang 14's TSan needs its fixed memory
# layout, which kernels with more mmap randomization bits break.
stage "ThreadSanitizer build (clang-14): the concurrent parts and the server"
CC=clang-14 CXX=clang++-14 cmake -S . -B build-tsan -G Ninja "${san_flags[@]}" \
  -DSURFDEFORM_WERROR=ON -DSURFDEFORM_TSAN=ON -DSURFDEFORM_BUILD_TESTS=ON \
  -DSURFDEFORM_BUILD_BENCH=OFF > /dev/null
cmake --build build-tsan -j "$jobs" --target surfdeform_concurrency_tests surfdeform-server \
  surfdeform-server-faults surfdeform_integration_tests no_orphans
stage "concurrency tests under ThreadSanitizer"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/tsan_suppressions.txt"
setarch "$(uname -m)" -R build-tsan/tests/surfdeform_concurrency_tests --gtest_brief=1
setarch "$(uname -m)" -R ctest --test-dir build-tsan --output-on-failure -j "$jobs" \
  -R '^(ServerConcurrency|ServerShutdown|ServerTest|SlowClients|SlowReaders|Disconnects|Faults)\.'
unset TSAN_OPTIONS

stage "all tests (release)"
ctest --test-dir build --output-on-failure -j "$jobs"
stage "done"
