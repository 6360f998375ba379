#!/usr/bin/env bash
# Runs every test: the fast gate (fmt, clippy, docs), native Rust tests, the Python package's
# pytest suite, the wasm tests under Node, and the page in real Chromium (with the notebook widget
# in JupyterLab, from the Python test venv, and on a MyST page).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
echo "== the fast gate (scripts/lint.sh)"
./scripts/lint.sh
./scripts/setup.sh
echo "== native tests (cargo test --workspace)"
cargo test --workspace
echo "== release wasm build for the page (and the notebook widget's module, which the wheel carries)"
./scripts/build.sh
echo "== the Python package (scripts/python-test.sh: the manylinux wheel, pytest in a venv without Rust)"
./scripts/python-test.sh
echo "== the page's test flavour (pkg/hooks: the test hooks on)"
./scripts/build-hooks.sh
# Release: it reuses the build just made, and the golden runs take seconds instead of minutes.
# `wasm-pack test --node` (a debug build) runs the same tests.
echo "== wasm tests under Node (wasm-pack test --node --release)"
wasm-pack test --node --release
echo "== browser tests (Chromium via playwright-core) and the TypeScript declarations"
node --test tests/browser/
