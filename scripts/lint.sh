#!/usr/bin/env bash
# The fast gate, run first by the test command: the JavaScript modules parse, formatting, the
# core's layers, clippy (native and wasm32) and the docs, each with warnings as errors. A minute
# or two on a warm cache.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
installed=$(rustup component list --installed)
for c in rustfmt clippy; do
  grep -q "^$c" <<<"$installed" || rustup component add "$c"
done
rustup target list --installed | grep -qx wasm32-unknown-unknown || rustup target add wasm32-unknown-unknown
echo "== node --check (every JavaScript module of the page, the tests and the scripts parses)"
for f in www/*.js tests/browser/*.mjs bench/*.mjs scripts/*.mjs; do
  node --check "$f"
done
echo "== cargo fmt --check"
cargo fmt --all --check
echo "== the core's layers (tests/layers.rs: no import up the layers, no loop among src/ files)"
cargo test -q --test layers
echo "== cargo clippy (native, every target)"
cargo clippy --workspace --all-targets -- -D warnings
echo "== cargo clippy (the library without the test hooks, native and wasm32)"
cargo clippy -p sec-playground --lib -- -D warnings
cargo clippy --lib --target wasm32-unknown-unknown -- -D warnings
echo "== cargo clippy (wasm32: the web module with the test hooks, and the wasm tests)"
cargo clippy --lib --tests --target wasm32-unknown-unknown -- -D warnings
echo "== cargo doc"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace --quiet
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --lib --target wasm32-unknown-unknown --quiet
