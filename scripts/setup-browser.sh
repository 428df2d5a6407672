#!/usr/bin/env bash
# Installs what the browser tests of `timbre serve` (tests/browser/, run by
# scripts/test-browser.sh) need, on Debian 12 (run as root, or with sudo available):
#   chromium         Debian's Chromium, run headless (/usr/bin/chromium); Playwright downloads
#                    no browser of its own
#   playwright-core  from npm, the exact version of tests/browser/package-lock.json (`npm ci`
#                    into tests/browser/node_modules, again whenever the lock file is newer)
#   nodejs, npm      Debian's, if there is no Node.js (Debian 12's is 18, which
#                    playwright-core 1.61 supports)
# Idempotent: when everything is installed it only checks and returns.
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
[ -x /usr/bin/chromium ] || missing+=(chromium)
command -v node >/dev/null || missing+=(nodejs)
command -v npm >/dev/null || missing+=(npm)
if [ "${#missing[@]}" -gt 0 ]; then
    echo "setup-browser: installing ${missing[*]}" >&2
    scripts/apt-install.sh "${missing[@]}"
fi

major="$(node -p 'process.versions.node.split(".")[0]')"
[ "$major" -ge 18 ] || { echo "setup-browser: Node.js $(node --version) is older than 18, which playwright-core needs" >&2; exit 1; }

dir=tests/browser
if [ ! -f "$dir/node_modules/playwright-core/package.json" ] || [ "$dir/package-lock.json" -nt "$dir/node_modules" ]; then
    echo "setup-browser: npm ci in $dir" >&2
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
fi
