#!/usr/bin/env bash
# Writes sample GLB output and validates it with the Khronos glTF validator;
# a truncated copy must fail (so the check itself can fail).
# Usage: check_glb_output.sh WRITE_GLB_SAMPLES_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$1" "$out"
node "$here/validate.mjs" "$out"/*.glb
head -c 600 "$out/grid.glb" > "$out/truncated.bin"
if node "$here/validate.mjs" "$out/truncated.bin" > /dev/null; then
  echo "the validator accepted a truncated GLB: the check is not working" >&2
  exit 1
fi
echo "negative control: truncated GLB rejected"
# The Draco GLB in pieces: 121 x 121 vertices in four primitives, no crack.
python3 "$here/check_glb_pieces.py" "$out/bumpy_pieces.glb" 4 14641
