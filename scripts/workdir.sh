# Sourced by the benchmark scripts, from the repository root, with their arguments: builds
# timbre, sets $timbre to it, and makes the work directory $work (the first argument, or a
# temporary directory removed on exit). Installs GNU time (/usr/bin/time, which the scripts
# measure peak memory with) when missing.
[ -x /usr/bin/time ] || scripts/apt-install.sh time
cargo build --release --locked --quiet
timbre="$PWD/target/release/timbre"
work="${1:-}"
if [ -z "$work" ]; then
    work="$(mktemp -d)"
    trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"
