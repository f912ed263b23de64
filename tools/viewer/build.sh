#!/usr/bin/env bash
# Builds the browser viewer into viewer/dist: the core compiled to WebAssembly, its wasm-bindgen
# bindings, and the page bundled with three.js (esbuild), so that it works offline. Installs the
# wasm32 target and the wasm-bindgen CLI matching Cargo.lock when they are missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
rustup target add wasm32-unknown-unknown >/dev/null 2>&1 || true
version=$(grep -A1 '^name = "wasm-bindgen"$' Cargo.lock | sed -n 's/^version = "\(.*\)"$/\1/p')
if ! wasm-bindgen --version 2>/dev/null | grep -qF "$version"; then
  cargo install wasm-bindgen-cli --version "$version" --quiet
fi
cargo build --release --target wasm32-unknown-unknown -p prehensile-wasm
wasm-bindgen --target web --out-dir viewer/pkg \
  target/wasm32-unknown-unknown/release/prehensile_wasm.wasm
(cd viewer && npm ci --no-audit --no-fund --silent && npm run bundle --silent)
rm -f viewer/dist/prehensile_wasm_bg.wasm # the page inlines it in main.js
cp viewer/index.html viewer/dist/
echo "viewer built: serve viewer/dist (e.g. python3 -m http.server -d viewer/dist) and open it"
