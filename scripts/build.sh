#!/usr/bin/env bash
# Builds the release wasm package into pkg/ (wasm-pack, then binaryen's wasm-opt from npm).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
./scripts/setup.sh
wasm-pack build --release --target web --out-dir pkg
node_modules/.bin/wasm-opt -O3 pkg/sec_playground_bg.wasm -o pkg/sec_playground_bg.wasm
# The page's npm dependencies, pinned by package-lock.json, shipped with it (no CDN).
mkdir -p www/vendor
cp node_modules/uplot/dist/uPlot.esm.js node_modules/uplot/dist/uPlot.min.css node_modules/uplot/LICENSE www/vendor/
ls -l pkg/sec_playground_bg.wasm | awk '{print "[build] pkg/sec_playground_bg.wasm: " $5 " bytes"}'
