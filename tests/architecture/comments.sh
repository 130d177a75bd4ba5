#!/usr/bin/env bash
# Comments say what the code does and why, in words that stay true: no
# issue numbers ("issue #37", "Issue 34, item 4", "(#38)": the tracker is
# not the code's history) and no dates ("2026-12", "measured 2026-05-02":
# a dated figure rots; BENCHMARKS.md keeps figures with the command that
# remakes them). Checked over every tracked source, script and build file.
set -euo pipefail
cd "$(dirname "$0")/../.."
mapfile -t files < <(git ls-files -co --exclude-standard '*.cpp' '*.hpp' '*.h' '*.js' '*.mjs' \
  '*.sh' '*.py' '*.lua' '*.yaml' '*.conf' 'CMakeLists.txt' '*/CMakeLists.txt' '*Dockerfile' |
  grep -v -e node_modules -e '^tests/fuzz/seeds/')
fail=0
report() { echo "FAIL: $1"; printf '%s\n' "$2" | sed 's/^/  /'; fail=1; }
hits=$(grep -nE '\b[Ii]ssues? #?[0-9]+|\(#[0-9]+\)|\bitem [0-9]+ of issue' "${files[@]}" |
  grep -v '^tests/architecture/comments.sh:' || true)
[[ -z $hits ]] || report "an issue number in the code (say what and why instead)" "$hits"
hits=$(grep -nE '\b20[0-9]{2}-(0[1-9]|1[0-2])\b' "${files[@]}" |
  grep -v '^tests/architecture/comments.sh:' || true)
[[ -z $hits ]] || report "a date in the code (dated figures go in BENCHMARKS.md with their command)" "$hits"
((fail == 0)) && echo "comments: no issue numbers, no dates (${#files[@]} files)"
exit $fail
