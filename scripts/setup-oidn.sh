#!/usr/bin/env bash
# Installs Intel Open Image Denoise (OIDN) for building timbre with `--features denoise`.
# Debian 12 does not package OIDN, so this takes it from PyPI's pyoidn wheel (2.5.1.0,
# manylinux2014 x86_64), which ships Intel's OIDN 2.5.1 shared libraries and the oneTBB they
# need, and lays out the CPU device's libraries as an OIDN_DIR for the oidn crate's build:
#   DIR/lib/libOpenImageDenoise.so{,.2,.2.5.1}, libOpenImageDenoise_core.so.2.5.1,
#   DIR/lib/libOpenImageDenoise_device_cpu.so.2.5.1, libtbb.so.12
# (found by each other through their rpath $ORIGIN/../lib; the GPU devices are left out).
# Usage: scripts/setup-oidn.sh [DIR]      (DIR defaults to target/oidn of this repository)
# then:  OIDN_DIR=DIR cargo build --release --features denoise
# (build.rs puts DIR/lib in the binaries' rpath, so they run without LD_LIBRARY_PATH).
# Idempotent: when DIR holds this exact install (its stamp file says so) it returns at once.
# Needs python3 with pip (installed from Debian's packages when missing) and PyPI; nothing is
# installed into the system's Python or into the repository.
set -euo pipefail

repo="$(cd "$(dirname "$0")/.." && pwd)"
dir="${1:-$repo/target/oidn}"
mkdir -p "$dir"
dir="$(cd "$dir" && pwd)"

wheel_version="2.5.1.0"
wheel_name="pyoidn-$wheel_version-py3-none-manylinux2014_x86_64.whl"
wheel_sha256="32ad13368f8de1ef63001942ad05b02a00cd732d1206d97f352d3a3f606d823e"
stamp="$dir/.timbre-oidn"
stamp_text="pyoidn $wheel_version $wheel_sha256"
libs=(libOpenImageDenoise.so.2.5.1 libOpenImageDenoise_core.so.2.5.1
    libOpenImageDenoise_device_cpu.so.2.5.1 libtbb.so.12)

installed() {
    [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$stamp_text" ] && [ -e "$dir/lib/libOpenImageDenoise.so" ]
}
if installed; then
    exit 0
fi

if [ "$(uname -m)" != "x86_64" ]; then
    echo "setup-oidn: the pyoidn wheel used here is for x86_64 only (this is $(uname -m));" \
        "install OIDN another way and point OIDN_DIR at it" >&2
    exit 1
fi
if ! python3 -m pip --version >/dev/null 2>&1; then
    echo "setup-oidn: installing python3-pip" >&2
    "$repo/scripts/apt-install.sh" python3 python3-pip
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "setup-oidn: downloading pyoidn $wheel_version from PyPI" >&2
python3 -m pip download --quiet --disable-pip-version-check --no-deps --only-binary=:all: \
    --platform manylinux2014_x86_64 "pyoidn==$wheel_version" -d "$work/wheel"
wheel="$work/wheel/$wheel_name"
[ -f "$wheel" ] || { echo "setup-oidn: pip did not fetch $wheel_name (got: $(ls "$work/wheel"))" >&2; exit 1; }
have_sha="$(sha256sum "$wheel" | awk '{print $1}')"
if [ "$have_sha" != "$wheel_sha256" ]; then
    echo "setup-oidn: $wheel_name has sha256 $have_sha, expected $wheel_sha256" >&2
    exit 1
fi
# Only the CPU device's libraries (the wheel's 170 MB are mostly GPU devices and SYCL).
python3 - "$wheel" "$work/lib" "${libs[@]}" <<'PYTHON'
import os, sys, zipfile
wheel, out, names = sys.argv[1], sys.argv[2], sys.argv[3:]
os.makedirs(out)
with zipfile.ZipFile(wheel) as z:
    for name in names:
        with z.open(f"pyoidn/oidn/lib/{name}") as f, open(os.path.join(out, name), "wb") as o:
            o.write(f.read())
PYTHON

# Lay out the new install beside the old one and swap them, so that an interrupted run leaves
# either the old install or none (the stamp is written last).
new="$dir/.new"
rm -rf "$new"
mkdir -p "$new"
mv "$work/lib" "$new/lib"
ln -s libOpenImageDenoise.so.2.5.1 "$new/lib/libOpenImageDenoise.so.2"
ln -s libOpenImageDenoise.so.2 "$new/lib/libOpenImageDenoise.so"
rm -rf "$dir/lib" "$stamp"
mv "$new/lib" "$dir/"
rmdir "$new"
echo "$stamp_text" >"$stamp"
echo "setup-oidn: OIDN installed in $dir (build with OIDN_DIR=$dir cargo build --release --features denoise)" >&2
