#!/usr/bin/env bash
# The Python package for machines beyond x86_64 Linux: the sdist, installed with pip into a clean
# venv where only a Rust toolchain is added (what pip does on a platform with no wheel), and the
# manylinux2014 aarch64 wheel, cross-compiled with zig from PyPI. Each is checked: the sdist
# carries what the build reads and installs into a working package; the aarch64 wheel's tag, its
# extension's machine (AArch64) and the newest glibc symbol it needs (<= 2.17). Both land in
# target/wheels/. The sdist compiles the crates from scratch: several minutes. Not part of the test
# command (scripts/test.sh builds and tests the x86_64 wheel); run it before a release, after
# scripts/build.sh (which makes the notebook widget's module and files both packages carry).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
if [ ! -f crates/sec-py/python/sec_playground/_widget/widget.js ]; then
    echo "[python-dist] the notebook widget's module is missing: run scripts/build.sh first" >&2
    exit 1
fi
build="$PWD/target/py-build"
[ -x "$build/bin/python" ] || python3 -m venv "$build"
"$build/bin/pip" install -q --disable-pip-version-check -r crates/sec-py/requirements-build.txt
maturin() { VIRTUAL_ENV="$build" PATH="$build/bin:$PATH" "$build/bin/maturin" "$@"; }
mkdir -p target/wheels
say() { printf '[python-dist] %s\n' "$*"; }

# 1. The sdist: every file the build reads (the core's sources and its bundled encoders).
rm -f target/wheels/sec_playground-*.tar.gz
maturin sdist -m crates/sec-py/Cargo.toml -o target/wheels
sdist=$(ls target/wheels/sec_playground-*.tar.gz)
files=$(tar tzf "$sdist")
say "$sdist: $(stat -c %s "$sdist") bytes, $(wc -l <<<"$files") files"
# The notebook widget's module and files are built here (scripts/build.sh) and carried as they are.
for f in pyproject.toml Cargo.toml Cargo.lock src/lib.rs assets/encoders/double-t-maze.secae \
         crates/sec-py/src/lib.rs python/sec_playground/__init__.py README.md \
         python/sec_playground/_widget/widget.js python/sec_playground/_widget/files/pkg/sec_playground_bg.wasm; do
    grep -qx "sec_playground-[^/]*/$f" <<<"$files" || { say "the sdist lacks $f"; exit 1; }
done
# The workspace's results, page, tests and docs stay out (the crates' own tests may come along).
if grep -qE '^sec_playground-[^/]*/(results|www|tests|target|docs|bench)/' <<<"$files"; then
    say "the sdist carries files the build does not read:"
    grep -E '^sec_playground-[^/]*/(results|www|tests|target|docs|bench)/' <<<"$files" | head
    exit 1
fi

# 2. pip builds it in a clean venv: a Rust toolchain on PATH, maturin fetched by pip.
venv="$PWD/target/py-sdist-venv"
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/pip" install -q --disable-pip-version-check --no-cache-dir "$sdist"
"$venv/bin/python" - <<'EOF'
import gymnasium as gym
import sec_playground
env = gym.make("SecPlayground/DoubleTMaze-v0")
obs, _ = env.reset(seed=1)
assert obs.shape == (84, 84, 3)
run = sec_playground.Run(seed=1)
m = run.episode()
print(f"[python-dist] the sdist's build works: {len(env.unwrapped.get_action_meanings())} actions, episode 0 reward {m['reward']}")
EOF

# 3. The aarch64 wheel (manylinux2014: glibc 2.17).
rustup target list --installed | grep -qx aarch64-unknown-linux-gnu || rustup target add aarch64-unknown-linux-gnu
rm -f target/wheels/sec_playground-*aarch64*.whl
maturin build --release --quiet --zig --target aarch64-unknown-linux-gnu --compatibility manylinux2014 \
    -m crates/sec-py/Cargo.toml -o target/wheels
wheel=$(ls target/wheels/sec_playground-*manylinux*aarch64*.whl)
say "$wheel: $(stat -c %s "$wheel") bytes"
case "$wheel" in *-cp39-abi3-*manylinux_2_17_aarch64*.whl) ;; *) say "unexpected tags: $wheel"; exit 1 ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/bin/python" -m zipfile -e "$wheel" "$tmp"
so=$(find "$tmp" -name '_core*.so')
machine=$(readelf -h "$so" | sed -n 's/^ *Machine: *//p')
[ "$machine" = "AArch64" ] || { say "$so is for $machine, not AArch64"; exit 1; }
newest=$(readelf -V --wide "$so" | grep -o 'GLIBC_[0-9.]*' | sort -t. -k1,1 -k2,2n -k3,3n -V | tail -1)
say "extension: $machine, newest glibc symbol $newest"
# The README is the long description PyPI shows.
meta=$(find "$tmp" -name METADATA)
grep -q '^Description-Content-Type: text/markdown' "$meta" && grep -qx '# SEC Playground' "$meta" \
    || { say "the wheel's METADATA lacks the README"; exit 1; }
[ "$(printf '%s\nGLIBC_2.17\n' "$newest" | sort -V | tail -1)" = "GLIBC_2.17" ] || { say "needs $newest > 2.17"; exit 1; }
say "ok"
