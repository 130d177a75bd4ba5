#!/usr/bin/env bash
# Checklist 25: replicas go away behind nginx under load, and no client
# request fails. Three surfdeform-server replicas on loopback behind Debian's
# nginx running docker/nginx.conf, the shipped configuration, with only its
# addresses changed (Docker's DNS name becomes the three loopback ports).
# 1. Four clients send deformations for a bounded time; a second in, one
#    replica is stopped as an orchestrator stops it (SIGTERM: it stops
#    accepting and finishes what it has).
# 2. Four slower requests go out at once (two per surviving replica) and the
#    replica serving two of them crashes while it computes them (SIGKILL);
#    nginx must send them again to the other one.
# Every response must be 200 with the expected bytes. What no proxy can hide,
# and this test does not claim: a crash in the microseconds between a
# response's header and its body (nginx has already passed the header on).
# Usage: replica_failover.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
server_bin=$1
out=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -9 "$p" 2> /dev/null || true; done
  declare -F stop_nginx > /dev/null && stop_nginx "$out"
  wait 2> /dev/null || true  # the killed replicas
  rm -rf "$out"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  echo "nginx's error log (last lines):" >&2
  tail -n 20 "$out/nginx-error.log" >&2 2> /dev/null || true
  exit 1
}

# Three replicas; each prints its port once listening.
source "$here/launch_server.sh"
ports=()
# No kept answers: the replicas must be working when one is stopped or killed.
launch_replicas 3 "$out/replica" --answer-cache-mib 0

# docker/nginx.conf with loopback addresses and this run's temporary paths.
source "$here/nginx_front.sh"
start_nginx "$out" "${ports[@]}"
base=$NGINX_BASE

# The paper's thin plate on an inline cylinder, subdivided to a fine
# tolerance: ~40 ms of work each, so that every replica, the one stopped too,
# is in the middle of a request most of the time (a request nginx has already
# sent is retried only because deformation is idempotent: non_idempotent in
# proxy_next_upstream).
plate="$out/plate.obj"
python3 - "$plate" << 'EOF'
import sys
with open(sys.argv[1], "w") as f:
    for k in range(8):
        f.write("v %g %g %g\n" % (0.5 if k & 1 else -0.5, 0.25 if k & 2 else -0.25, 0.025 if k & 4 else -0.025))
    f.write("f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n")
EOF
params='{"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},"sampling":{"nu":16,"nv":16},"placement":{"scale":"fit"},"subdivision":{"tolerance":3e-4}}'
slow_params=${params/3e-4/1e-4}  # ~4x the work
post() {  # params, output file: prints the status code, or curl's error
  local code
  code=$(curl -s -o "$2" -w '%{http_code}' -X POST -H "Content-Type: model/obj" \
    -H "X-Surfdeform-Params: $1" --data-binary @"$plate" "$base/v1/deform") || code="curl-error-$?"
  echo "$code"
}
[[ $(post "$params" "$out/reference.drc") == 200 ]] || fail "the first request through nginx failed"
[[ $(post "$slow_params" "$out/slow-reference.drc") == 200 ]] || fail "the slow request failed"

# Four clients, each for 3 s (at most 3000 requests); replica 2 is stopped at 1 s.
client() {
  local id=$1 end=$((SECONDS + 3)) n=0
  while ((SECONDS < end && n < 3000)); do
    post "$params" "$out/c$id.drc" >> "$out/codes$id"
    cmp -s "$out/c$id.drc" "$out/reference.drc" || echo "different bytes" >> "$out/codes$id"
    n=$((n + 1))
  done
}
load=()
for c in 1 2 3 4; do
  client "$c" &
  load+=($!)
done
sleep 1
# A replica's own count of the requests it is running (its /metrics).
running_on() {
  curl -s "http://127.0.0.1:$1/metrics" | awk '$1 == "surfdeform_admission_running" { print $2 }'
}
# Stopped while it serves: a bounded wait until it has a request in flight,
# then the stop at once (the count that let the loop end is the one reported:
# a second read could land between two requests and see none).
stopped_in_flight=0
for _ in $(seq 200); do
  stopped_in_flight=$(running_on "${ports[1]}")
  ((${stopped_in_flight:-0} >= 1)) && break
  sleep 0.01
done
kill -TERM "${pids[1]}"
for p in "${load[@]}"; do wait "$p" || fail "a load client ended with status $?"; done

total=$(cat "$out"/codes* | wc -l)
ok=$(cat "$out"/codes* | grep -c '^200$' || true)
echo "under load: $total requests, $ok answered 200 (replica on port ${ports[1]} stopped at 1 s with $stopped_in_flight in flight)"
# At least a request per client (the sanitized build is some ten times slower).
((total >= 4)) || fail "only $total requests in 3 s: the load did not run"
((${stopped_in_flight:-0} >= 1)) || fail "the stopped replica had no request in flight when stopped"
((ok == total)) || fail "$((total - ok)) of $total requests failed: $(cat "$out"/codes* | sort | uniq -c | tr '\n' ' ')"
for _ in $(seq 100); do
  kill -0 "${pids[1]}" 2> /dev/null || break
  sleep 0.05
done
if kill -0 "${pids[1]}" 2> /dev/null; then fail "the stopped replica did not exit"; fi

# In flight: nginx (one worker, least connections) gives two of four concurrent
# slow requests to each surviving replica; the third replica crashes while it
# computes its two, which nginx must send again to the first.
rm -f "$out"/codes*
for c in 1 2 3 4; do
  post "$slow_params" "$out/s$c.drc" > "$out/codes$c" &
  load[c]=$!
done
# The crashing replica's own count says its requests are in flight when the
# kill comes (a bounded wait for them to arrive).
in_flight=0
for _ in $(seq 100); do
  in_flight=$(running_on "${ports[2]}")
  ((${in_flight:-0} >= 1)) && break
  sleep 0.02
done
[[ ${in_flight:-0} -ge 1 ]] || fail "no request was in flight on the replica about to crash"
kill -9 "${pids[2]}"
for c in 1 2 3 4; do wait "${load[c]}" || fail "slow request $c: its client ended with status $?"; done
for c in 1 2 3 4; do
  [[ $(cat "$out/codes$c") == 200 ]] || fail "slow request $c: $(cat "$out/codes$c") after its replica died"
  cmp -s "$out/s$c.drc" "$out/slow-reference.drc" || fail "slow request $c: different bytes"
done
curl -sf -o /dev/null "$base/healthz" || fail "nginx stopped answering"
echo "replica failover: $total requests with a replica stopped under load, and 4 in flight ($in_flight on the crashing one when killed): none failed"
