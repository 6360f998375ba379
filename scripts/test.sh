#!/usr/bin/env bash
# Runs every test: the fast gate (fmt, clippy, docs), native Rust tests, the Python package's
# pytest suite, the wasm tests under Node, and the page in real Chromium (with the notebook widget
# in JupyterLab, from the Python test venv, and on a MyST page).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
# Each phase says when it starts (seconds since the start), so a slow run shows where time went.
phase() { echo "== [${SECONDS} s] $*"; }
phase "the fast gate (scripts/lint.sh)"
./scripts/lint.sh
./scripts/setup.sh
phase "native tests (cargo test --workspace)"
cargo test --workspace
phase "release wasm build for the page (and the notebook widget's module, which the wheel carries)"
./scripts/build.sh
phase "the Python package (scripts/python-test.sh: the manylinux wheel, pytest in a venv without Rust)"
./scripts/python-test.sh
phase "the page's test flavour (pkg/hooks: the test hooks on)"
./scripts/build-hooks.sh
# Release, so the golden runs take seconds instead of minutes; with parallel code generation and
# no link-time optimisation (the shipped builds' cgu = 1 and thin LTO): the test build reuses no
# shipped artifact (other features), so this only halves its compile (160 -> 87 s here) and gives
# the same bits. `wasm-pack test --node` (a debug build) runs the same tests.
phase "wasm tests under Node (wasm-pack test --node --release)"
CARGO_PROFILE_RELEASE_CODEGEN_UNITS=16 CARGO_PROFILE_RELEASE_LTO=false wasm-pack test --node --release
phase "browser tests (Chromium via playwright-core) and the TypeScript declarations"
node --test tests/browser/
phase "done"
