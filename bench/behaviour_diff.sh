#!/usr/bin/env bash
# Do two server builds answer alike? Runs bench/behaviour_snapshot.py (about
# 30 fixed requests across every route, output format and error class)
# against each and compares the bodies, ETags and statistics (timings left
# out). A refactoring that claims "behaviour unchanged" shows it with this.
# Usage: behaviour_diff.sh BASE_SERVER NEW_SERVER
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../tests/integration/launch_server.sh"
out=$(mktemp -d)
pids=()
trap 'kill "${pids[@]}" 2> /dev/null || true; rm -rf "$out"' EXIT

snapshot() {
  # A data directory of its own: the default one is shared, and a surface
  # the other build (or an earlier run) kept there answers "cached": true.
  launch_server "$1" "$out/$2.log" --data-dir "$out/$2-data"
  pids+=("$SERVER_PID")
  [[ -n $SERVER_PORT ]] || { echo "$1 did not start: $(cat "$out/$2.log")" >&2; exit 1; }
  python3 "$here/behaviour_snapshot.py" "$SERVER_PORT" "$here/../client/web/samples" > "$out/$2.txt"
  kill "$SERVER_PID"
}
snapshot "$1" base
snapshot "$2" new
echo "$(wc -l < "$out/base.txt") requests"
if diff "$out/base.txt" "$out/new.txt"; then
  echo "identical: every status, body, ETag and statistic"
else
  echo "DIFFERENT (< base, > new)" >&2
  exit 1
fi
