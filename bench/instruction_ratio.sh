#!/usr/bin/env bash
# Instructions per bunny request, counted by valgrind's callgrind: the
# server's, those inside Draco's encoder (draco::Encoder::EncodeMeshToBuffer,
# inclusive), and their ratio; the same for bench/draco_only_server (the
# ceiling of capacity_bench: reads the body and encodes the same output).
#
# The counts do not depend on the machine's load, which makes them the
# noise-free companion of capacity_bench's CPU-time ratios (whose
# targets are 1.25x with subdivision off and 1.35x adaptive, in CPU time).
# They are user-space instructions only: the kernel's share (socket
# copies) is not in them, and an instruction is not a cycle (Draco's
# encoder waits on memory more than the deformation does).
#
# Usage: bench/instruction_ratio.sh [BUILD_DIR (build)] [REQUESTS (3)]
# Needs a Release build with -DSURFDEFORM_BUILD_BENCH=ON and valgrind
# (scripts/setup.sh installs it). Takes about a minute.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
requests=${2:-3}
server=$build/server/surfdeform-server
ceiling=$build/bench/draco_only_server
bunny=../shared/data/bunny.ply
for need in valgrind callgrind_control callgrind_annotate curl python3; do
  command -v "$need" > /dev/null || {
    echo "instruction_ratio: needs $need (scripts/setup.sh installs it)" >&2
    exit 1
  }
done
for f in "$server" "$ceiling" "$bunny"; do
  [[ -e $f ]] || {
    echo "instruction_ratio: $f is missing (a Release build with -DSURFDEFORM_BUILD_BENCH=ON)" >&2
    exit 1
  }
done

work=$(mktemp -d)
pid=
cleanup() {
  [[ -n $pid ]] && kill "$pid" 2> /dev/null && wait "$pid" 2> /dev/null
  rm -rf "$work"
}
trap cleanup EXIT

# start NAME BINARY ARGS...: runs the binary under callgrind, instrumentation
# off, and sets $pid and $port from the {"port":N} it prints first.
start() {
  local name=$1
  shift
  valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file="$work/$name.%p" \
    "$@" > "$work/$name.out" 2> "$work/$name.err" &
  pid=$!
  port=
  for _ in $(seq 300); do
    port=$(sed -n 's/.*"port":\([0-9]*\).*/\1/p' "$work/$name.out" | head -1)
    [[ -n $port ]] && curl -s -o /dev/null "http://127.0.0.1:$port/" && return 0
    sleep 0.2
  done
  echo "instruction_ratio: $1 did not start under valgrind:" >&2
  cat "$work/$name.err" >&2
  exit 1
}

# measure NAME ARGS...: runs `post ARGS...` twice (warm: caches, memo,
# arenas), then REQUESTS times with instrumentation on; prints the program's
# instructions and those inside Draco's encoder, per request.
measure() {
  local name=$1
  shift
  post "$@"
  post "$@"
  callgrind_control -i on "$pid" > /dev/null 2>&1
  for _ in $(seq "$requests"); do post "$@"; done
  callgrind_control -i off "$pid" > /dev/null 2>&1
  callgrind_control -d "$pid" > /dev/null 2>&1
  kill "$pid"
  wait "$pid" 2> /dev/null || true
  pid=
  local dump
  dump=$(ls "$work/$name".*.1 2> /dev/null | head -1)
  [[ -n $dump ]] || dump=$(ls "$work/$name".* | grep -v '\.out$\|\.err$' | tail -1)
  callgrind_annotate --inclusive=yes --threshold=100 "$dump" 2> /dev/null | python3 -c '
import re, sys
total = encode = 0
for line in sys.stdin:
    m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)", line)
    if not m:
        continue
    n = int(m.group(1).replace(",", ""))
    if "PROGRAM TOTALS" in m.group(2):
        total = n
    elif "draco::Encoder::EncodeMeshToBuffer(" in m.group(2):
        encode = max(encode, n)
if not total or not encode:
    sys.exit("instruction_ratio: no counts in the dump")
r = int(sys.argv[1])
print(total / r, encode / r)
' "$requests"
}

post_deform() {  # post_deform PARAMS OUTFILE
  curl -sf -o "$2" -H "X-Surfdeform-Params: $1" -H 'Content-Type: application/octet-stream' \
    --data-binary @"$bunny" "http://127.0.0.1:$port/v1/deform"
}

surface=$(python3 -c '
import json
s = json.load(open("client/web/samples/figure10.json"))
s.pop("description", None)
print(json.dumps({"surface": s, "sampling": {"nu": 16, "nv": 16}}))')

printf 'bunny (%s) on the cached Figure 10 surface (16x16), Draco out; %d requests counted\n' \
  "$(stat -c %s "$bunny") bytes" "$requests"
printf '%-9s | %-15s %-15s %-9s | %-15s %-15s %-9s | %s\n' mode "server Ir/req" "in Draco" ratio \
  "ceiling Ir/req" "in Draco" ratio "server/ceiling"
for mode in off adaptive; do
  # No kept answers: every request does its work.
  start server "$server" --host 127.0.0.1 --port 0 --log-level off --answer-cache-mib 0
  id=$(curl -sf -H 'Content-Type: application/json' --data-binary "$surface" \
    "http://127.0.0.1:$port/v1/surfaces" | python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])')
  params="{\"surface_id\":\"$id\",\"placement\":{\"scale\":\"fit\",\"anchor\":\"center\"},\"subdivision\":{\"mode\":\"$mode\"}"
  post_deform "$params,\"output\":{\"format\":\"ply\"}}" "$work/out.ply"
  post() { post_deform "$params}" /dev/null; }
  read -r s_total s_encode < <(measure server)

  start ceiling "$ceiling" --ply "$work/out.ply"
  post() { post_deform "{}" /dev/null; }
  read -r c_total c_encode < <(measure ceiling)
  rm -f "$work"/server.* "$work"/ceiling.*

  python3 -c '
import sys
mode, st, se, ct, ce = sys.argv[1], *map(float, sys.argv[2:])
m = lambda x: "%.1fM" % (x / 1e6)
print("%-9s | %-15s %-15s %-9s | %-15s %-15s %-9s | %.2fx" % (
    mode, m(st), m(se), "%.2fx" % (st / se), m(ct), m(ce), "%.2fx" % (ct / ce), st / ct))
' "$mode" "$s_total" "$s_encode" "$c_total" "$c_encode"
done
echo "ratio: all instructions per request / those inside draco::Encoder::EncodeMeshToBuffer"
echo "(user space; each server warmed with two requests first)."
