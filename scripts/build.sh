#!/usr/bin/env bash
# Builds the playground: the release wasm in two flavours (pkg/: wasm SIMD; pkg/scalar/: the
# fallback for engines without it, same bits), both without the YAML parser (41 KB gzipped, used
# only by the arena page), and the arena page's own build with it (pkg/arena/: scalar, which every
# engine runs; that page runs no encoder), each through binaryen's wasm-opt from npm, the page's
# vendored npm files, and dist/sec-playground/: a self-contained static folder a teacher copies
# next to a course page (no build step, no network), which is also the npm package.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
./scripts/setup.sh
wasm-pack build --release --target web --out-dir pkg -- --no-default-features
# The scalar builds have other target features, so their own target dir keeps both cached.
RUSTFLAGS="-C target-feature=-simd128" CARGO_TARGET_DIR=target/scalar \
    wasm-pack build --release --target web --out-dir pkg/scalar -- --no-default-features
RUSTFLAGS="-C target-feature=-simd128" CARGO_TARGET_DIR=target/scalar \
    wasm-pack build --release --target web --out-dir pkg/arena
for d in pkg pkg/scalar; do
    node_modules/.bin/wasm-opt -O3 "$d/sec_playground_bg.wasm" -o "$d/sec_playground_bg.wasm"
done
# The arena build (2.6 MB with rapier3d) at -O1: -O3 took 4 minutes here for a file 0.6 % larger
# gzipped, and -O1, -O2, -O3 and no pass at all step its arenas at the same speed in Node
# (BENCHMARKS.md, "What the pushable objects cost").
node_modules/.bin/wasm-opt -O1 pkg/arena/sec_playground_bg.wasm -o pkg/arena/sec_playground_bg.wasm
# The page's npm dependencies, pinned by package-lock.json, shipped with it (no CDN).
mkdir -p www/vendor
# uPlot's own minified build (22 KB gzipped instead of the ES module's 42 KB) as an ES module: it
# declares `var uPlot`, which a module can export.
cp node_modules/uplot/dist/uPlot.min.css node_modules/uplot/LICENSE www/vendor/
rm -f www/vendor/uPlot.esm.js
{ cat node_modules/uplot/dist/uPlot.iife.min.js; printf '\nexport default uPlot;\n'; } > www/vendor/uPlot.esm.min.js
# The self-contained folder: only what the pages load.
rm -rf dist/sec-playground
mkdir -p dist/sec-playground/pkg/scalar dist/sec-playground/pkg/arena
mkdir -p dist/sec-playground/assets
cp index.html embed.html arena.html dist/sec-playground/
cp -r www dist/sec-playground/www
cp -r assets/encoders dist/sec-playground/assets/encoders
# The arena page's arenas: the tasks' files and the Olympics corpus with its menu.
cp -r assets/arenas dist/sec-playground/assets/arenas
cp -r assets/reference dist/sec-playground/assets/reference
cp -r assets/warm-up dist/sec-playground/assets/warm-up
for d in pkg pkg/scalar pkg/arena; do
    cp "$d/sec_playground.js" "$d/sec_playground.d.ts" "$d/sec_playground_bg.wasm" "dist/sec-playground/$d/"
done
# The notebook widget's module (one file: the element and its workers; docs/EMBED.md), in the
# package for static pages (MyST), and with the files it is given at run time in the Python
# package, whose kernel sends them (crates/sec-py/python/sec_playground/notebook.py).
node scripts/widget-build.mjs dist/sec-playground
widget=crates/sec-py/python/sec_playground/_widget
rm -rf "$widget"
mkdir -p "$widget/files/pkg/scalar" "$widget/files/assets" "$widget/files/www/vendor"
cp dist/sec-playground/widget.js "$widget/"
cp pkg/sec_playground_bg.wasm "$widget/files/pkg/"
cp pkg/scalar/sec_playground_bg.wasm "$widget/files/pkg/scalar/"
cp -r assets/encoders assets/reference assets/warm-up "$widget/files/assets/"
cp www/style.css "$widget/files/www/"
cp www/vendor/uPlot.min.css "$widget/files/www/vendor/"
# The folder is also the npm package (package.json, README; the element's manifest is in www/).
node scripts/npm-package.mjs dist/sec-playground
for f in pkg/sec_playground_bg.wasm pkg/scalar/sec_playground_bg.wasm pkg/arena/sec_playground_bg.wasm; do
    echo "[build] $f: $(stat -c %s "$f") bytes, $(gzip -9c "$f" | wc -c) gzipped"
done
echo "[build] dist/sec-playground: $(du -sk dist/sec-playground | cut -f1) KB"
