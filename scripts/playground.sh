#!/usr/bin/env bash
# Installs what is missing, builds the wasm package and serves the playground on localhost.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
exec node scripts/serve.mjs "${PORT:-8080}"
