#!/usr/bin/env bash
# The Kubernetes manifests (docker/k8s) and compose.yaml, offline: yamllint
# (Debian), then the Kubernetes schemas and the drain/probe/resource rules
# (validate.mjs, npm kubernetes-models, installed by scripts/setup.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
k8s="$here/../../docker/k8s"
command -v yamllint > /dev/null || { echo "FAIL: yamllint is not installed (scripts/setup.sh installs it)" >&2; exit 1; }
[[ -d $here/node_modules/kubernetes-models ]] || { echo "FAIL: run scripts/setup.sh (npm ci in tests/k8s)" >&2; exit 1; }
yamllint -s -c "$k8s/.yamllint.yaml" "$k8s" "$k8s/../compose.yaml"
node "$here/validate.mjs" "$k8s"
