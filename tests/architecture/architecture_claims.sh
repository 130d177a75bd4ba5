#!/usr/bin/env bash
# The claims of docs/ARCHITECTURE.md that a script can check, checked:
# - every folder of server/ and every stage of server/engine/ is named on
#   the page (its tree and its pipeline);
# - httplib.h and Eigen never meet in one translation unit: the headers that
#   meet httplib (service/service.hpp, service/reply.hpp, the CLI's
#   api_client.hpp) reach no engine header and no Eigen header, however
#   deep (the project's includes followed from server/, proto/ and client/);
# - the HTTP layer maps statuses to HTTP codes in one place: only
#   server/http/problem.cpp names the codes of base/status.hpp's errors;
# - the viewer: no file under client/web/public/ is over 400 lines, only
#   viewer_state.js defines actions (no other file calls createStore), and
#   the browser tests read the page through window.surfdeformTest only.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
page=$root/docs/ARCHITECTURE.md
fail=0
report() { echo "FAIL: $1"; printf '%s\n' "$2" | sed 's/^/  /'; fail=1; }

for dir in "$root"/server/*/; do
  name=server/$(basename "$dir")/
  grep -qF "$name" "$page" || report "docs/ARCHITECTURE.md does not name $name" "add it to the tree"
done
for dir in "$root"/server/engine/*/; do
  name=$(basename "$dir")/
  grep -qE "(^|[ \`])$name" "$page" || report "docs/ARCHITECTURE.md does not name the stage $name" \
    "add it to the pipeline"
done

hits=$(python3 - "$root" << 'PY'
import os, re, sys
root = sys.argv[1]
bases = [os.path.join(root, d) for d in ("server", ".", "client/cli")]
def find(name, here):
    for base in [here] + bases:
        p = os.path.normpath(os.path.join(base, name))
        if os.path.isfile(p):
            return p
    return None
def reach(start):
    seen, todo, bad = set(), [start], []
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen.add(f)
        for line in open(f, encoding="utf-8", errors="replace"):
            m = re.match(r'\s*#\s*include\s*([<"])([^>"]+)[>"]', line)
            if not m:
                continue
            name = m.group(2)
            if name.startswith("Eigen/") or name.startswith("engine/"):
                bad.append(f"{os.path.relpath(f, root)} includes {name}")
            if m.group(1) == '"':
                p = find(name, os.path.dirname(f))
                if p:
                    todo.append(p)
    return bad
for h in ("server/service/service.hpp", "server/service/reply.hpp", "client/cli/api_client.hpp"):
    for b in reach(os.path.join(root, h)):
        print(f"{h}: {b}")
PY
)
[[ -z $hits ]] || report "a header that meets httplib reaches Eigen or the engine" "$hits"

hits=$(grep -rnE 'ErrorCode::k[A-Za-z]+' "$root/server/http" --include=*.cpp |
  grep -E 'status *= *[0-9]{3}|return [0-9]{3}|case ErrorCode' | grep -v '/problem.cpp:' || true)
[[ -z $hits ]] || report "an error code mapped to HTTP outside server/http/problem.cpp" "$hits"

web=$root/client/web/public
hits=$(wc -l "$web"/*.js | awk '$2 != "total" && $1 > 400 {print $2 ": " $1 " lines"}')
[[ -z $hits ]] || report "a viewer file over 400 lines" "$hits"
hits=$(grep -ln 'createStore(' "$web"/*.js | grep -vE '/(app|store)\.js$' || true)
[[ -z $hits ]] || report "a second store in the viewer" "$hits"
hits=$(grep -nE 'window\.surfdeform[A-SU-Z][a-zA-Z]*' "$root"/tests/browser/*.mjs "$root"/bench/*.mjs || true)
[[ -z $hits ]] || report "a test reads the page past window.surfdeformTest" "$hits"

((fail == 0)) && echo "architecture claims: all hold"
exit $fail
