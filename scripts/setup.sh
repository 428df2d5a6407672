#!/usr/bin/env bash
# Installs the system packages timbre needs on Debian 12 (run as root, or with sudo available).
# Idempotent: when everything is installed it only checks and returns.
#   libembree-dev  Embree 3 headers and library (ray tracing kernels)
#   libclang-dev   libclang for bindgen (reads the shim's header at build time)
#   openexr        exrheader, used by the tests to validate written EXR files
#   gcc            compiles the C shim (normally present with the Rust toolchain)
#   g++            compiles libFuzzer for the fuzz smoke run of the tests (scripts/fuzz.sh)
# and checks that rustc is at least the rust-version declared in Cargo.toml.
set -euo pipefail

packages=(libembree-dev libclang-dev openexr gcc g++)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}" >&2
    "$(dirname "$0")/apt-install.sh" "${missing[@]}"
fi

for tool in rustc cargo rustfmt cargo-clippy; do
    command -v "$tool" >/dev/null || { echo "setup: $tool not found; install the Rust toolchain (rustup) with rustfmt and clippy" >&2; exit 1; }
done

# The toolchain must be at least Cargo.toml's rust-version, the one statement of the minimum.
manifest="$(dirname "$0")/../Cargo.toml"
required="$(sed -n 's/^rust-version *= *"\([0-9.]*\)".*/\1/p' "$manifest")"
[ -n "$required" ] || { echo "setup: no rust-version in $manifest" >&2; exit 1; }
have="$(rustc --version | awk '{print $2}')"
if [ "$(printf '%s\n' "$required" "$have" | sort -V | head -n 1)" != "$required" ]; then
    echo "setup: rustc $have is older than $required, the rust-version in Cargo.toml; update the toolchain (rustup update stable)" >&2
    exit 1
fi
