#!/usr/bin/env bash
# Text shaped and meshed: surfdeform's typesetter (HarfBuzz, FreeType,
# CGAL's CDT; bench/text_bench) beside opentype.js + earcut in Node
# (bench/text_peer, installed by scripts/setup.sh), the same texts, font,
# tolerance and solids, in one run. Prints each side's JSON and the ratios.
# Usage: bench/text_vs_opentype.sh [BUILD_DIR] [REPEAT]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
repeat=${2:-50}
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
ours=$("$build/bench/text_bench" --font "$font" --repeat "$repeat")
texts=$(python3 -c 'import json,sys; [print(t["text"]) for t in json.load(sys.stdin)["texts"]]' <<< "$ours")
mapfile -t args <<< "$texts"
peer=$(node "$root/bench/text_peer/peer.mjs" "$font" 0.01 4 "$repeat" "${args[@]}")
echo "$ours"
echo "$peer"
python3 - "$ours" "$peer" <<'PY'
import json, sys
ours, peer = json.loads(sys.argv[1]), json.loads(sys.argv[2])
for a, b in zip(ours["texts"], peer["texts"]):
    print(f'{a["chars"]:4d} chars: ours {a["ms"]:.3f} ms, {a["triangles"]} triangles '
          f'(fewest over the points the tolerance needs: {a["fewest_triangles"]}); '
          f'peer {b["ms"]:.3f} ms, {b["triangles"]} triangles; '
          f'peer/ours time {b["ms"] / a["ms"]:.2f}x, triangles {a["triangles"] / b["triangles"]:.3f}x')
PY
