#!/usr/bin/env bash
# Checks that two builds of timbre render every example scene (scenes/*.toml and
# scenes/research/*.toml) to the same bytes: PNG (its pixels), and OpenEXR with every AOV. For refactors
# that must not change a picture; compare against a build of the commit before, e.g.
#   git worktree add ../before HEAD~ && (cd ../before && cargo build --release)
#   scripts/same-renders.sh ../before/target/release/timbre target/release/timbre
#
# Usage: scripts/same-renders.sh OLD NEW [--full] [SCENE...]
#   --full   at each scene's own size and samples (default: 96x72, 2 samples per pixel)
# Prints one line per scene and exits non-zero if any differs. OpenEXR files are compared byte
# for byte but for the scene fingerprint in their header (timbre.scene).
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: scripts/same-renders.sh OLD NEW [--full] [SCENE...]" >&2; exit 2; }
old=$(realpath "$1") new=$(realpath "$2")
shift 2
size=(--width 96 --height 72 --spp 2)
if [ "${1:-}" = "--full" ]; then
    size=()
    shift
fi
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/*.toml scenes/research/*.toml)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
differ=0
# Replaces a PNG file by its IHDR and IDAT chunks only.
pixels() {
    python3 - "$1" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
at, kept = 8, b""
while at < len(data):
    n, kind = struct.unpack(">I4s", data[at:at + 8])
    if kind in (b"IHDR", b"IDAT"):
        kept += data[at:at + 12 + n]
    at += 12 + n
open(sys.argv[1], "wb").write(kept)
PY
}
# Blanks the value of an OpenEXR file's timbre.scene attribute: a fingerprint of the scene as
# read, which changes when a build reads scenes into other structures, not with the picture.
provenance() {
    python3 - "$1" <<'PY'
import struct, sys
data = bytearray(open(sys.argv[1], "rb").read())
name = b"timbre.scene\0string\0"
at = data.find(name)
if at >= 0:
    at += len(name)
    (n,) = struct.unpack("<i", data[at:at + 4])
    data[at + 4:at + 4 + n] = b"0" * n
open(sys.argv[1], "wb").write(data)
PY
}
for scene in "${scenes[@]}"; do
    [ -f "$scene" ] || continue
    outcome=same
    for build in old new; do
        binary=$old
        [ $build = new ] && binary=$new
        mkdir -p "$work/$build"
        # Every file a render writes (stereo renders may write several) lands in the folder;
        # the EXR with every AOV, or without for stereo views, which have none.
        render() { "$binary" render "$scene" "${size[@]}" --quiet "$@" >"$work/$build.log" 2>&1; }
        render -o "$work/$build/picture.png" &&
            { render -o "$work/$build/picture.exr" --aov depth,normal,object ||
                { grep -q 'single views only' "$work/$build.log" &&
                    render -o "$work/$build/picture.exr"; }; } ||
            outcome="a render failed: $(tail -n 1 "$work/$build.log")"
    done
    count=$(find "$work/new" -type f | wc -l)
    # PNGs are compared by their pixels (IHDR and IDAT chunks): builds may write other chunks
    # (provenance, colour chunks).
    for png in "$work"/old/*.png "$work"/new/*.png; do
        [ -f "$png" ] && pixels "$png"
    done
    for exr in "$work"/old/*.exr "$work"/new/*.exr; do
        [ -f "$exr" ] && provenance "$exr"
    done
    if [ "$outcome" = same ] && ! diff -r -q "$work/old" "$work/new" >/dev/null; then
        outcome="DIFFERS: $(diff -r -q "$work/old" "$work/new" | head -n 3 | tr '\n' ' ' || true)"
    fi
    [ "$outcome" = same ] || differ=1
    echo "$scene: $outcome ($count files)"
    rm -rf "$work/old" "$work/new"
done
exit $differ
