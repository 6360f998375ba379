#!/usr/bin/env bash
# Builds the release wasm package into pkg/ (wasm-pack, then binaryen's wasm-opt from npm).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
./scripts/setup.sh
wasm-pack build --release --target web --out-dir pkg
node_modules/.bin/wasm-opt -O3 pkg/sec_playground_bg.wasm -o pkg/sec_playground_bg.wasm
ls -l pkg/sec_playground_bg.wasm | awk '{print "[build] pkg/sec_playground_bg.wasm: " $5 " bytes"}'
