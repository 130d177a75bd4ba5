# Sourced by the integration scripts. launch_server BINARY LOG [FLAGS...]
# starts surfdeform-server on a free loopback port in the background (log
# level warn, output to LOG), waits until it says it is listening, and sets
# SERVER_PID and SERVER_PORT (empty if it did not start within 10 s).
launch_server() {
  local bin=$1 log=$2
  shift 2
  "$bin" --host 127.0.0.1 --port 0 --log-level warn "$@" > "$log" &
  SERVER_PID=$!
  for _ in $(seq 200); do
    grep -q '"listening"' "$log" 2> /dev/null && break
    sleep 0.05
  done
  SERVER_PORT=$(sed -n 's/.*"port":\([0-9]*\).*/\1/p' "$log" | head -1)
}

# launch_replicas N LOG_PREFIX [FLAGS...]: N servers as above (logs
# LOG_PREFIX1.log ...), appended to the arrays pids and ports; fails the test
# (fail from the caller) if one does not start.
launch_replicas() {
  local n=$1 prefix=$2
  shift 2
  for r in $(seq "$n"); do
    launch_server "$server_bin" "$prefix$r.log" "$@"
    pids+=("$SERVER_PID")
    disown
    ports+=("$SERVER_PORT")
    [[ -n $SERVER_PORT ]] || fail "replica $r did not start: $(cat "$prefix$r.log")"
  done
}

# serve_for_test BINARY [FLAGS...]: the frame of a script that tests one
# server: a scratch directory $out (removed on exit, with the server killed
# if still running), the server started there (launch_server), $base its
# URL, and fail MESSAGE (unless the script has its own). stop_served_server
# then asks the server to stop with SIGTERM and fails unless it exits 0.
serve_for_test() {
  out=$(mktemp -d)
  server_pid=
  trap 'if [[ -n $server_pid ]]; then kill -9 "$server_pid" 2> /dev/null || true; fi; rm -rf "$out"' EXIT
  launch_server "$1" "$out/server.log" "${@:2}"
  server_pid=$SERVER_PID
  base="http://127.0.0.1:$SERVER_PORT"
}
declare -F fail > /dev/null || fail() { echo "FAIL: $*" >&2; exit 1; }
stop_served_server() {
  kill -TERM "$server_pid"
  wait "$server_pid" || fail "the server did not exit 0 on SIGTERM"
  server_pid=
}
