#!/usr/bin/env bash
# Runs every test: native Rust tests, the wasm tests under Node, and the page in real Chromium.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
./scripts/setup.sh
echo "== native tests (cargo test --workspace)"
cargo test --workspace
echo "== wasm tests under Node (wasm-pack test --node)"
wasm-pack test --node
echo "== release wasm build for the page"
./scripts/build.sh
echo "== browser tests (Chromium via playwright-core)"
node --test tests/browser/
