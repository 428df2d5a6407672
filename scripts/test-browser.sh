#!/usr/bin/env bash
# The end-to-end tests of `timbre serve` in a real browser (tests/browser/preview.test.mjs):
# headless Debian Chromium driven by playwright-core, against target/release/timbre (build it
# first: `cargo build --release`; scripts/test.sh runs this after `cargo test --release`).
# Installs Chromium and the npm package first if missing (scripts/setup-browser.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-browser.sh
[ -x target/release/timbre ] || { echo "test-browser: target/release/timbre not found; run cargo build --release" >&2; exit 1; }
TIMBRE="$PWD/target/release/timbre" node --test tests/browser/*.test.mjs
