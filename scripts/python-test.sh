#!/usr/bin/env bash
# The Python package's suite: builds crates/sec-py into a virtual environment with maturin and
# runs its pytest tests (about a minute on a warm cache; the first run installs the pinned
# packages of crates/sec-py/requirements-test.txt and compiles PyO3).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
venv="${SEC_PY_VENV:-$PWD/target/py-venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q --disable-pip-version-check -r crates/sec-py/requirements-test.txt
VIRTUAL_ENV="$venv" PATH="$venv/bin:$PATH" maturin develop --release --quiet -m crates/sec-py/Cargo.toml
"$venv/bin/python" -m pytest -q crates/sec-py/tests
