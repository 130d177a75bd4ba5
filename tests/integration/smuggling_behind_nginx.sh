#!/usr/bin/env bash
# Checklist 32: a body on a method that takes none is never read as the next
# request, behind nginx running docker/nginx.conf (keep-alive connections to
# the replica, shared by its clients). Client A sends GET /healthz whose body
# is a whole POST /v1/surfaces; client B then asks GET /v1/info on the same
# upstream connection. B must get /v1/info's own answer (before: A's 201,
# nginx logging "upstream sent more data than specified"), and A a 400 (or
# nginx's own refusal), never a 201; no surface is made.
# Usage: smuggling_behind_nginx.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
server_bin=$1
out=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -9 "$p" 2> /dev/null || true; done
  declare -F stop_nginx > /dev/null && stop_nginx "$out"
  wait 2> /dev/null || true
  rm -rf "$out"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  tail -n 20 "$out/nginx-error.log" >&2 2> /dev/null || true
  exit 1
}
source "$here/launch_server.sh"
ports=()
launch_replicas 1 "$out/replica"
source "$here/nginx_front.sh"
start_nginx "$out" "${ports[@]}"
nginx_port=${NGINX_BASE##*:}

body='{"surface":{"kind":"cylinder","radius":7,"height":1}}'
smuggled=$(printf 'POST /v1/surfaces HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: %d\r\n\r\n%s' "${#body}" "$body")
attack() {  # client A, its own connection to nginx: the status line it got
  exec 3<> "/dev/tcp/127.0.0.1/$nginx_port"
  printf 'GET /healthz HTTP/1.1\r\nHost: x\r\nContent-Length: %d\r\nConnection: close\r\n\r\n%s' \
    "${#smuggled}" "$smuggled" >&3
  timeout 10 cat <&3 | head -1 | tr -d '\r'
  exec 3<&-
}
for round in 1 2 3; do
  a=$(attack)
  [[ $a != *201* ]] || fail "round $round: the smuggled POST was answered to its sender: $a"
  # Client B, right after, on whatever upstream connection nginx keeps.
  b=$(curl -s -w '\n%{http_code}' "$NGINX_BASE/v1/info")
  [[ ${b##*$'\n'} == 200 && $b == *'"limits"'* ]] ||
    fail "round $round: client B did not get its own /v1/info: ${b:0:300}"
  [[ $b != *'"id"'* ]] || fail "round $round: client B got a surface's reply: ${b:0:300}"
done
# Nothing was flattened: the replica never read the smuggled request.
made=$(curl -s "http://127.0.0.1:${ports[0]}/metrics" |
  sed -n 's/^surfdeform_cache_misses_total \([0-9]*\).*/\1/p')
[[ ${made:-0} == 0 ]] || fail "the replica flattened $made surfaces: the smuggled request was served"
! grep -q "upstream sent more data than specified" "$out/nginx-error.log" ||
  fail "nginx saw a response it did not ask for"
echo "smuggling behind nginx: every client got its own answer"
