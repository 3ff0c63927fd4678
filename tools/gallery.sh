#!/usr/bin/env bash
# Renders the gallery (the paper's Fig. 1, white coat lit from above, and Fig. 2, skin, under
# every shading model) with `dermis render` into docs/gallery/: one image per line of
# docs/gallery/shots.txt. tests/cli/gallery.rs checks the committed images against the renderer,
# so run this after any change that moves pixels.
# Usage: bash tools/gallery.sh [path/to/dermis]   (default: target/release/dermis)
set -euo pipefail
cd "$(dirname "$0")/.."
dermis=${1:-target/release/dermis}
out=docs/gallery
mkdir -p "$out"
while read -r name args; do
  case "$name" in '' | '#'*) continue ;; esac
  # shellcheck disable=SC2086 # the arguments are words
  "$dermis" render $args --out "$out/$name.png" </dev/null
done < "$out/shots.txt"
