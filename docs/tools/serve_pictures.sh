#!/bin/sh
# The pictures of sliding in docs/serve.md: tests/browser/draw.test.mjs writes them, 640x400,
# beside its screenshots (target/browser-demo/serve-*.png); this copies them into docs/.
# Run from the repository's root after the browser test.
set -eu
shots=${BROWSER_DEMO:-target/browser-demo}
for name in slide slid-run; do
  cp "$shots/serve-$name.png" "docs/serve-$name.png"
done
