#!/usr/bin/env bash
# The tests of the Python package (python/tests/, pytest): installs the package with
# `pip install .` (the README's command) into the environment of scripts/setup-python.sh, then
# runs pytest. The tests compare with target/release/timbre (build it first: `cargo build
# --release`; scripts/test.sh runs this after `cargo test --release`), build the wheel with its
# bundled libraries and install it into a fresh environment, and run the example notebooks.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="$(scripts/setup-python.sh)"
[ -x target/release/timbre ] || { echo "test-python: target/release/timbre not found; run cargo build --release" >&2; exit 1; }
# The native module is built for this environment's Python.
export PYO3_PYTHON="$venv/bin/python"
# The package was once installed as the distribution `timbre` (now `timbre-optics`): an install
# of that name is removed, or its native module for this Python would shadow the new abi3 one.
if "$venv/bin/python" -m pip show --quiet timbre >/dev/null 2>&1; then
    "$venv/bin/python" -m pip uninstall --quiet --yes timbre
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps .
# From the tests' folder, so that `import timbre` finds the installed package, not python/timbre.
(cd python/tests && TIMBRE="$PWD/../../target/release/timbre" "$venv/bin/python" -m pytest -q -p no:cacheprovider)
