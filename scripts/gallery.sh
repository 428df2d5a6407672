#!/usr/bin/env bash
# Renders the README's gallery: each of the Dr TIM paper's figures that scenes/fig*.toml
# reproduces, at half size (320 x 240) with the samples its scene sets, into docs/gallery/, and
# writes docs/gallery/README.md, a table of them with their scene files and titles (the first
# sentence of each scene's opening comment). Run from anywhere after building (cargo build --release); the
# pictures are committed, so run it again when a figure's scene or the renderer changes.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
timbre=${TIMBRE:-$root/target/release/timbre}
out=$root/docs/gallery
mkdir -p "$out"
index=$out/README.md
{
    echo "# Gallery: the Dr TIM paper's figures"
    echo
    echo "Made by \`scripts/gallery.sh\` from the scenes in \`scenes/\` (320 x 240, the samples each"
    echo "scene sets); \`timbre render scenes/NAME.toml -o NAME.png\` makes each at full size."
    echo
    echo "| figure | scene |"
    echo "| ------ | ----- |"
} > "$index"
for scene in "$root"/scenes/fig*.toml; do
    name=$(basename "$scene" .toml)
    "$timbre" render "$scene" -q --width 320 -o "$out/$name.png"
    # The first sentence of the scene's opening comment.
    title=$(awk '/^#/ { sub(/^# */, ""); if ($0 == "") exit; printf "%s ", $0; next } { exit }' "$scene" \
        | sed -E 's/(Fig|e\.g|i\.e)\. /\1.~/g; s/\. .*/./; s/~/ /g; s/ +$//')
    echo "| ![$name]($name.png) | \`scenes/$name.toml\`: $title |" >> "$index"
done
echo "gallery: $(ls "$out"/*.png | wc -l) pictures in $out"
