#!/usr/bin/env bash
# Uploaded fonts in the formats POST /v1/fonts takes, against the real
# server: a built-in font compressed to WOFF2 by Google's encoder
# (tests/fonts, npm wawoff2) is read as WOFF2, and a text set in it is the
# same mesh, byte for byte, as in the TrueType file it came from; a
# truncated WOFF2 is a 400 and the server goes on.
# Usage: woff2_fonts.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/launch_server.sh"
serve_for_test "$1"

ttf=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
node "$here/../fonts/to_woff2.mjs" "$ttf" "$out/dejavu.woff2"
[[ $(head -c 4 "$out/dejavu.woff2") == wOF2 ]] || fail "the encoder wrote no WOFF2"

code=$(curl -sS -o "$out/up.json" -w '%{http_code}' --data-binary @"$out/dejavu.woff2" \
  -H 'Content-Type: font/woff2' "$base/v1/fonts")
[[ $code == 201 ]] || fail "POST /v1/fonts (WOFF2): $code $(cat "$out/up.json")"
read -r id format family < <(python3 -c '
import json, sys
f = json.load(open(sys.argv[1]))
print(f["id"], f["format"], f["family"].replace(" ", "_"))' "$out/up.json")
[[ $format == woff2 && $family == DejaVu_Sans ]] || fail "read as $format, $family"

text_mesh() {  # FONT OUTPUT
  curl -sS --fail-with-body -H 'Content-Type: application/json' -o "$2" \
    -d '{"text":{"string":"Ada Lovelace, 1815 \u0633\u0644\u0627\u0645","font":"'"$1"'"},"output":{"format":"ply"}}' \
    "$base/v1/text" || fail "POST /v1/text with $1: $(cat "$2")"
}
text_mesh DejaVuSans "$out/ttf.ply"
text_mesh "$id" "$out/woff2.ply"
cmp -s "$out/ttf.ply" "$out/woff2.ply" || fail "the WOFF2's text differs from the TrueType file's"
[[ $(stat -c %s "$out/ttf.ply") -gt 10000 ]] || fail "the text's mesh is $(stat -c %s "$out/ttf.ply") bytes"

# Truncated: FreeType's WOFF2 reader refuses it, a 400 naming the font.
head -c 20000 "$out/dejavu.woff2" > "$out/cut.woff2"
code=$(curl -sS -o "$out/cut.json" -w '%{http_code}' --data-binary @"$out/cut.woff2" "$base/v1/fonts")
[[ $code == 400 ]] || fail "a truncated WOFF2: $code $(cat "$out/cut.json")"
grep -q '"field":"font"' "$out/cut.json" || fail "the refusal names the font: $(cat "$out/cut.json")"
curl -sS --fail "$base/healthz" > /dev/null || fail "the server is down after a broken font"
stop_served_server
echo "woff2 fonts: ok"
