#!/usr/bin/env bash
# Runs every test: native Rust tests, the wasm tests under Node, and the page in real Chromium.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
./scripts/setup.sh
echo "== native tests (cargo test --workspace)"
cargo test --workspace
echo "== release wasm build for the page"
./scripts/build.sh
# Release: it reuses the build just made, and the golden runs take seconds instead of minutes.
# `wasm-pack test --node` (a debug build) runs the same tests.
echo "== wasm tests under Node (wasm-pack test --node --release)"
wasm-pack test --node --release
echo "== browser tests (Chromium via playwright-core) and the TypeScript declarations"
node --test tests/browser/
