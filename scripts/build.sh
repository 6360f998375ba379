#!/usr/bin/env bash
# Builds the playground: the release wasm in two flavours (pkg/: wasm SIMD; pkg/scalar/: the
# fallback for engines without it, same bits), each through binaryen's wasm-opt from npm, the
# page's vendored npm files, and dist/sec-playground/: a self-contained static folder a teacher
# copies next to a course page (no build step, no network).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
./scripts/setup.sh
wasm-pack build --release --target web --out-dir pkg
node_modules/.bin/wasm-opt -O3 pkg/sec_playground_bg.wasm -o pkg/sec_playground_bg.wasm
# The scalar build has other target features, so its own target dir keeps both cached.
RUSTFLAGS="-C target-feature=-simd128" CARGO_TARGET_DIR=target/scalar \
    wasm-pack build --release --target web --out-dir pkg/scalar
node_modules/.bin/wasm-opt -O3 pkg/scalar/sec_playground_bg.wasm -o pkg/scalar/sec_playground_bg.wasm
# The page's npm dependencies, pinned by package-lock.json, shipped with it (no CDN).
mkdir -p www/vendor
cp node_modules/uplot/dist/uPlot.esm.js node_modules/uplot/dist/uPlot.min.css node_modules/uplot/LICENSE www/vendor/
# The self-contained folder: only what the pages load.
rm -rf dist/sec-playground
mkdir -p dist/sec-playground/pkg/scalar
mkdir -p dist/sec-playground/assets
cp index.html embed.html arena.html dist/sec-playground/
cp -r www dist/sec-playground/www
cp -r assets/encoders dist/sec-playground/assets/encoders
cp -r assets/reference dist/sec-playground/assets/reference
cp -r assets/warm-up dist/sec-playground/assets/warm-up
for d in pkg pkg/scalar; do
    cp "$d/sec_playground.js" "$d/sec_playground_bg.wasm" "dist/sec-playground/$d/"
done
cp LICENSE* dist/sec-playground/ 2>/dev/null || true
for f in pkg/sec_playground_bg.wasm pkg/scalar/sec_playground_bg.wasm; do
    echo "[build] $f: $(stat -c %s "$f") bytes, $(gzip -9c "$f" | wc -c) gzipped"
done
echo "[build] dist/sec-playground: $(du -sk dist/sec-playground | cut -f1) KB"
