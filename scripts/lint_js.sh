#!/usr/bin/env bash
# ESLint (eslint:recommended, tests/lint/eslint.config.mjs) and Prettier
# (.prettierrc.json) over the project's JavaScript, HTML and CSS: the viewer
# (client/web/public), and the browser tests, benchmarks and helpers run by
# Node. Both must be clean. With --fix, Prettier rewrites the files and
# ESLint fixes what it can.
set -euo pipefail
cd "$(dirname "$0")/.."
lint=tests/lint/node_modules/.bin
[[ -x $lint/eslint && -x $lint/prettier ]] || {
  echo "lint_js: run scripts/setup.sh first (npm ci in tests/lint)" >&2
  exit 1
}
mapfile -t files < <(git ls-files -co --exclude-standard 'client/web/public/*.js' \
  'client/web/public/*.html' 'client/web/public/*.css' '*.mjs' | grep -v node_modules)
mapfile -t scripts < <(printf '%s\n' "${files[@]}" | grep -E '\.m?js$')
if [[ ${1:-} == --fix ]]; then
  "$lint/prettier" --log-level warn --write "${files[@]}"
  "$lint/eslint" -c tests/lint/eslint.config.mjs --fix "${scripts[@]}"
else
  "$lint/prettier" --log-level warn --check "${files[@]}"
  "$lint/eslint" -c tests/lint/eslint.config.mjs --max-warnings 0 "${scripts[@]}"
fi
echo "lint_js: ${#scripts[@]} scripts clean (ESLint), ${#files[@]} files formatted (Prettier)"
