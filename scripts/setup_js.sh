#!/usr/bin/env bash
# Installs the JavaScript checks of tests/js (Khronos glTF-Validator, three.js) from the
# committed lock file. Installs nodejs/npm with apt-get first if `node` is missing.
# Re-runs `npm ci` only when tests/js/node_modules is missing or older than the lock file.
# Usage: bash scripts/setup_js.sh
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "setup_js: installing nodejs and npm" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    nodejs npm >/dev/null
fi

major="$(node -p 'process.versions.node.split(".")[0]')"
if [ "$major" -lt 18 ]; then
  echo "setup_js: node $(node --version) is too old (need >= 18)" >&2
  exit 1
fi

cd tests/js
stamp="node_modules/.dermis-lock.sha256"
want="$(sha256sum package-lock.json | cut -d' ' -f1)"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] &&
   [ -d node_modules/gltf-validator ] && [ -d node_modules/three ]; then
  echo "setup_js: tests/js/node_modules is up to date" >&2
  exit 0
fi
echo "setup_js: npm ci in tests/js" >&2
npm ci --no-audit --no-fund --loglevel=error
echo "$want" > "$stamp"
node --input-type=module -e 'import v from "gltf-validator"; import * as T from "three";
  console.error(`setup_js: gltf-validator ${v.version()}, three r${T.REVISION}`)'
