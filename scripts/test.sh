#!/usr/bin/env bash
# The whole test suite, as the README's quick start and CI run it.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --all-targets --release --locked -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --locked
cargo test --release --locked
# The Slurm scripts of cluster/slurm/ on a real one-node Slurm cluster (installs slurm-wlm and
# munge if missing); it uses target/release/timbre, which `cargo test --release` has just built.
scripts/slurm-e2e.sh
# A short fuzz smoke run, 20 s a target from the committed corpus (docs/RELIABILITY.md);
# installs cargo-fuzz if missing.
scripts/fuzz.sh 20
