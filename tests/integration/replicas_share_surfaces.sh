#!/usr/bin/env bash
# Surfaces shared across replicas: three surfdeform-server replicas with
# --redis behind Debian's nginx running docker/nginx.conf (addresses only
# changed), and a real redis-server, all on loopback.
# 1. A surface created through nginx is used by id through nginx 50 times
#    (25 routed by X-Surfdeform-Surface-Id, 25 without it): all 200, the same
#    bytes. The routed ones all reach one replica (consistent hashing); the
#    others reach every replica, which read the surface from Redis.
# 2. Redis killed under load: no request fails. Redis back: sharing resumes.
# 3. The replica that holds a surface killed under load: requests by id move
#    to another replica (nginx retries, the hash moves), which reads it from
#    Redis: none fails (a response the kill cut after its header is sent
#    again by the client, as any client of an idempotent route would).
# Usage: replicas_share_surfaces.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
server_bin=$1
command -v redis-server > /dev/null || { echo "FAIL: redis-server is not installed (scripts/setup.sh installs it)" >&2; exit 1; }
out=$(mktemp -d)
pids=()
redis_pid=""
cleanup() {
  for p in "${pids[@]}" $redis_pid; do kill -9 "$p" 2> /dev/null || true; done
  declare -F stop_nginx > /dev/null && stop_nginx "$out"
  wait 2> /dev/null || true  # the killed replicas
  rm -rf "$out"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  for r in 1 2 3; do
    echo "replica $r's log (last lines):" >&2
    tail -n 5 "$out/replica$r.log" >&2 2> /dev/null || true
  done
  tail -n 20 "$out/nginx-error.log" >&2 2> /dev/null || true
  exit 1
}
redis_port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
start_redis() {
  redis-server --port "$redis_port" --bind 127.0.0.1 --save '' --appendonly no \
    --loglevel warning > "$out/redis.log" 2>&1 &
  redis_pid=$!
  disown
  for _ in $(seq 100); do
    [[ $(redis-cli -p "$redis_port" ping 2> /dev/null) == PONG ]] && return 0
    sleep 0.05
  done
  fail "redis-server did not start: $(cat "$out/redis.log")"
}
start_redis

source "$here/launch_server.sh"
ports=()
launch_replicas 3 "$out/replica" --redis "redis://127.0.0.1:$redis_port"
source "$here/nginx_front.sh"
start_nginx "$out" "${ports[@]}"
base=$NGINX_BASE

# A metric's value on replica R (0 when absent).
metric() {
  curl -sf "http://127.0.0.1:${ports[$1]}/metrics" | awk -v m="$2" '$1 == m { v = $2 } END { print v + 0 }'
}
deforms_on() { metric "$1" 'surfdeform_http_requests_total{route="/v1/deform",method="POST",status="200"}'; }
surface() {  # a cylinder sampled n x n: a new surface for each n
  echo "{\"surface\":{\"kind\":\"cylinder\",\"radius\":2,\"height\":3,\"angle_deg\":180},\"sampling\":{\"nu\":$1,\"nv\":$1}}"
}
create() {  # base, n: prints the surface id
  curl -sf -H 'Content-Type: application/json' -d "$(surface "$2")" "$1/v1/surfaces" \
    | python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])'
}
plate="$out/plate.obj"
printf 'v -0.5 -0.25 0\nv 0.5 -0.25 0\nv 0.5 0.25 0\nv -0.5 0.25 0\nf 1 2 3 4\n' > "$plate"
# A response cut after its header (curl's 18, a partial transfer) is sent
# again once when RETRY_CUT is set, as a client behind a load balancer does
# with an idempotent request; each such retry is logged to $out/retried.
post() {  # params, output file, [surface id for the routing header]: prints the status code
  local code routing=() attempt
  [[ -n ${3:-} ]] && routing=(-H "X-Surfdeform-Surface-Id: $3")
  for attempt in 1 2; do
    code=$(curl -s -o "$2" -w '%{http_code}' -X POST -H "Content-Type: model/obj" \
      -H "X-Surfdeform-Params: $1" "${routing[@]}" --data-binary @"$plate" "$base/v1/deform") \
      && break || code="curl-error-$?"
    [[ $code == curl-error-18 && -n ${RETRY_CUT:-} && $attempt == 1 ]] || break
    echo "$code" >> "$out/retried"
  done
  echo "$code"
}

# 1. Flatten once through nginx, deform by id through nginx 50 times.
id=$(create "$base" 16) || fail "POST /v1/surfaces through nginx failed"
by_id="{\"surface_id\":\"$id\",\"placement\":{\"scale\":\"fit\"}}"
[[ $(post "$by_id" "$out/reference.drc" "$id") == 200 ]] || fail "the first deformation by id failed"
before=()
for r in 0 1 2; do before+=("$(deforms_on $r)"); done
codes=()
for k in $(seq 25); do
  codes+=("$(post "$by_id" "$out/d.drc" "$id")")
  cmp -s "$out/d.drc" "$out/reference.drc" || codes+=("different-bytes")
done
served_by=0
for r in 0 1 2; do
  n=$(($(deforms_on $r) - before[r]))
  ((n == 0 || n == 25)) || fail "25 requests routed by surface id were spread: replica $((r + 1)) served $n"
  ((n == 25)) && served_by=$((served_by + 1))
done
((served_by == 1)) || fail "no single replica served the 25 requests routed by surface id"
for k in $(seq 25); do
  codes+=("$(post "$by_id" "$out/d.drc")")  # no routing header: least connections
  cmp -s "$out/d.drc" "$out/reference.drc" || codes+=("different-bytes")
done
bad=$(printf '%s\n' "${codes[@]}" | grep -vc '^200$' || true)
((bad == 0)) || fail "$bad of 50 requests by id failed: $(printf '%s\n' "${codes[@]}" | sort | uniq -c | tr '\n' ' ')"
for r in 0 1 2; do
  [[ $(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:${ports[r]}/v1/surfaces/$id") == 200 ]] \
    || fail "replica $((r + 1)) does not serve surface $id by id"
done
hits=0
for r in 0 1 2; do hits=$((hits + $(metric $r 'surfdeform_l2_lookups_total{result="hit"}'))); done
((hits >= 2)) || fail "the other replicas did not read the surface from Redis ($hits second-level hits)"
echo "shared: 50 deformations by id through nginx all 200 with the same bytes; routed ones on one replica; $hits second-level hits"

# 1b. A model uploaded once through nginx, routed by its id (the first 32 hex
#     digits of its SHA-256), and deformed by id through nginx: routed, the
#     upload and the deformations meet on one replica; unrouted, the other
#     replicas read the model from Redis. Every reply the same bytes as
#     sending the mesh.
model_id=$(sha256sum "$plate" | cut -c1-32)
inline="{\"surface\":{\"kind\":\"cylinder\",\"radius\":2,\"height\":3,\"angle_deg\":180},\"sampling\":{\"nu\":16,\"nv\":16},\"placement\":{\"scale\":\"fit\"}"
[[ $(post "$inline}" "$out/with-mesh.drc") == 200 ]] || fail "the deformation with the mesh failed"
uploads_on() { metric "$1" 'surfdeform_http_requests_total{route="/v1/models",method="POST",status="201"}'; }
code=$(curl -s -o "$out/model.json" -w '%{http_code}' -H "X-Surfdeform-Model-Id: $model_id" \
  -H 'Content-Type: application/octet-stream' --data-binary @"$plate" "$base/v1/models")
[[ $code == 201 ]] || fail "POST /v1/models through nginx: $code $(cat "$out/model.json")"
by_model() {  # output file, [routing header]: prints the status code
  curl -s -o "$1" -w '%{http_code}' -H 'Content-Type: application/json' "${@:2}" \
    -d "$inline,\"model_id\":\"$model_id\"}" "$base/v1/deform"
}
before=()
for r in 0 1 2; do before+=("$(deforms_on $r)"); done
for k in $(seq 10); do
  code=$(by_model "$out/m.drc" -H "X-Surfdeform-Model-Id: $model_id")
  [[ $code == 200 ]] || fail "deformation by model id through nginx: $code $(head -c 300 "$out/m.drc")"
  cmp -s "$out/m.drc" "$out/with-mesh.drc" || fail "a deformation by model id differs from sending the mesh"
done
for r in 0 1 2; do
  n=$(($(deforms_on $r) - before[r]))
  ((n == 0 || n == 10)) || fail "10 requests routed by model id were spread: replica $((r + 1)) served $n"
  ((n == 10)) && (($(uploads_on $r) != 1)) && fail "the routed deformations reached replica $((r + 1)), not the one that took the upload"
done
for k in $(seq 10); do
  code=$(by_model "$out/m.drc")
  [[ $code == 200 ]] || fail "unrouted deformation by model id: $code $(head -c 300 "$out/m.drc")"
  cmp -s "$out/m.drc" "$out/with-mesh.drc" || fail "an unrouted deformation by model id differs"
done
for r in 0 1 2; do
  [[ $(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:${ports[r]}/v1/models/$model_id") == 200 ]] \
    || fail "replica $((r + 1)) does not find model $model_id (Redis)"
done
echo "models: uploaded once through nginx, 20 deformations by id all 200 with the bytes of sending the mesh; routed ones on the upload's replica"

# 2. Redis killed under load (requests by id, routed, and with new inline
#    surfaces), then back.
client() {  # id: 3 s of requests
  local c=$1 end=$((SECONDS + 3)) n=0 inline
  while ((SECONDS < end && n < 3000)); do
    # A new surface each time: every one reads and writes Redis.
    inline="{\"surface\":{\"kind\":\"cylinder\",\"radius\":2,\"height\":3,\"angle_deg\":180},\"sampling\":{\"nu\":$((5 + n % 200)),\"nv\":$((5 + c))}}"
    if ((n % 2)); then post "$by_id" "$out/c$c.drc" "$id"; else post "$inline" "$out/c$c.drc"; fi >> "$out/codes$c"
    n=$((n + 1))
  done
}
run_load() {  # what to do 1 s in
  rm -f "$out"/codes*
  local load=()
  for c in 1 2 3 4; do
    client "$c" &
    load+=($!)
  done
  sleep 1
  "$@"
  for p in "${load[@]}"; do wait "$p" || fail "a load client ended with status $?"; done
  local total ok
  total=$(cat "$out"/codes* | wc -l)
  ok=$(cat "$out"/codes* | grep -c '^200$' || true)
  ((total >= 12)) || fail "only $total requests in 3 s: the load did not run"
  ((ok == total)) || fail "$((total - ok)) of $total requests failed: $(cat "$out"/codes* | sort | uniq -c | tr '\n' ' ')"
  LOAD_TOTAL=$total
}
kill_redis() { kill -9 "$redis_pid"; }
run_load kill_redis
echo "Redis killed under load: $LOAD_TOTAL requests, all 200"
grep -q '"state":"down"' "$out"/replica*.log || fail "no replica logged the shared tier going down"
start_redis
# Sharing resumes once each replica's breaker lets a probe through (5 s).
resumed=0
for n in $(seq 20 40); do
  new_id=$(create "http://127.0.0.1:${ports[0]}" "$n") || fail "replica 1 failed to flatten"
  if [[ $(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:${ports[1]}/v1/surfaces/$new_id") == 200 ]]; then
    resumed=1
    break
  fi
  sleep 0.5
done
((resumed)) || fail "after Redis came back, replica 2 never found a surface replica 1 flattened"
echo "Redis back: a surface flattened on replica 1 is served by id on replica 2"

# 3. Kill the replica that serves this surface's routed requests. nginx sends
#    again any request the dead replica had not begun to answer. What no proxy
#    can hide is a kill between a response's header and its body, which
#    cpp-httplib sends in two writes (nginx has passed the header on): the
#    first write wakes nginx, and the replica preempted there widens that gap
#    from microseconds to a time slice, so it is hit in about one run in four.
#    The client sends that request again, at most once per client (one
#    connection each).
owner=-1
for r in 0 1 2; do
  b=$(deforms_on $r)
  post "$by_id" "$out/d.drc" "$id" > /dev/null
  (($(deforms_on $r) > b)) && owner=$r && break
done
((owner >= 0)) || fail "cannot tell which replica serves surface $id"
kill_owner() { kill -9 "${pids[owner]}"; }
rm -f "$out/retried"
RETRY_CUT=1 run_load kill_owner
retried=0
[[ -f $out/retried ]] && retried=$(wc -l < "$out/retried")
((retried <= 4)) || fail "$retried responses were cut, more than the 4 clients had in flight at the kill"
echo "the replica holding surface $id killed under load: $LOAD_TOTAL requests, all 200 ($retried cut at the kill and sent again)"
echo "replicas share surfaces: ok"
