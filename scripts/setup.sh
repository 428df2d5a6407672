#!/usr/bin/env bash
# Installs the system packages timbre needs on Debian 12 (run as root, or with sudo available).
# Idempotent: when everything is installed it only checks and returns.
#   libembree-dev  Embree 3 headers and library (ray tracing kernels)
#   libclang-dev   libclang for bindgen (reads the shim's header at build time)
#   openexr        exrheader, used by the tests to validate written EXR files
#   gcc            compiles the C shim (normally present with the Rust toolchain)
set -euo pipefail

packages=(libembree-dev libclang-dev openexr gcc)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}" >&2
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

for tool in cargo rustfmt cargo-clippy; do
    command -v "$tool" >/dev/null || { echo "setup: $tool not found; install the Rust toolchain (rustup) with rustfmt and clippy" >&2; exit 1; }
done
