#!/usr/bin/env bash
# Builds surfdeform and runs its main job. Until the HTTP server lands this is
# the flattening demo: it flattens a built-in surface and prints its quality.
# Extra arguments go to the demo (try --help).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target surfdeform-demo
exec ./build/server/surfdeform-demo "$@"
