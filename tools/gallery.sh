#!/usr/bin/env bash
# Reproduces the paper's Fig. 1 (white coat lit from above) and Fig. 2 (skin) with
# `dermis render`, into docs/gallery/. Usage: bash tools/gallery.sh [path/to/dermis]
set -euo pipefail
cd "$(dirname "$0")/.."
dermis=${1:-target/release/dermis}
out=docs/gallery
mkdir -p "$out"
for m in dipole ward oss oss-stable burley tabulated preintegrated; do
  "$dermis" render --shading "$m" --material white-coat --light 0.3,3.2,0.6 --clip 0 --time 0.5 \
    --size 480x540 --out "$out/fig1-white-coat-$m.png"
  "$dermis" render --shading "$m" --material skin1 --clip 1 --time 0.2 \
    --size 480x540 --out "$out/fig2-skin-$m.png"
done
