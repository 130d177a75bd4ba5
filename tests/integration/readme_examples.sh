#!/usr/bin/env bash
# Every example of the README and docs/*.md, as written: each ```sh
# block but the two set-up commands and the load test (tested on their own)
# runs from a copy of the repository's root against the real server, with
# only these substitutions: the server's address for 127.0.0.1:8080,
# `surfdeform` the built CLI, `ID` a surface id. A curl that gets an HTTP
# error fails its block (--fail-with-body), as does any command that exits
# non-zero; every file an example writes with -o must be there, not empty.
# Then the CLI's exit code for a missing input file: 4, as the README says.
# Usage: readme_examples.sh SERVER_BINARY CLI_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=$(mktemp -d)
server_pid=
cleanup() {
  [[ -n $server_pid ]] && kill "$server_pid" 2> /dev/null && wait "$server_pid" 2> /dev/null
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

source "$here/launch_server.sh"
launch_server "$1" "$work/server.log"
server_pid=$SERVER_PID
[[ -n $SERVER_PORT ]] || fail "the server did not start: $(cat "$work/server.log")"
base="http://127.0.0.1:$SERVER_PORT"
mkdir -p "$work/bin" "$work/run"
ln -s "$(realpath "$2")" "$work/bin/surfdeform"
ln -s "$root/client" "$work/run/client"

id=$(python3 -c 'import json,sys; print(json.dumps({"surface": json.load(open(sys.argv[1]))}))' \
  "$root/client/web/samples/cone.json" \
  | curl -sS -f -H 'Content-Type: application/json' --data-binary @- "$base/v1/surfaces" \
  | python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])')
[[ $id =~ ^[0-9a-f]{32}$ ]] || fail "surface id '$id'"

python3 - "$work" "$root/README.md" "$root"/docs/*.md << 'PY'
import re, sys
kept = []
for path in sys.argv[2:]:
    blocks = re.findall(r"^```sh\n(.*?)^```", open(path).read(), re.S | re.M)
    kept += [b for b in blocks if "scripts/" not in b]
assert len(kept) >= 18, f"{len(kept)} example blocks in the README and docs/"
for n, b in enumerate(kept):
    open(f"{sys.argv[1]}/block{n:02d}.sh", "w").write(b)
PY

count=0
for block in "$work"/block*.sh; do
  count=$((count + 1))
  body=$(sed -e "s#http://127.0.0.1:8080#$base#g" -e "s/\bID\b/$id/g" "$block")
  echo "== README example $count: $(head -1 "$block")"
  # A shell of its own, so that `set -e` holds (it does not in a subshell
  # whose status is tested).
  (cd "$work/run" && PATH="$work/bin:$PATH" SURFDEFORM_SERVER="$base" bash -euo pipefail -c \
    'curl() { command curl -sS --fail-with-body "$@"; }; '"$body") > "$work/out.txt" 2>&1 || {
    cat "$work/out.txt"
    fail "README example $count failed:"$'\n'"$(cat "$block")"
  }
  # Every file written with -o.
  for file in $(grep -oE '(^|\s)-o\s+\S+' "$block" | awk '{print $2}'); do
    [[ -s $work/run/$file ]] || fail "README example $count wrote no $file"
  done
done
((count >= 9)) || fail "only $count README examples ran"

# The README's exit codes: a local file that cannot be read is 4.
set +e
SURFDEFORM_SERVER=$base "$2" deform "$work/no-such-file.ply" --surface-id "$id" -o "$work/x.glb" \
  2> "$work/missing.txt"
code=$?
set -e
((code == 4)) || fail "a missing input file exits $code, not 4: $(cat "$work/missing.txt")"
grep -q "no-such-file.ply" "$work/missing.txt" || fail "the message does not name the file"
echo "README examples: $count blocks as written, and exit code 4 for a missing file"
