#!/usr/bin/env bash
# The whole test suite, as the README's quick start and CI run it.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# The Python environment (target/python): its Python builds the Python package's native module
# (python/), which clippy checks with the rest of the workspace.
venv="$(scripts/setup-python.sh)"
export PYO3_PYTHON="$venv/bin/python"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --release --locked -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --locked
# ffmpeg (Debian's package) encodes the movies of tests/movies.rs (timbre render --encode).
command -v ffmpeg >/dev/null || scripts/apt-install.sh ffmpeg
cargo test --release --locked
# `timbre serve` end to end in headless Chromium (tests/browser/, against target/release/timbre,
# which `cargo test --release` has just built); installs chromium and playwright-core if missing.
scripts/test-browser.sh
# The Python package (python/tests/, pytest): `pip install .`, arrays against target/release/timbre,
# the wheel with its bundled libraries in a fresh environment, the example notebooks and the
# dask example (scripts/test-python.sh).
scripts/test-python.sh
# The Slurm scripts of cluster/slurm/ on a real one-node Slurm cluster (installs slurm-wlm and
# munge if missing); it uses target/release/timbre, which `cargo test --release` has just built.
scripts/slurm-e2e.sh
# A short fuzz smoke run, 20 s a target from the committed corpus (docs/RELIABILITY.md);
# installs cargo-fuzz if missing.
scripts/fuzz.sh 20
# The same suite against Embree 4 (the `embree4` feature) beside Debian's Embree 3, and with
# denoising (the `denoise` feature, tests/denoise.rs): installs Embree 4.4 into target/embree4
# and Intel Open Image Denoise 2.5 into target/oidn from the package registries
# (scripts/setup-embree4.sh, scripts/setup-oidn.sh), then clippy and every test with both
# features. Only timbre itself is built again (the dependencies' builds are shared); the last
# line puts the Embree 3 build of target/release/timbre back.
embree4="$PWD/target/embree4"
oidn="$PWD/target/oidn"
scripts/setup-embree4.sh "$embree4"
scripts/setup-oidn.sh "$oidn"
export EMBREE_DIR="$embree4" OIDN_DIR="$oidn"
cargo clippy --all-targets --release --locked --features embree4,denoise -- -D warnings
cargo test --release --locked --features embree4,denoise
unset EMBREE_DIR OIDN_DIR
cargo build --release --locked --quiet
