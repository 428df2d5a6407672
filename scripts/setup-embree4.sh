#!/usr/bin/env bash
# Installs Embree 4 beside Debian 12's Embree 3, for building timbre with `--features embree4`.
# Debian 12 packages only Embree 3, so this takes Embree 4 from the package registries:
#   the library  PyPI's embreex wheel (4.4.0.post1, manylinux x86_64) ships Intel's Embree 4.4
#                shared library and the oneTBB it needs (libembree4-<hash>.so.4, libtbb-<hash>.so.12,
#                found by each other through $ORIGIN); they load on Debian 12's glibc
#   the headers  the crates.io crate embree4-sys (0.0.12, downloaded as a file; nothing of it is
#                built) ships Embree 4's C headers
#                (lib/embree4/rtcore*.h, Embree 4.2's; the shim copes with 4.2 headers over a
#                4.4 library, see vendor-headers/shim.c)
# and lays them out as an EMBREE_DIR for build.rs:
#   DIR/include/embree4/rtcore*.h
#   DIR/lib/libembree4.so -> libembree4-<hash>.so.4 (the library's SONAME), libtbb-<hash>.so.12
# Usage: scripts/setup-embree4.sh [DIR]      (DIR defaults to target/embree4 of this repository)
# then:  EMBREE_DIR=DIR cargo build --release --features embree4
# Idempotent: when DIR holds this exact install (its stamp file says so) it only checks and
# returns. Needs python3 with pip (installed from Debian's packages when missing) and the
# registries (PyPI, crates.io); nothing is installed into the system's Python or into the
# repository, and no cache of cargo's or pip's is needed.
set -euo pipefail

repo="$(cd "$(dirname "$0")/.." && pwd)"
dir="${1:-$repo/target/embree4}"
mkdir -p "$dir"
dir="$(cd "$dir" && pwd)"

wheel_version="4.4.0.post1"
# The wheel for CPython 3.11 on manylinux_2_28 x86_64, pinned by its digest (the libraries in
# the wheels for other Python versions are the same build, but their file names may differ).
wheel_name="embreex-$wheel_version-cp311-cp311-manylinux_2_27_x86_64.manylinux_2_28_x86_64.whl"
wheel_sha256="2cd0f7d5c6342e6247e31f700761689cae7829454d8c6de0c41e62124a023e1f"
headers_crate="embree4-sys"
headers_version="0.0.12"
headers_url="https://static.crates.io/crates/$headers_crate/$headers_crate-$headers_version.crate"
headers_sha256="a1c23ca437f91a52068a03088b80395115c87a669874e54120f4552f1bedaf67"
stamp="$dir/.timbre-embree4"
stamp_text="embreex $wheel_version $wheel_sha256; $headers_crate $headers_version $headers_sha256"

installed() {
    [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$stamp_text" ] &&
        [ -f "$dir/include/embree4/rtcore.h" ] && [ -e "$dir/lib/libembree4.so" ]
}
if installed; then
    exit 0
fi

if [ "$(uname -m)" != "x86_64" ]; then
    echo "setup-embree4: the embreex wheel used here is for x86_64 only (this is $(uname -m));" \
        "install Embree 4 another way and point EMBREE_DIR at it" >&2
    exit 1
fi

# pip, only to download the wheel (nothing is installed with it).
if ! python3 -m pip --version >/dev/null 2>&1; then
    echo "setup-embree4: installing python3-pip" >&2
    "$repo/scripts/apt-install.sh" python3 python3-pip
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "setup-embree4: downloading embreex $wheel_version from PyPI" >&2
python3 -m pip download --quiet --disable-pip-version-check --no-deps --only-binary=:all: \
    --platform manylinux_2_28_x86_64 --python-version 3.11 --implementation cp --abi cp311 \
    "embreex==$wheel_version" -d "$work/wheel"
wheel="$work/wheel/$wheel_name"
[ -f "$wheel" ] || { echo "setup-embree4: pip did not fetch $wheel_name (got: $(ls "$work/wheel"))" >&2; exit 1; }
have_sha="$(sha256sum "$wheel" | awk '{print $1}')"
if [ "$have_sha" != "$wheel_sha256" ]; then
    echo "setup-embree4: $wheel_name has sha256 $have_sha, expected $wheel_sha256" >&2
    exit 1
fi
python3 -m zipfile -e "$wheel" "$work/unpacked"
libs="$work/unpacked/embreex.libs"
embree_lib="$(cd "$libs" && ls libembree4*.so.4 2>/dev/null | head -n 1)"
tbb_lib="$(cd "$libs" && ls libtbb*.so.12 2>/dev/null | head -n 1)"
if [ -z "$embree_lib" ] || [ -z "$tbb_lib" ]; then
    echo "setup-embree4: no libembree4*.so.4 and libtbb*.so.12 in the wheel's embreex.libs/" >&2
    exit 1
fi

echo "setup-embree4: downloading the headers of $headers_crate $headers_version from crates.io" >&2
# The .crate file (a gzipped tar) from crates.io's download address, pinned by its digest; only
# its headers are used, so none of its dependencies is resolved or fetched (cargo would resolve
# them for every platform, and need from cargo's cache what a fresh machine lacks).
crate_file="$work/$headers_crate-$headers_version.crate"
python3 - "$headers_url" "$crate_file" <<'PYTHON'
import sys, urllib.request
with urllib.request.urlopen(sys.argv[1], timeout=120) as response, open(sys.argv[2], "wb") as out:
    out.write(response.read())
PYTHON
have_sha="$(sha256sum "$crate_file" | awk '{print $1}')"
if [ "$have_sha" != "$headers_sha256" ]; then
    echo "setup-embree4: $headers_url has sha256 $have_sha, expected $headers_sha256" >&2
    exit 1
fi
mkdir -p "$work/crate"
tar -xzf "$crate_file" -C "$work/crate"
headers="$work/crate/$headers_crate-$headers_version/lib/embree4"
[ -f "$headers/rtcore.h" ] || { echo "setup-embree4: no lib/embree4/rtcore.h in $headers_crate $headers_version" >&2; exit 1; }

# Lay out the new install beside the old one and swap them, so that an interrupted run leaves
# either the old install or none (the stamp is written last).
new="$dir/.new"
rm -rf "$new"
mkdir -p "$new/include/embree4" "$new/lib"
cp "$headers"/*.h "$new/include/embree4/"
cp "$libs/$embree_lib" "$libs/$tbb_lib" "$new/lib/"
ln -s "$embree_lib" "$new/lib/libembree4.so"
[ "$embree_lib" = "libembree4.so.4" ] || ln -s "$embree_lib" "$new/lib/libembree4.so.4"
rm -rf "$dir/include" "$dir/lib" "$stamp"
mv "$new/include" "$new/lib" "$dir/"
rmdir "$new"
echo "$stamp_text" >"$stamp"
echo "setup-embree4: Embree 4 installed in $dir (build with EMBREE_DIR=$dir cargo build --release --features embree4)" >&2
