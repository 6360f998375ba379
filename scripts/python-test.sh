#!/usr/bin/env bash
# The Python package's suite, run against the wheel a user installs: builds crates/sec-py into a
# manylinux2014 wheel (maturin with zig from PyPI as the linker, in target/py-build), installs it
# into a test venv (target/py-venv) and runs pytest there with no Rust toolchain on PATH. About two
# minutes on a warm cache; the first run installs the pinned packages of
# crates/sec-py/requirements-{build,test}.txt (JupyterLab among them, for the widget's browser
# test) and compiles PyO3. The wheel carries the notebook widget's module, which scripts/build.sh
# makes: run that first.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
build="$PWD/target/py-build"
venv="${SEC_PY_VENV:-$PWD/target/py-venv}"
for v in "$build" "$venv"; do [ -x "$v/bin/python" ] || python3 -m venv "$v"; done
"$build/bin/pip" install -q --disable-pip-version-check -r crates/sec-py/requirements-build.txt
if [ ! -f crates/sec-py/python/sec_playground/_widget/widget.js ]; then
    echo "[python-test] the notebook widget's module is missing: run scripts/build.sh first (the wheel carries it)" >&2
    exit 1
fi
rm -f target/wheels/sec_playground-*.whl
VIRTUAL_ENV="$build" PATH="$build/bin:$PATH" maturin build --release --quiet --zig --compatibility manylinux2014 \
    -m crates/sec-py/Cargo.toml -o target/wheels
wheel=$(ls target/wheels/sec_playground-*-manylinux*.whl)
echo "[python-test] $wheel: $(stat -c %s "$wheel") bytes"
"$venv/bin/pip" install -q --disable-pip-version-check -r crates/sec-py/requirements-test.txt
"$venv/bin/pip" install -q --disable-pip-version-check --force-reinstall --no-deps "$wheel"
# The suite sees what a user without Rust sees: no cargo, rustc or maturin on PATH.
clean_path="$venv/bin:/usr/local/bin:/usr/bin:/bin"
if PATH="$clean_path" command -v cargo >/dev/null || PATH="$clean_path" command -v rustc >/dev/null; then
    echo "[python-test] a Rust toolchain is on the test PATH ($clean_path); the wheel test needs none" >&2
    exit 1
fi
# The submitit example and the Ray test drive the runner binary, where a build of it exists (the
# test command's native tests build the debug one from this checkout, so it comes first; the tests
# that need it are skipped without one).
targets="${CARGO_TARGET_DIR:-$PWD/target}"
bin=""
for b in "$targets/debug/sec-experiment" "$targets/release/sec-experiment"; do
    if [ -x "$b" ]; then bin=$(cd "$(dirname "$b")" && pwd)/sec-experiment; break; fi
done
cd crates/sec-py # the tests import the installed wheel, not python/ in the source tree
env -i HOME="$HOME" PATH="$clean_path" LANG=C.UTF-8 SEC_NO_RUST=1 SEC_EXPERIMENT_BIN="$bin" "$venv/bin/python" -m pytest -q tests
