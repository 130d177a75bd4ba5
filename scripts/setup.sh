#!/usr/bin/env bash
# Installs every system package the build, the tests and the benchmarks need.
# Idempotent: when everything is already installed it only checks and returns.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git clang-format
  libeigen3-dev            # engine: dense and sparse linear algebra
  libsuitesparse-dev libopenblas0-serial  # CHOLMOD for the mesh flattening, on OpenBLAS (serial: no threads of its own)
  libgtest-dev libgmock-dev googletest  # unit tests
  libbenchmark-dev         # benchmark executables
  libcli11-dev             # command-line flags
  nlohmann-json3-dev       # surface files in tests and benchmarks
  libcgal-dev libgmp-dev libmpfr-dev  # glyphs' constrained Delaunay triangulation; parts' self-intersection checks; peers in benchmarks
  lib3mf-dev               # 3MF output of printable parts (POST /v1/parts)
  libdraco-dev draco       # Draco meshes: library, and draco_decoder for round-trip tests
  libtinygltf-dev          # glTF / GLB
  libmeshoptimizer-dev     # EXT_meshopt_compression of animations' morph targets (/v1/animate)
  libcpp-httplib-dev       # the HTTP server (and the client in integration tests)
  libssl-dev               # SHA-256 for surface ids and ETags (OpenSSL)
  libhiredis-dev           # the optional shared surface tier (--redis)
  libxxhash-dev            # XXH3 digests of models: the service's placement memo
  libharfbuzz-dev libfreetype-dev  # text: HarfBuzz shapes, FreeType reads outlines (WOFF2 too)
  # The built-in fonts (service/builtin_fonts.hpp): DejaVu (Latin, Greek,
  # Cyrillic; sans, serif, mono), Cantarell (OpenType CFF: cubic outlines),
  # Amiri (Arabic), Ezra SIL (Hebrew), Lohit (Devanagari).
  fonts-dejavu-core fonts-cantarell fonts-hosny-amiri fonts-sil-ezra fonts-lohit-deva
  curl python3 python3-yaml  # the README's curl examples and the contract check, run as a test
  assimp-testmodels        # real glTF, OBJ, PLY, STL, OFF files (and broken ones) for tests
  clang-14 libclang-rt-14-dev  # libFuzzer for the mesh import fuzzer (tests/fuzz)
)
# npm installs the web viewer's three.js (client/web) and, for the tests, the
# Khronos glTF validator, puppeteer-core (which drives Debian's Chromium and
# Firefox ESR: no browser download) and kubernetes-models (the Kubernetes
# schemas, to check docker/k8s offline). A machine that already has node and npm
# (e.g. Node 20) keeps them. SURFDEFORM_SETUP_BUILD_ONLY=1 (the Docker image's
# build stage) skips what only the tests need.
build_only=${SURFDEFORM_SETUP_BUILD_ONLY:-0}
command -v node > /dev/null && command -v npm > /dev/null || packages+=(nodejs npm)
if [[ $build_only != 1 ]]; then
  # The viewer's browser tests: Firefox runs on an xvfb display (xvfb-run needs
  # xauth, only recommended), its WebGL on Mesa's software renderer.
  packages+=(chromium firefox-esr xvfb xauth libgl1-mesa-dri)
  packages+=(nginx)     # the replica failover test runs docker/nginx.conf (no Docker needed)
  packages+=(redis-server)  # the shared tier's tests run a real Redis (no Docker needed)
  packages+=(wrk)           # tests/load and scripts/loadtest.sh
  packages+=(yamllint)      # docker/k8s manifests are linted offline
  packages+=(valgrind)      # bench/instruction_ratio.sh counts instructions per request
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages present"
else
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  # Debian's nginx and redis-server packages start system services (ports 80,
  # 6379) when installed; the tests run their own. Without a policy-rc.d (Docker images have one),
  # deny service starts for the duration of the install.
  policy=/usr/sbin/policy-rc.d
  if [[ ! -e $policy ]]; then
    printf '#!/bin/sh\nexit 101\n' | "${sudo_cmd[@]}" tee "$policy" > /dev/null
    "${sudo_cmd[@]}" chmod 755 "$policy"
    trap '"${sudo_cmd[@]}" rm -f "$policy"' EXIT  # removed however the install ends
  fi
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# npm packages, pinned by the committed package-lock.json files.
root=$(cd "$(dirname "$0")/.." && pwd)
npm_ci() {  # folder, a package that shows it is installed
  if [[ ! -d "$root/$1/node_modules/$2" ]]; then
    echo "setup: npm ci in $1"
    npm ci --prefix "$root/$1" --no-audit --no-fund --loglevel=error
  fi
}
npm_ci client/web meshoptimizer  # the newest of its packages: an older install re-runs
if [[ $build_only != 1 ]]; then
  npm_ci tests/gltf gltf-validator
  npm_ci tests/browser puppeteer-core
  npm_ci tests/k8s kubernetes-models
  npm_ci tests/fonts wawoff2  # WOFF2 files for the font upload test (Google's encoder)
  npm_ci bench/text_peer opentype.js  # the text benchmark's peer (opentype.js + earcut)
  npm_ci tests/lint prettier  # ESLint and Prettier (scripts/lint_js.sh)
fi
