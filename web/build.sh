#!/usr/bin/env bash
# Builds the explorer for the browser into web/dist/: index.html, the
# JavaScript glue and the .wasm, a static folder any web server can host.
#
#   bash web/build.sh                      # build web/dist
#   python3 -m http.server -d web/dist     # serve it on http://localhost:8000
#
# Needs the wasm32 target and wasm-bindgen-cli at the version of the
# wasm-bindgen crate in Cargo.lock (the glue and the crate must match):
#   rustup target add wasm32-unknown-unknown
#   cargo install wasm-bindgen-cli --version <that version> --no-default-features
# Debian's binaryen (wasm-opt), if installed, makes the .wasm smaller.
set -euo pipefail
cd "$(dirname "$0")/.."

want=$(awk '/^name = "wasm-bindgen"$/ {getline; gsub(/version = |"/, ""); print; exit}' Cargo.lock)
if ! rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
  echo "error: the wasm32 target is missing: rustup target add wasm32-unknown-unknown" >&2
  exit 2
fi
have=$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)
if [ "$have" != "$want" ]; then
  echo "error: wasm-bindgen-cli ${have:-is not installed}${have:+ does not match}: Cargo.lock has wasm-bindgen $want;" \
    "install it with: cargo install wasm-bindgen-cli --version $want --no-default-features" >&2
  exit 2
fi

cargo build --profile web --target wasm32-unknown-unknown --bin oneblock
out=web/dist
tmp=$(mktemp -d web/.dist.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
wasm-bindgen --target web --no-typescript --out-dir "$tmp" --out-name oneblock \
  target/wasm32-unknown-unknown/web/oneblock.wasm
if command -v wasm-opt >/dev/null 2>&1; then
  wasm-opt -O2 --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
    --enable-mutable-globals "$tmp/oneblock_bg.wasm" -o "$tmp/oneblock_bg.opt.wasm"
  mv "$tmp/oneblock_bg.opt.wasm" "$tmp/oneblock_bg.wasm"
fi
cp web/index.html web/bench.html "$tmp/"
# Replace the old folder in one step: a server never sees half a build.
rm -rf "$out.old"
[ -d "$out" ] && mv "$out" "$out.old"
mv "$tmp" "$out"
rm -rf "$out.old"
trap - EXIT
echo "built $out: $(du -h "$out/oneblock_bg.wasm" | cut -f1) of wasm; serve it with: python3 -m http.server -d $out"
