# Sourced by the integration scripts. start_nginx OUT PORT... runs Debian's
# nginx on docker/nginx.conf, the shipped configuration, with only its
# addresses changed (Docker's DNS name becomes the given loopback ports, in
# every upstream) and this run's temporary paths under OUT. Sets NGINX_BASE
# (http://127.0.0.1:port) once nginx answers; fails the test otherwise.
# Needs fail() from the caller.
start_nginx() {
  local out=$1
  shift
  local nginx_bin servers="" port
  nginx_bin=$(command -v nginx || echo /usr/sbin/nginx)
  [[ -x $nginx_bin ]] || fail "nginx is not installed (scripts/setup.sh installs it)"
  chmod 755 "$out"  # nginx's workers (user nobody) write their temporary files here
  port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  for p in "$@"; do servers+="server 127.0.0.1:$p max_fails=2 fail_timeout=5s; "; done
  mkdir -p "$out/tmp"
  chmod 777 "$out/tmp"
  sed -e '/resolver 127.0.0.11/d' \
    -e "s|server surfdeform:8080 max_fails=2 fail_timeout=5s;|$servers|" \
    -e "s|listen 8080;|listen 127.0.0.1:$port;|" \
    -e "s|^http {|http {\n  access_log off;\n  client_body_temp_path $out/tmp/body;\n  proxy_temp_path $out/tmp/proxy;\n  fastcgi_temp_path $out/tmp/fastcgi;\n  uwsgi_temp_path $out/tmp/uwsgi;\n  scgi_temp_path $out/tmp/scgi;|" \
    -e 's|^worker_processes auto;|worker_processes 1;|' \
    "$(dirname "${BASH_SOURCE[0]}")/../../docker/nginx.conf" > "$out/nginx.conf"
  local last=${*: -1}
  (($(grep -c "127.0.0.1:$last " "$out/nginx.conf") >= 2)) \
    || fail "the upstream lines of docker/nginx.conf changed: update tests/integration/nginx_front.sh"
  "$nginx_bin" -p "$out" -c "$out/nginx.conf" -g "pid $out/nginx.pid; error_log $out/nginx-error.log warn;" \
    || fail "nginx did not start: $(cat "$out/nginx-error.log" 2> /dev/null)"
  NGINX_BASE="http://127.0.0.1:$port"
  for _ in $(seq 100); do
    curl -s -o /dev/null "$NGINX_BASE/healthz" && return 0
    sleep 0.05
  done
  fail "nginx does not answer on $NGINX_BASE"
}

# stop_nginx OUT: stops the nginx that start_nginx OUT ran the way its manual
# says (nginx -s stop, its fast shutdown, through the pid file), and waits
# until the master and each of its workers have exited; a kill -9 only for
# what is still there after 10 s. A worker left behind would outlive the test
# (tests/support/no_orphans fails it).
stop_nginx() {
  local out=$1 nginx_bin master workers p
  [[ -f $out/nginx.pid ]] || return 0
  nginx_bin=$(command -v nginx || echo /usr/sbin/nginx)
  master=$(cat "$out/nginx.pid")
  workers=$(pgrep -P "$master" || true)
  "$nginx_bin" -p "$out" -c "$out/nginx.conf" -g "pid $out/nginx.pid; error_log $out/nginx-error.log warn;" \
    -s stop 2> /dev/null || kill -TERM "$master" 2> /dev/null || true
  for _ in $(seq 200); do
    local alive=0
    for p in $master $workers; do  # a zombie has exited
      grep -qs '^State:[[:space:]]*[^Z]' "/proc/$p/status" && alive=1
    done
    ((alive)) || return 0
    sleep 0.05
  done
  echo "nginx did not stop within 10 s: killing it" >&2
  for p in $master $workers; do kill -9 "$p" 2> /dev/null || true; done
}
