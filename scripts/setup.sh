#!/usr/bin/env bash
# Installs bumprad's Debian packages (only those missing), Node.js if the machine has none,
# three.js from the npm registry for the viewer's walkthrough (pinned by
# server/web/package-lock.json, compiled into the server), and builds Release into build/.
# With --tests, also what the tests need: Chromium, playwright-core and gltf-validator from
# the npm registry, pinned by tests/web/package-lock.json, and clang for the fuzz target,
# built into build-fuzz/.
# Idempotent: a second run installs nothing and rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

lists=(scripts/debian-packages.txt)
[[ "${1:-}" == "--tests" ]] && lists+=(scripts/test-packages.txt)
mapfile -t packages < <(cat "${lists[@]}" | grep -v '^#' | grep -v '^$')
if ! command -v npm >/dev/null; then
  packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# npm ci reinstalls only when a lock file changed since its last install.
npm_ci() {
  if ! cmp -s "$1/package-lock.json" "$1/node_modules/.installed-lock.json"; then
    (cd "$1" && npm ci --no-audit --no-fund --loglevel=error &&
      cp package-lock.json node_modules/.installed-lock.json)
  fi
}
npm_ci server/web

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"

if [[ "${1:-}" == "--tests" ]]; then
  scripts/fuzz.sh --build-only  # clang, ASan and UBSan, into build-fuzz/
  npm_ci tests/web
fi
