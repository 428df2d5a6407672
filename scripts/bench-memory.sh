#!/usr/bin/env bash
# Peak memory and time of studio renders from 1024² to 65536² (or up to MAX_SIDE), each under an
# address-space cap of 2 GB, written as PNG into a temporary directory (deleted afterwards).
# Prints a Markdown table for docs/PERFORMANCE.md. The 65536² render takes about 10 minutes
# on 2 cores. Usage: scripts/bench-memory.sh [MAX_SIDE] [THREADS]
set -euo pipefail
cd "$(dirname "$0")/.."
max=${1:-65536}
threads=${2:-$(nproc)}
cargo build --release --locked -q
timbre=$PWD/target/release/timbre
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| image | pixels | peak RSS | wall time | PNG size |"
echo "|---|---|---|---|---|"
for side in 1024 2048 4096 8192 16384 32768 65536; do
    [ "$side" -le "$max" ] || break
    start=$(date +%s.%N)
    line=$(prlimit --as=2000000000 "$timbre" render -o "$out/studio.png" \
        --width "$side" --height "$side" --threads "$threads" | grep -o 'peak memory [0-9]* MiB')
    end=$(date +%s.%N)
    size=$(stat -c %s "$out/studio.png")
    rm -f "$out/studio.png"
    awk -v side="$side" -v rss="${line#peak memory }" -v t="$(awk "BEGIN {print $end - $start}")" \
        -v size="$size" 'BEGIN { printf "| %d² | %.3g | %s | %.1f s | %.1f MB |\n", side, side * side, rss, t, size / 1e6 }'
done
