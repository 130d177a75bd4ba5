#!/usr/bin/env bash
# Builds surfdeform and starts its HTTP server on 127.0.0.1:8080 with the
# in-process defaults (in-memory surface cache, no other service needed).
# Extra arguments go to the server (try --help); every flag also has an
# environment variable (SURFDEFORM_PORT, ...). Stop it with Ctrl-C.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target surfdeform-server
exec ./build/server/surfdeform-server "$@"
