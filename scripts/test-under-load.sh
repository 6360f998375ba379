#!/usr/bin/env bash
# The wasm and browser suites with every core kept busy, several times in a row: a test that
# reads a value and what shows it at two moments, or waits for a time instead of a condition,
# fails here where it passes on an idle machine. CI's machines are busy; the suites must hold.
#
#   scripts/test-under-load.sh [ROUNDS]      (default 3; needs scripts/test.sh's builds: pkg/,
#                                             pkg/hooks/, and wasm-pack, Node, Chromium)
#
# Each core gets a `yes > /dev/null` at normal priority for the whole script; they are stopped
# on exit, however it exits. It stops at the first failing round and says which.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
rounds="${1:-3}"
case "$rounds" in '' | *[!0-9]* | 0) echo "test-under-load: ROUNDS '$rounds' is not a whole number >= 1" >&2; exit 2 ;; esac
for built in pkg/sec_playground.js pkg/hooks/sec_playground.js; do
    [ -f "$built" ] || { echo "test-under-load: $built is missing: run scripts/build.sh and scripts/build-hooks.sh (or scripts/test.sh) first" >&2; exit 2; }
done
cores=$(nproc)
load=()
stop() { [ ${#load[@]} -eq 0 ] || kill "${load[@]}" 2>/dev/null || true; }
trap stop EXIT INT TERM
for _ in $(seq "$cores"); do
    yes > /dev/null &
    load+=("$!")
done
echo "[test-under-load] $cores busy loops on $cores cores; $rounds rounds of the wasm and browser suites"
for round in $(seq "$rounds"); do
    start=$(date +%s)
    echo "[test-under-load] round $round/$rounds: wasm tests under Node"
    wasm-pack test --node --release || { echo "[test-under-load] round $round: the wasm suite failed under load" >&2; exit 1; }
    echo "[test-under-load] round $round/$rounds: browser tests"
    node --test tests/browser/ || { echo "[test-under-load] round $round: the browser suite failed under load" >&2; exit 1; }
    echo "[test-under-load] round $round passed in $(( $(date +%s) - start )) s (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
done
echo "[test-under-load] $rounds rounds passed"
