#!/usr/bin/env bash
# Makes the README's picture (docs/viewer.png) from the real viewer in
# Chromium: builds the server if needed, opens the page as a newcomer does,
# and saves it once the exact result is on screen. Run it after a change to
# the viewer's look and commit the picture it writes.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target surfdeform-server
node tests/browser/screenshot.mjs build/server/surfdeform-server "${1:-docs/viewer.png}"
