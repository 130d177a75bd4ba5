#!/usr/bin/env bash
# Load-tests surfdeform with wrk (tests/load/*.lua) and prints one table.
#   scripts/loadtest.sh [URL]
# Without a URL it builds (Release) and starts a server of its own on a free
# loopback port. It creates the Figure 10 surface, then deforms a mesh by its
# id at 1, 2, 3, 4, 6, 8, ... connections until goodput (200s per second)
# stops rising: the best step is the capacity. Then it runs at 4x those
# connections, and at least 4 past the server's slots and queue places so
# that it must refuse some (overload), then at the capacity's connections once more, and
# prints, per step: requests per second, goodput,
# p50 / p90 / p99 of the served requests, the status codes, the server's
# CPU time per served request (from /metrics: process_cpu_seconds_total),
# and what refusals cost: the worker CPU time per refused request against
# a served one, and the share of the server's CPU not spent on served
# requests (surfdeform_http_request_cpu_seconds, per worker thread, against
# process_cpu_seconds_total: other tenants of the machine slow both alike,
# so the ratios hold where goodput does not).
#
# Environment:
#   LOADTEST_FORM         the request form, which sets the script:
#                         inline_draco (the default: deform_by_id, the raw
#                         mesh each time, Draco out), id_draco (the model
#                         uploaded once and named by model_id, Draco out),
#                         id_meshopt (by id, GLB with meshopt), repeated
#                         (id_meshopt against a server that keeps answers:
#                         the same request answered from them); or all:
#                         each form in turn, then one table of their
#                         capacities, CPU and bytes per request and the
#                         ratios to inline_draco. A server this script starts
#                         keeps no answers (--answer-cache-mib 0) but for
#                         repeated, so that identical requests measure the
#                         work; give a URL's server that flag likewise.
#   LOADTEST_SCRIPT       deform_by_id (default), deform_multipart, deform_inline,
#                         deform_model_id (without LOADTEST_FORM)
#   LOADTEST_MESH         the mesh (default client/web/samples/bunny.ply)
#   LOADTEST_SUBDIVISION  off (default), adaptive, uniform
#   LOADTEST_SECONDS      seconds per step (default 5)
#   LOADTEST_MAX_CONNECTIONS  the last step tried (default 64)
#   LOADTEST_OVERLOAD_CONNECTIONS  the overload step's connections (default
#                         4x the capacity's, at least slots + queue + 4)
#   LOADTEST_FAULT        sent as X-Surfdeform-Fault (surfdeform-server-faults
#                         only: shedding_off proves that the check fails)
#   LOADTEST_CHECK=1      exit 1 unless: no code but 200 and 503, every 503
#                         has Retry-After, no socket error; at overload, past
#                         the server's slots and queue (/v1/info), requests
#                         were refused, a refusal cost at most
#                         LOADTEST_MAX_REFUSAL_COST (default 0.1) of a served
#                         request's worker CPU, and at most
#                         LOADTEST_MAX_REFUSAL_SHARE (default 0.08) of the
#                         server's CPU went to anything but the served
#                         requests (refusals, the gate, the kernel's part of
#                         the connections); and, only where
#                         LOADTEST_MIN_OVERLOAD is set (say 0.8), goodput at
#                         overload at least that share of the capacity
#                         measured in the same run (the mean of the capacity
#                         step and its rerun after the overload): goodput
#                         moves with the machine's other tenants, so CI
#                         reports it and does not check it
#   LOADTEST_JSON=FILE    also write the steps as JSON
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
form=${LOADTEST_FORM:-}
if [[ $form == all ]]; then
  forms_dir=$(mktemp -d)
  trap 'rm -rf "$forms_dir"' EXIT
  for f in inline_draco id_draco id_meshopt repeated; do
    echo "== $f"
    LOADTEST_FORM=$f LOADTEST_JSON="$forms_dir/$f.json" LOADTEST_CHECK=0 "$0" "$@"
  done
  python3 - "$forms_dir" << 'PY'
import json, os, sys
rows = []
for f in ("inline_draco", "id_draco", "id_meshopt", "repeated"):
    r = json.load(open(os.path.join(sys.argv[1], f + ".json")))
    best = max(r["steps"][:-2], key=lambda w: w["codes"].get("200", 0) / w["duration_s"])
    served = best["codes"].get("200", 0)
    rows.append((f, r["capacity"], best["connections"], 1000 * best["server_cpu_s"] / served,
                 best["bytes"] / max(best["requests"], 1), best["served_ms"]["p50"]))
base = rows[0]
print(f"\n{'form':<13} {'capacity':>9} {'conns':>5} {'CPU ms/req':>10} {'bytes/resp':>10} {'p50 ms':>8}"
      f" | {'capacity':>8} {'CPU':>6} {'bytes':>6}  (to inline_draco)")
for f, cap, conns, cpu, size, p50 in rows:
    print(f"{f:<13} {cap:>9.1f} {conns:>5} {cpu:>10.2f} {size:>10.0f} {p50:>8.1f}"
          f" | {cap / base[1]:>7.2f}x {cpu / base[3]:>5.2f}x {size / base[4]:>5.2f}x")
PY
  exit 0
fi
case $form in
  "" | inline_draco) script=${LOADTEST_SCRIPT:-deform_by_id} ;;
  id_draco | id_meshopt | repeated) script=deform_model_id ;;
  *) echo "loadtest: LOADTEST_FORM is inline_draco, id_draco, id_meshopt, repeated or all" >&2; exit 2 ;;
esac
# Kept answers would serve identical requests without work: only the
# repeated form measures them.
keep_answers=()
[[ $form == repeated ]] || keep_answers=(--answer-cache-mib 0)
mesh=${LOADTEST_MESH:-$root/client/web/samples/bunny.ply}
subdivision=${LOADTEST_SUBDIVISION:-off}
seconds=${LOADTEST_SECONDS:-5}
max_connections=${LOADTEST_MAX_CONNECTIONS:-64}
min_overload=${LOADTEST_MIN_OVERLOAD:-}
max_refusal_cost=${LOADTEST_MAX_REFUSAL_COST:-0.1}
max_refusal_share=${LOADTEST_MAX_REFUSAL_SHARE:-0.08}
command -v wrk > /dev/null || { echo "loadtest: wrk is not installed (scripts/setup.sh installs it)" >&2; exit 2; }
[[ -f $mesh ]] || { echo "loadtest: no mesh at $mesh (set LOADTEST_MESH)" >&2; exit 2; }
[[ -f $root/tests/load/$script.lua ]] || { echo "loadtest: no script tests/load/$script.lua" >&2; exit 2; }
work=$(mktemp -d)
server_pid=""
cleanup() {
  [[ -n $server_pid ]] && kill "$server_pid" 2> /dev/null && wait "$server_pid" 2> /dev/null
  rm -rf "$work"
}
trap cleanup EXIT

url=${1:-}
if [[ -z $url ]]; then
  bin=${SURFDEFORM_SERVER:-$root/build/server/surfdeform-server}
  if [[ ! -x $bin ]]; then
    cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
    cmake --build "$root/build" --target surfdeform-server > /dev/null
  fi
  "$bin" --host 127.0.0.1 --port 0 --log-level warn "${keep_answers[@]}" > "$work/server.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 200); do
    grep -q '"listening"' "$work/server.log" 2> /dev/null && break
    sleep 0.05
  done
  port=$(sed -n 's/.*"port":\([0-9]*\).*/\1/p' "$work/server.log" | head -1)
  [[ -n $port ]] || { echo "loadtest: the server did not start: $(cat "$work/server.log")" >&2; exit 2; }
  url="http://127.0.0.1:$port"
fi
url=${url%/}

python3 - "$root/client/web/samples/figure10.json" > "$work/surface.json" << 'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s.pop("description", None)
print(json.dumps({"surface": s, "sampling": {"nu": 32, "nv": 32}}, separators=(",", ":")))
PY
id=$(curl -sf -H 'Content-Type: application/json' --data-binary @"$work/surface.json" "$url/v1/surfaces" \
  | python3 -c 'import json, sys; print(json.load(sys.stdin)["id"])') \
  || { echo "loadtest: POST /v1/surfaces to $url failed" >&2; exit 2; }
case $script in
  deform_inline) args=("$work/surface.json" "$mesh" "$subdivision") ;;
  deform_model_id)
    model=$(curl -sf --data-binary @"$mesh" -H 'Content-Type: application/octet-stream' "$url/v1/models" \
      | python3 -c 'import json, sys; print(json.load(sys.stdin)["id"])') \
      || { echo "loadtest: POST /v1/models to $url failed" >&2; exit 2; }
    compression=draco
    [[ $form == id_meshopt || $form == repeated ]] && compression=meshopt
    args=("$id" "$model" "$subdivision" "$compression")
    ;;
  *) args=("$id" "$mesh" "$subdivision") ;;
esac
# Requests that can run or wait at once: past them, requests are refused.
room=$(curl -sf "$url/v1/info" | python3 -c '
import json, sys
l = json.load(sys.stdin)["limits"]
print(l["max_in_flight"] + l["max_queued"])')
export LOADTEST_FAULT=${LOADTEST_FAULT:-}

metric() { curl -sf "$url/metrics" | awk -v m="$1" '$1 == m { v = $2 } END { print v + 0 }'; }
# The metrics a step reads before and after it, as "name value" lines.
counters() {
  curl -sf "$url/metrics" | awk '$1 == "process_cpu_seconds_total" ||
    $1 ~ /^surfdeform_http_request_cpu_seconds_(sum|count)\{outcome="(served|refused)"\}$/'
}
# Requests of a previous step that the server is still finishing would be
# counted in this one: wait until only the /metrics request is in flight.
settle() {
  for _ in $(seq 100); do
    (($(metric surfdeform_http_requests_in_flight | cut -d. -f1) <= 1)) && return 0
    sleep 0.1
  done
}
step() {  # connections: appends one JSON line to $work/steps
  local c=$1 out
  settle
  counters > "$work/before"
  out=$(wrk -t"$c" -c"$c" -d"${seconds}s" --timeout 30s -s "$root/tests/load/$script.lua" "$url" -- "${args[@]}" \
    | grep '^{"wrk"') || { echo "loadtest: wrk failed at $c connections" >&2; exit 2; }
  settle  # the step's last requests are counted once they are answered
  counters > "$work/after"
  python3 -c '
import json, sys
def read(path):
    return {name: float(v) for name, v in (line.split() for line in open(path))}
w = json.loads(sys.argv[1])["wrk"]
w["connections"] = int(sys.argv[2])
before, after = read(sys.argv[3]), read(sys.argv[4])
delta = lambda name: after.get(name, 0.0) - before.get(name, 0.0)
w["server_cpu_s"] = delta("process_cpu_seconds_total")
for outcome in ("served", "refused"):
    w[outcome + "_worker_cpu_s"] = delta(f"surfdeform_http_request_cpu_seconds_sum{{outcome=\"{outcome}\"}}")
    w[outcome + "_counted"] = round(delta(f"surfdeform_http_request_cpu_seconds_count{{outcome=\"{outcome}\"}}"))
print(json.dumps(w))' "$out" "$c" "$work/before" "$work/after" >> "$work/steps"
}
goodput_of_last() { tail -1 "$work/steps" | python3 -c 'import json, sys; w = json.load(sys.stdin); print(w["codes"].get("200", 0) / w["duration_s"])'; }

echo "loadtest: $url, ${form:-} tests/load/$script.lua, $(basename "$mesh"), subdivision $subdivision, ${seconds} s per step"
best=0 best_c=0 flat=0
for c in 1 2 3 4 6 8 12 16 24 32 48 64 96 128; do
  ((c > max_connections)) && break
  step "$c"
  g=$(goodput_of_last)
  if python3 -c "import sys; sys.exit(0 if $g > $best * 1.03 else 1)"; then
    best=$g best_c=$c flat=0
  else
    flat=$((flat + 1))
    ((flat >= 2)) && break  # two steps without a 3% gain: past capacity
  fi
done
overload_c=${LOADTEST_OVERLOAD_CONNECTIONS:-$((4 * best_c > room + 4 ? 4 * best_c : room + 4))}
step "$overload_c"
# The capacity step once more, right after the overload: on a shared machine
# the cores' speed drifts by tens of percent within a minute, and the check
# compares the overload with the capacity around it (the mean of the two).
step "$best_c"

python3 - "$work/steps" "$best_c" "$overload_c" "${LOADTEST_CHECK:-0}" "$min_overload" "${LOADTEST_JSON:-}" \
  "$room" "$max_refusal_cost" "$max_refusal_share" << 'PY'
import json, sys
steps = [json.loads(l) for l in open(sys.argv[1])]
best_c, overload_c, check, json_out = int(sys.argv[2]), int(sys.argv[3]), sys.argv[4] == "1", sys.argv[6]
min_overload = float(sys.argv[5]) if sys.argv[5] else None
room, max_refusal_cost, max_refusal_share = int(sys.argv[7]), float(sys.argv[8]), float(sys.argv[9])

def refusal_cost(w):
    """Worker CPU per refused request over that per served one (None without both), and the
    share of the server's CPU not spent on served requests."""
    served, refused = w["served_worker_cpu_s"], w["refused_worker_cpu_s"]
    share = 1 - served / w["server_cpu_s"] if w["server_cpu_s"] > 0 else None
    if not w["refused_counted"] or not w["served_counted"] or served <= 0:
        return None, share
    return (refused / w["refused_counted"]) / (served / w["served_counted"]), share

print(f"{'conns':>5} {'req/s':>8} {'goodput':>8} {'p50 ms':>8} {'p90 ms':>8} {'p99 ms':>8} {'p99/p50':>7} {'CPU ms/req':>10}"
      f" {'refusal/served':>14} {'not serving':>11}  codes")
for w in steps:
    served = w["codes"].get("200", 0)
    rps = w["requests"] / w["duration_s"]
    good = served / w["duration_s"]
    s = w["served_ms"]
    ratio = s["p99"] / s["p50"] if s["p50"] else 0
    cpu = 1000 * w["server_cpu_s"] / served if served else float("nan")
    per, share = refusal_cost(w)
    per_text = f"{per:14.3f}" if per is not None else f"{'-':>14}"
    share_text = f"{100 * share:10.1f}%" if share is not None else f"{'-':>11}"
    codes = " ".join(f"{k}:{v}" for k, v in sorted(w["codes"].items()))
    errors = sum(w["socket_errors"].values())
    tag = (" (capacity again)" if w is steps[-1] else " (overload)" if w is steps[-2]
           else " (capacity)" if w["connections"] == best_c else "")
    print(f"{w['connections']:>5} {rps:>8.1f} {good:>8.1f} {s['p50']:>8.1f} {s['p90']:>8.1f} {s['p99']:>8.1f} {ratio:>7.2f} {cpu:>10.1f}"
          f" {per_text} {share_text}  {codes}" + (f" socket-errors:{errors}" if errors else "") + tag)
capacity = max(w["codes"].get("200", 0) / w["duration_s"] for w in steps[:-2])
again = steps[-1]["codes"].get("200", 0) / steps[-1]["duration_s"]
around = (capacity + again) / 2  # the capacity before and after the overload step
over = steps[-2]
over_good = over["codes"].get("200", 0) / over["duration_s"]
over_per, over_share = refusal_cost(over)
print(f"capacity {capacity:.1f} req/s at {best_c} connections ({again:.1f} again after the overload, "
      f"mean {around:.1f}); at {overload_c} connections goodput {over_good:.1f} req/s "
      f"({100 * over_good / around:.0f}% of that mean), served p99/p50 "
      f"{over['served_ms']['p99'] / max(over['served_ms']['p50'], 1e-9):.2f}")
if over_per is not None:
    print(f"at overload: {over['refused_counted']} refused, each {over_per:.3f} of a served request's worker CPU; "
          f"{100 * over_share:.1f}% of the server's CPU went to anything but the served requests")
if json_out:
    json.dump({"steps": steps, "capacity": capacity, "capacity_again": again, "capacity_connections": best_c,
               "overload_connections": overload_c, "overload_goodput": over_good,
               "overload_refusal_cost": over_per, "overload_refusal_share": over_share},
              open(json_out, "w"), indent=1)
if check:
    problems = []
    for w in steps:
        other = {k: v for k, v in w["codes"].items() if k not in ("200", "503")}
        if other: problems.append(f"{w['connections']} connections: codes other than 200 and 503: {other}")
        if w["retry_after_missing"]: problems.append(f"{w['connections']} connections: {w['retry_after_missing']} 503s without Retry-After")
        if sum(w["socket_errors"].values()): problems.append(f"{w['connections']} connections: socket errors {w['socket_errors']}")
    if overload_c > room and not over["refused_counted"]:
        problems.append(f"{overload_c} connections against {room} slots and queue places: no request was refused")
    if over_per is not None and over_per > max_refusal_cost:
        problems.append(f"a refusal cost {over_per:.3f} of a served request's worker CPU (at most {max_refusal_cost})")
    if over_share is not None and over_share > max_refusal_share:
        problems.append(f"{100 * over_share:.1f}% of the server's CPU went to anything but the served requests at overload "
                        f"({over['refused_counted']} refused, {over['served_counted']} served; at most {100 * max_refusal_share:.0f}%)")
    if min_overload is not None and over_good < min_overload * around:
        problems.append(f"goodput at overload {over_good:.1f} req/s is under {min_overload:.0%} of capacity {around:.1f} req/s "
                        f"(the mean of {capacity:.1f} before and {again:.1f} after)")
    for p in problems: print("FAIL: " + p)
    sys.exit(1 if problems else 0)
PY
