#!/usr/bin/env bash
# The memory and time bounds of docs/RELIABILITY.md: makes each hostile or very large input and
# prints what `timbre check` answered (its exit code and the start of its message), its wall
# time and its peak resident memory.
#
#   scripts/hostile-bounds.sh [WORKDIR]    (default: a temporary directory, removed afterwards)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/workdir.sh "$@"
cd "$work"

# `measure LABEL [--cap BYTES] ARGS...`: one row of the table (BYTES: an address-space limit).
measure() {
    local label=$1
    shift
    local limit=()
    if [ "$1" = "--cap" ]; then
        limit=(prlimit "--as=$2")
        shift 2
    fi
    local out code
    out=$( { /usr/bin/time -f "TIME %e %M" "${limit[@]}" "$timbre" "$@" >/dev/null; } 2>&1) && code=0 || code=$?
    local message times
    message=$(grep -v '^TIME' <<<"$out" | head -n 1 | cut -c1-90 || true)
    times=$(grep '^TIME' <<<"$out" | tail -n 1)
    read -r _ wall kib <<<"$times"
    printf '| %s | %s | %s s | %s MiB | %s |\n' "$label" "$code" "$wall" "$((kib / 1024))" "${message:-OK}"
}

python3 - <<'PY'
import random
random.seed(1)
def spheres(path, n):
    with open(path, "w") as f:
        f.write('studio = "empty"\n')
        for i in range(n):
            x, y, z = (random.uniform(-5, 5) for _ in range(3))
            f.write(f'[[object]]\nname = "sphere-{i}"\nshape = {{ type = "sphere", '
                    f'centre = [{x:.4f}, {y:.4f}, {z + 10:.4f}], radius = 0.01 }}\n'
                    f'surface = {{ type = "coloured", diffuse = [0.1, 0.2, 0.3] }}\n')
spheres("million.toml", 1_000_000)
spheres("million-and-one.toml", 1_000_001)
sphere = ('[[object]]\nshape = { type = "sphere", centre = [0, 0, 5], radius = 0.01 }\n'
          'surface = { type = "mirror" }\n')
open("copies.toml", "w").write(
    sphere + 'array = { vectors = [[0.1, 0, 0], [0, 0.1, 0]], counts = [10000, 1000] }\n')
for level in range(20):
    open(f"diamond{level}.toml", "w").write(f'[[include]]\nfile = "diamond{level + 1}.toml"\n' * 2)
open("diamond20.toml", "w").write(sphere)
for level in range(2000):
    open(f"chain{level}.toml", "w").write(f'[[include]]\nfile = "chain{level + 1}.toml"\n')
open("chain2000.toml", "w").write(sphere)
open("dense.toml", "w").write('studio = "empty"\nx = [' + '1,' * 25_000_000 + '1]\n')
open("big.toml", "w").write("# " + "x" * 9_000_000 + "\n")
open("includes-1-gib.toml", "w").write('[[include]]\nfile = "big.toml"\n' * 130)
open("bomb.ply", "wb").write(
    b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
    b"property float y\nproperty float z\nelement face 4000000000\n"
    b"property list uchar int vertex_indices\nend_header\n\0\0\0\0")
open("ply-bomb.toml", "w").write(
    '[[object]]\nshape = { type = "mesh", file = "bomb.ply" }\nsurface = { type = "mirror" }\n')
PY
rm -f fifo.toml && mkfifo fifo.toml

echo "| input | exit | wall | peak RSS | message |"
echo "|---|---|---|---|---|"
measure "10⁶ spheres (172 MB)" check million.toml
measure "10⁶ spheres, two --set" check million.toml --set render.width=10 --set object.999999.shape.radius=2
measure "10⁶ + 1 spheres" check million-and-one.toml
measure "10⁷ array copies (150 B)" check copies.toml
measure "10⁷ array copies, 4 GB cap" --cap 4000000000 check copies.toml
measure "include diamond, 2²⁰ copies" check diamond0.toml
measure "include chain, 2000 deep" check chain0.toml
measure "130 × 9 MB includes" check includes-1-gib.toml
measure "50 MB inline array" check dense.toml
measure "PLY header: 4·10⁹ vertices" check ply-bomb.toml
measure "FIFO as scene" check fifo.toml
measure "/dev/zero as scene" check /dev/zero
measure "--threads 100000" render --threads 100000 -o x.png
