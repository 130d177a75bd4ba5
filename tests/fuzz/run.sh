#!/usr/bin/env bash
# Builds the mesh import fuzzer with clang (libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer) and runs it from a seed corpus of small real
# files: for SECONDS (default 60), or, with FUZZ_RUNS set, for that many inputs
# from a fixed seed (deterministic: what scripts/test.sh does).
# Usage: tests/fuzz/run.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-60}
CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSURFDEFORM_FUZZ=ON -DSURFDEFORM_BUILD_TESTS=OFF -DSURFDEFORM_BUILD_BENCH=OFF \
  -DSURFDEFORM_AVX2=OFF > /dev/null
cmake --build build-fuzz --target import_fuzzer
corpus=$(mktemp -d)
trap 'rm -rf "$corpus"' EXIT
models=/usr/share/assimp/models
for f in PLY/cube.ply PLY/cube_binary.ply OBJ/box.obj OBJ/cube_usemtl.obj STL/triangle.stl \
         OFF/Cube.off glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf; do
  cp "$models/$f" "$corpus/$(echo "$f" | tr / _)"
done
mkdir -p build-fuzz/crashes
if [[ -n ${FUZZ_RUNS:-} ]]; then
  budget=(-runs="$FUZZ_RUNS" -seed=1)
else
  budget=(-max_total_time="$seconds")
fi
./build-fuzz/tests/fuzz/import_fuzzer "$corpus" "${budget[@]}" -max_len=65536 \
  -rss_limit_mb=2048 -artifact_prefix=build-fuzz/crashes/ -print_final_stats=1
