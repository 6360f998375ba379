#!/usr/bin/env bash
# Builds the page's test flavour into pkg/hooks/: the playground's release SIMD build (pkg/: no
# YAML parser, no rigid bodies) with the `test-hooks` feature (timing loops for bench/, a
# deliberate panic for the page's error-path test), through the same wasm-opt as the published
# build so the benchmarks time what users run. It shares every dependency with pkg/'s build. The published
# pkg/ and dist/ never contain it; the page loads it only with `?wasm=hooks` in its address.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
./scripts/setup.sh
wasm-pack build --release --target web --out-dir pkg/hooks -- --no-default-features --features test-hooks
node_modules/.bin/wasm-opt -O3 pkg/hooks/sec_playground_bg.wasm -o pkg/hooks/sec_playground_bg.wasm
