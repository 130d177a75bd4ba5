#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer) and runs them:
#   import  mesh import (every format), then every writer on what it accepted
#   params  request JSON into the request types
#   http    whole connections into the HTTP layer: framing, multipart, routes,
#           and the connection gate's head checks
#   estimate  small deformation requests with extreme numbers: each answered
#           within a time bound (the target aborts past it) and -rss_limit_mb
#   memory  parameter sets that scale memory (sampling, range, lattice factor,
#           relax steps, tolerance, frames): the heap a request takes never
#           passes the service's estimate for it
#   font    font files (whole, or real fonts with bytes overwritten) through
#           FreeType, HarfBuzz and the glyph mesher, behind the font limits
# Each starts from its committed seeds (tests/fuzz/seeds/TARGET) and the
# corpus it grew before, kept in BUILD/corpus/TARGET between runs.
# Findings go to BUILD/crashes/TARGET-*; the run fails on one.
#
# Usage: tests/fuzz/run.sh [SECONDS] [TARGET...]
#   SECONDS per target (default 60); targets default to all six.
#   FUZZ_RUNS=N instead runs N inputs per target from a fixed seed
#   (deterministic on a fresh clone: what scripts/test.sh does).
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=60
if [[ ${1:-} =~ ^[0-9]+$ ]]; then
  seconds=$1
  shift
fi
targets=("$@")
((${#targets[@]})) || targets=(import params http estimate memory font)
# FUZZ_BUILD_DIR=DIR uses a build already configured with SURFDEFORM_FUZZ
# (scripts/test.sh's build-san, which also holds the sanitized tests); by
# default the fuzzers get a build of their own, build-fuzz.
dir=${FUZZ_BUILD_DIR:-build-fuzz}
if [[ -z ${FUZZ_BUILD_DIR:-} ]]; then
  CC=clang-14 CXX=clang++-14 cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSURFDEFORM_FUZZ=ON -DSURFDEFORM_BUILD_TESTS=OFF -DSURFDEFORM_BUILD_BENCH=OFF \
    -DSURFDEFORM_AVX2=OFF > /dev/null
fi
cmake --build "$dir" --target "${targets[@]/%/_fuzzer}"
mkdir -p "$dir/crashes"
for t in "${targets[@]}"; do
  if [[ -n ${FUZZ_RUNS:-} ]]; then
    # An estimate input is a whole request through the service (milliseconds
    # under the sanitizers, against microseconds for the parsers): a tenth.
    # An http input is a whole connection (some 5 ms each, 140 s for 30000
    # in CI): a third.
    runs=$FUZZ_RUNS
    [[ $t == estimate ]] && runs=$((FUZZ_RUNS / 10))
    [[ $t == http ]] && runs=$((FUZZ_RUNS / 3))
    # A memory input is a flattening or an animation (some 35 ms each under
    # the sanitizers): a thirtieth. The release build's property test
    # (MemoryEstimatesAreUpperBounds) runs 10,000 of the same cases.
    [[ $t == memory ]] && runs=$((FUZZ_RUNS / 30))
    # A font input opens a whole font and shapes and meshes a line of four
    # scripts (a few ms under the sanitizers): a tenth.
    [[ $t == font ]] && runs=$((FUZZ_RUNS / 10))
    budget=(-runs="$runs" -seed=1)
  else
    budget=(-max_total_time="$seconds")
  fi
  echo "== fuzzing $t"
  mkdir -p "$dir/corpus/$t"
  # Quiet by default: a line per second of progress is noise in CI logs.
  "$dir/tests/fuzz/${t}_fuzzer" "$dir/corpus/$t" "tests/fuzz/seeds/$t" "${budget[@]}" \
    -max_len=65536 -timeout=20 -rss_limit_mb=2048 -artifact_prefix="$dir/crashes/$t-" \
    -print_final_stats=1 -print_coverage=0 -close_fd_mask=1
done
