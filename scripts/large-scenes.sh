#!/usr/bin/env bash
# The large-scene benchmark of docs/PERFORMANCE.md: generates bumpy-sphere meshes of 1 and 10
# million triangles as binary PLY, checks them, and renders each in front of TIM's studio at
# 1920x1080. The CLI's summary lines give load time, BVH build time and peak memory.
#
#   scripts/large-scenes.sh [WORKDIR]      (default: a temporary directory, removed afterwards)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/workdir.sh "$@"
for n in 1000000 10000000; do
    "$timbre" generate-mesh --triangles "$n" -o "$work/sphere-$n.ply"
    cat > "$work/sphere-$n.toml" <<SCENE
studio = "lattice"
[render]
width = 1920
height = 1080
[[object]]
name = "sphere-$n"
shape = { type = "mesh", file = "sphere-$n.ply" }
surface = { type = "shiny", colour = [0.9, 0.3, 0.2] }
transform = { scale = 0.6, translate = [0, 0, 5] }
SCENE
    echo "== $n triangles: check (load only)"
    /usr/bin/time -f "   wall %e s, peak RSS %M KiB" "$timbre" check "$work/sphere-$n.toml" | grep -E "triangles"
    echo "== $n triangles: render 1920x1080"
    "$timbre" render "$work/sphere-$n.toml" -o "$work/sphere-$n.png"
done
