#!/bin/sh
# Copy the /check page's browser libraries from node_modules (after `npm ci`) into
# app/checker/static/vendor/, each beside its licence. The app serves these copies itself: no CDN.
# tests/checker/test_checker_vendor.py checks that the copies equal node_modules' files.
set -eu
cd "$(dirname "$0")/.."
vendor=app/checker/static/vendor
test -d node_modules/jsqr -a -d node_modules/@noble/ed25519 || { echo "run 'npm ci' first" >&2; exit 1; }
mkdir -p "$vendor"
cp node_modules/jsqr/dist/jsQR.js "$vendor/jsQR.js"
cp node_modules/jsqr/LICENSE "$vendor/jsQR.LICENSE"
cp node_modules/@noble/ed25519/index.js "$vendor/noble-ed25519.js"
cp node_modules/@noble/ed25519/LICENSE "$vendor/noble-ed25519.LICENSE"
echo "vendored: $(ls "$vendor" | tr '\n' ' ')"
