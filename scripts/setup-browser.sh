#!/usr/bin/env bash
# Installs what the browser tests of `timbre serve` (tests/browser/, run by
# scripts/test-browser.sh) need, on Debian 12 (run as root, or with sudo available):
#   chromium         Debian's Chromium, run headless (/usr/bin/chromium); Playwright downloads
#                    no browser of its own
#   playwright-core  from npm, the exact version of tests/browser/package-lock.json (`npm ci`
#                    into tests/browser/node_modules, again whenever the lock file is newer)
# Node.js 20 or newer with npm must be installed already (playwright-core needs Node 20).
# Idempotent: when everything is installed it only checks and returns.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ ! -x /usr/bin/chromium ]; then
    echo "setup-browser: installing chromium" >&2
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi

for tool in node npm; do
    command -v "$tool" >/dev/null || { echo "setup-browser: $tool not found; install Node.js 20 or newer with npm" >&2; exit 1; }
done
major="$(node -p 'process.versions.node.split(".")[0]')"
[ "$major" -ge 20 ] || { echo "setup-browser: Node.js $(node --version) is older than 20, which playwright-core needs" >&2; exit 1; }

dir=tests/browser
if [ ! -f "$dir/node_modules/playwright-core/package.json" ] || [ "$dir/package-lock.json" -nt "$dir/node_modules" ]; then
    echo "setup-browser: npm ci in $dir" >&2
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
fi
