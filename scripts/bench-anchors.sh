#!/usr/bin/env bash
# timbre against the performance anchors of ../shared/anchors (ANCHORS.md), on the same scenes,
# in one run: the bare-Embree C++ benchmark (the practical limit) and POV-Ray 3.7.
#
#   scripts/bench-anchors.sh [REPS] [WORKDIR]   (default 5 repetitions; a temporary directory)
#
# Builds timbre and the anchors, writes timbre scene files that reproduce the anchors' scenes
# exactly (LF: 108 capped cylinders r = 0.02 on the integer grid of [0,5]^3 and a chequered
# floor at y = -0.02; M: the anchor's own 1,000,000-triangle displaced sphere, exported by it
# and converted to PLY), checks timbre's pictures against bare Embree's pixel by pixel, and then
# runs REPS repetitions, each of them, for 1 and 2 threads, interleaving:
#   bare Embree's shading pass (primary ray + shadow ray + Lambert) on LF and M,
#   timbre rendering LF (floor as a plane), LF with the anchor's 2-triangle floor, and M,
#   POV-Ray on the lattice and the mesh (wall time, as `time` measures it),
#   primary rays only: bare Embree rtcIntersect1 and rtcIntersect8 on L and M, and timbre on
#     the same scenes with ambient light only (no shadow rays),
#   the BVH build of M against bare Embree's (MEDIUM quality, as timbre builds it),
#   TIM's studio at 1920x1080 (the pinhole at rest, at 0.99c, and a finite aperture with 8 spp),
#   timbre built against Embree 4 (scripts/setup-embree4.sh) on LF, M and the studio,
#   loading a 10-million-triangle binary PLY (timbre's test sphere),
# with the anchors' availability probe before and after (2.0 = two full cores). Ratios are
# taken within each repetition; the medians [min-max] are printed, and the raw figures are left
# in WORKDIR/raw.csv. The 1080p studio is timed too (Dr TIM's figures are the issue's).
set -euo pipefail
cd "$(dirname "$0")/.."
reps="${1:-5}"
shift || true
case "$reps" in
    '' | *[!0-9]* | 0) echo "usage: scripts/bench-anchors.sh [REPS (a positive integer)] [WORKDIR]" >&2; exit 2 ;;
esac
anchors="$(cd .. && pwd)/shared/anchors"
[ -d "$anchors/embree-limit" ] || { echo "no anchors at $anchors" >&2; exit 2; }
source scripts/workdir.sh "$@"
cargo build --release --locked --quiet --example image_diff
diff_images="$PWD/target/release/examples/image_diff"
# timbre built against Embree 4 too (the embree4 feature), in its own target directory.
scripts/setup-embree4.sh >/dev/null
EMBREE_DIR="$PWD/target/embree4" CARGO_TARGET_DIR="$PWD/target/embree4-build" \
    cargo build --release --locked --quiet --features embree4
timbre4="$PWD/target/embree4-build/release/timbre"

# --- the anchors -------------------------------------------------------------------------------
command -v povray >/dev/null || { apt-get update -qq && apt-get install -y -qq povray >/dev/null; }
rm -rf "$work/anchors" && cp -r "$anchors" "$work/anchors"
"$work/anchors/embree-limit/build.sh" >/dev/null
embree="$work/anchors/embree-limit/embree_limit"
probe() { "$embree" --probe; }

# --- the scenes -------------------------------------------------------------------------------
# The anchors' camera: 60 degrees across the image's outer edges (pixel pitch 2 tan 30° / W);
# timbre's angle spans the centres of the outermost columns (pitch 2 tan(a/2) / (W - 1)).
hfov=$(awk 'BEGIN { pi = atan2(0, -1); printf "%.17g", 2 * atan2(sin(pi/6) / cos(pi/6) * 1919 / 1920, 1) * 180 / pi }')
# Lambert as the anchors shade it: base x (0.1 ambient + 0.7 n.l); here diffuse = 0.7 base and an
# ambient light of 1/7. Matt surfaces have no specular term.
header() { # position view_direction light
    cat <<SCENE
studio = "none"
[render]
width = 1920
height = 1080
[camera]
position = $1
view_direction = $2
horizontal_view_angle_deg = $hfov
[[light]]
type = "ambient"
colour = [0.14285714285714285, 0.14285714285714285, 0.14285714285714285]
SCENE
    [ -n "$3" ] && printf '[[light]]\ntype = "point"\nposition = %s\ncolour = [1, 1, 1]\n' "$3"
    return 0
}
lattice() {
    for axis in 0 1 2; do for i in 0 1 2 3 4 5; do for j in 0 1 2 3 4 5; do
        local p=(0 0 0) e=(0 0 0)
        p[(axis + 1) % 3]=$i; p[(axis + 2) % 3]=$j
        e[(axis + 1) % 3]=$i; e[(axis + 2) % 3]=$j; e[axis]=5
        printf '[[object]]\nshape = { type = "cylinder", start = [%s, %s, %s], end = [%s, %s, %s], radius = 0.02 }\n' \
            "${p[@]}" "${e[@]}"
        printf 'surface = { type = "matt", colour = [0.63, 0.35, 0.07] }\n'
    done; done; done
}
# Chequer as the anchor's: floor(x) + floor(y) + floor(z) odd is 0.3, else 0.9; floor(y) = -1 on
# the floor, and on the plane (u, v) = (z, x), on the mesh (x, z), so tiles with
# floor(u) + floor(v) even are 0.3.
floor_surface='{ type = "chequerboard", surfaces = [{ type = "matt", colour = [0.21, 0.21, 0.21] }, { type = "matt", colour = [0.63, 0.63, 0.63] }] }'
lf_view=("[-6, 9, -9]" "[8.5, -7, 11.5]")
m_view=("[0.6, 1, -3.4]" "[-0.6, -1, 3.4]")
{
    header "${lf_view[@]}" "[-3, 12, -6]"
    lattice
    printf '[[object]]\nname = "floor"\nshape = { type = "plane", point = [0, -0.02, 0], normal = [0, 1, 0], u_direction = [0, 0, 1] }\nsurface = %s\n' "$floor_surface"
} >"$work/LF.toml"
{
    header "${lf_view[@]}" "[-3, 12, -6]"
    lattice
    printf '[[object]]\nname = "floor"\nshape = { type = "triangle-mesh", vertices = [[-1000, -0.02, -1000], [1000, -0.02, -1000], [1000, -0.02, 1000], [-1000, -0.02, 1000]], triangles = [[0, 2, 1], [0, 3, 2]] }\nsurface = %s\n' "$floor_surface"
} >"$work/LF-triangles.toml"
{ header "${lf_view[@]}" ""; lattice; } >"$work/L.toml"
"$embree" --export-pov "$work/mesh_m.inc" 2>/dev/null
# mesh2 (one "<x,y,z>" per line: 500,002 vertices, then 1,000,000 faces) to binary PLY with the
# anchor's f32 coordinates (printed with 9 significant digits, which round-trip).
perl -e '
    my (@v, @f, $part);
    while (<>) {
        if (/vertex_vectors/) { $part = "v"; next } if (/face_indices/) { $part = "f"; next }
        next unless /^<([^,]+),([^,]+),([^>]+)>/;
        if ($part eq "v") { push @v, pack("f<3", $1, $2, $3) } else { push @f, pack("C l<3", 3, $1, $2, $3) }
    }
    print "ply\nformat binary_little_endian 1.0\nelement vertex ", scalar(@v),
        "\nproperty float x\nproperty float y\nproperty float z\nelement face ", scalar(@f),
        "\nproperty list uchar int vertex_indices\nend_header\n", @v, @f;' "$work/mesh_m.inc" >"$work/m.ply"
mesh_object='[[object]]
shape = { type = "mesh", file = "m.ply", smooth = false }
surface = { type = "matt", colour = [0.56, 0.56, 0.56] }'
{ header "${m_view[@]}" "[5, 8, -6]"; echo "$mesh_object"; } >"$work/M.toml"
{ header "${m_view[@]}" ""; echo "$mesh_object"; } >"$work/M-primary.toml"
printf 'studio = "lattice"\n[render]\nwidth = 1920\nheight = 1080\n' >"$work/studio.toml"
# A 10-million-triangle binary PLY (timbre's test sphere) for loading.
"$timbre" generate-mesh --triangles 10000000 -o "$work/sphere-10m.ply" >/dev/null
printf 'studio = "none"\n[render]\nwidth = 64\nheight = 48\n[[object]]\nshape = { type = "mesh", file = "sphere-10m.ply" }\nsurface = { type = "matt", colour = [1, 1, 1] }\ntransform = { translate = [0, 0, 5] }\n' >"$work/sphere-10m.toml"

# --- the pictures agree -------------------------------------------------------------------------
"$embree" --shade-only --reps 1 --threads 2 --images "$work" >/dev/null 2>&1
echo "== pictures: timbre against bare Embree (8-bit linear, differences above 2/255)"
for s in LF LF-triangles M; do
    "$timbre" render -q "$work/$s.toml" -o "$work/timbre_$s.png"
    printf '   %-13s ' "$s:"
    "$diff_images" "$work/timbre_$s.png" "$work/embree_shade_${s%-triangles}.png" 2 --max-differing 999999999
done

# --- timings ----------------------------------------------------------------------------------
# timbre's summary lines: "... N rays in S s (R Mrays/s) -> FILE" and "scene: ... loaded in L s,
# BVH built in B s; ...". timbre_render records the render time as ITEM (and the load and BVH
# build times as ITEM_load and ITEM_build), or the throughput with --mrays.
timbre_render() { # item scene threads [--mrays] [timbre options...]
    local item=$1 scene=$2 threads=$3 mrays=""; shift 3
    [ "${1:-}" = --mrays ] && { mrays=1; shift; }
    local out
    out=$("${binary:-$timbre}" render "$work/$scene.toml" --threads "$threads" -o "$work/t_$item.png" "$@" 2>/dev/null)
    if [ -n "$mrays" ]; then
        record "$item" "$(sed -n 's/.* s (\([0-9.]*\) Mrays\/s).*/\1/p' <<<"$out")"
    else
        record "$item" "$(sed -n 's/.* rays in \([0-9.]*\) s .*/\1/p' <<<"$out")"
        record "${item}_load" "$(sed -n 's/.*loaded in \([0-9.]*\) s.*/\1/p' <<<"$out")"
        record "${item}_build" "$(sed -n 's/.*BVH built in \([0-9.]*\) s.*/\1/p' <<<"$out")"
    fi
}
wall() { # command... -> wall seconds (nothing, and a warning, if the command fails)
    local t0 t1
    t0=$(date +%s.%N)
    if ! "$@" >/dev/null 2>&1; then
        echo "warning: failed: $*" >&2
        return
    fi
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f", b - a }'
}
pov() { # scene threads
    povray +I"$work/anchors/povray-anchor/$1.pov" +O"$work/pov_$1.png" +W1920 +H1080 -A -D -V +FN \
        File_Gamma=1.0 +WT"$2"
}
mkdir -p /tmp/povray-anchor && ln -sf "$work/mesh_m.inc" /tmp/povray-anchor/mesh_m.inc
raw="$work/raw.csv"
echo "rep,threads,item,value" >"$raw"
record() { echo "$rep,$threads,$1,$2" >>"$raw"; }
echo "== $reps repetitions (each: 1 thread, then 2 threads), about $((reps * 90)) s"
for rep in $(seq 1 "$reps"); do
    for threads in 1 2; do
        record avail_before "$(probe)"
        "$embree" --shade-only --reps 1 --threads "$threads" 2>/dev/null |
            awk -F, '/^CSV,shade/ { print $3 "," $5 }' | while IFS=, read -r scene seconds; do
                echo "$rep,$threads,embree_shade_$scene,$seconds"
            done >>"$raw"
        for s in LF LF-triangles M L M-primary; do timbre_render "timbre_$s" "$s" "$threads"; done
        for s in LF M studio; do binary="$timbre4" timbre_render "timbre4_$s" "$s" "$threads"; done
        "$embree" --reps 1 --build-only --scenes M --qualities medium --device-threads "$threads" 2>/dev/null |
            awk -F, '/^CSV,build/ { print $6 }' | while read -r ms; do
                echo "$rep,$threads,embree_build_M,$(awk -v m="$ms" 'BEGIN { print m / 1000 }')"
            done >>"$raw"
        # Throughput of the moving and finite-aperture cameras against the pinhole at rest.
        timbre_render studio_pinhole studio "$threads" --mrays
        timbre_render studio_moving studio "$threads" --mrays --set 'camera.beta=[0,0,0.99]'
        timbre_render studio_aperture studio "$threads" --mrays --spp 8 \
            --set camera.aperture_radius=0.02 --set camera.focus_distance=15
        "$embree" --reps 1 --no-build --scenes L,M --methods 1,8 --threads "$threads" --qualities medium 2>/dev/null |
            awk -F, '/^CSV,render/ { print $3 "," $5 "," $7 }' | while IFS=, read -r scene method mrays; do
                echo "$rep,$threads,embree_rtc${method}_$scene,$(awk -v r="$mrays" 'BEGIN { print 2073600 / (r * 1e6) }')"
            done >>"$raw"
        record pov_wall_lattice "$(wall pov lattice "$threads")"
        record timbre_wall_LF "$(wall "$timbre" render -q "$work/LF.toml" --threads "$threads" -o "$work/w_LF.png")"
        record pov_wall_mesh "$(wall pov mesh "$threads")"
        record timbre_wall_M "$(wall "$timbre" render -q "$work/M.toml" --threads "$threads" -o "$work/w_M.png")"
        timbre_render timbre_studio studio "$threads"
        timbre_render sphere10m sphere-10m "$threads"
        record avail_after "$(probe)"
    done
    echo "   repetition $rep done"
done

# --- ratios -------------------------------------------------------------------------------------
awk -F, -v reps="$reps" '
    NR > 1 { v[$1, $2, $3] = $4 }
    function median(a, n,   i, j, t) {
        for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
        return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
    }
    function row(label, num, den, fmt,   t, r, n, a, lo, hi) {
        printf "| %s |", label
        for (t = 1; t <= 2; t++) {
            n = 0; delete a
            for (r = 1; r <= reps; r++) if (v[r, t, num] > 0 && v[r, t, den] > 0) a[++n] = v[r, t, num] / v[r, t, den]
            if (n == 0) { printf " – |"; continue }
            lo = hi = a[1]
            for (r = 1; r <= n; r++) { if (a[r] < lo) lo = a[r]; if (a[r] > hi) hi = a[r] }
            printf " " fmt " [" fmt "–" fmt "] |", median(a, n), lo, hi
        }
        printf "\n"
    }
    function time(label, item, scale, unit,   t, r, n, a) {
        printf "| %s |", label
        for (t = 1; t <= 2; t++) {
            n = 0; delete a
            for (r = 1; r <= reps; r++) if (v[r, t, item] > 0) a[++n] = v[r, t, item] * scale
            printf n ? " %.1f " unit " |" : " – |", median(a, n)
        }
        printf "\n"
    }
    function avail(   r, n, a, m) {
        n = 0
        for (r = 1; r <= reps; r++) { m = v[r, 2, "avail_before"]; if (v[r, 2, "avail_after"] < m) m = v[r, 2, "avail_after"]; a[++n] = m }
        return median(a, n)
    }
    END {
        printf "\n2-core availability during the 2-thread items (median of the reps, min of before and after): %.2f\n\n", avail()
        print "| same-run ratio, median [min–max] of " reps " | 1 thread | 2 threads |"
        print "|---|---|---|"
        row("timbre render / bare-Embree shading pass, LF", "timbre_LF", "embree_shade_LF", "%.2f")
        row("timbre render / bare-Embree shading pass, M", "timbre_M", "embree_shade_M", "%.2f")
        row("LF with the anchor'"'"'s 2-triangle floor / bare Embree LF", "timbre_LF-triangles", "embree_shade_LF", "%.2f")
        row("POV-Ray wall / timbre wall, LF", "pov_wall_lattice", "timbre_wall_LF", "%.1f")
        row("POV-Ray wall / timbre wall, M", "pov_wall_mesh", "timbre_wall_M", "%.1f")
        row("primary rays only, timbre / Embree rtcIntersect1, L", "timbre_L", "embree_rtc1_L", "%.2f")
        row("primary rays only, timbre / Embree rtcIntersect1, M", "timbre_M-primary", "embree_rtc1_M", "%.2f")
        row("primary rays only, timbre / Embree rtcIntersect8, L", "timbre_L", "embree_rtc8_L", "%.2f")
        row("primary rays only, timbre / Embree rtcIntersect8, M", "timbre_M-primary", "embree_rtc8_M", "%.2f")
        row("timbre with Embree 4 / bare Embree 3 shading pass, LF", "timbre4_LF", "embree_shade_LF", "%.2f")
        row("timbre with Embree 4 / bare Embree 3 shading pass, M", "timbre4_M", "embree_shade_M", "%.2f")
        row("timbre with Embree 4 / with Embree 3, studio", "timbre4_studio", "timbre_studio", "%.2f")
        row("camera at 0.99c / pinhole at rest, studio throughput", "studio_moving", "studio_pinhole", "%.2f")
        row("finite aperture (8 spp) / pinhole, studio throughput", "studio_aperture", "studio_pinhole", "%.2f")
        row("timbre BVH build / bare Embree build (MEDIUM), M", "timbre_M_build", "embree_build_M", "%.2f")
        print ""
        print "| time per frame, median of " reps " | 1 thread | 2 threads |"
        print "|---|---|---|"
        time("bare Embree shading pass, LF", "embree_shade_LF", 1000, "ms")
        time("timbre, LF", "timbre_LF", 1000, "ms")
        time("timbre, LF with 2 floor triangles", "timbre_LF-triangles", 1000, "ms")
        time("bare Embree shading pass, M", "embree_shade_M", 1000, "ms")
        time("timbre, M", "timbre_M", 1000, "ms")
        time("bare Embree rtcIntersect1, L", "embree_rtc1_L", 1000, "ms")
        time("bare Embree rtcIntersect8, L", "embree_rtc8_L", 1000, "ms")
        time("timbre, primary rays only, L", "timbre_L", 1000, "ms")
        time("bare Embree rtcIntersect1, M", "embree_rtc1_M", 1000, "ms")
        time("bare Embree rtcIntersect8, M", "embree_rtc8_M", 1000, "ms")
        time("timbre, primary rays only, M", "timbre_M-primary", 1000, "ms")
        time("POV-Ray wall, lattice", "pov_wall_lattice", 1, "s")
        time("timbre wall, LF", "timbre_wall_LF", 1, "s")
        time("POV-Ray wall, mesh", "pov_wall_mesh", 1, "s")
        time("timbre wall, M", "timbre_wall_M", 1, "s")
        time("timbre, the 1080p studio (Dr TIM: 23.9 s / 13.2 s)", "timbre_studio", 1000, "ms")
        time("timbre with Embree 4: LF", "timbre4_LF", 1000, "ms")
        time("timbre with Embree 4: M", "timbre4_M", 1000, "ms")
        time("timbre with Embree 4: studio", "timbre4_studio", 1000, "ms")
        time("timbre, M: loading the binary PLY", "timbre_M_load", 1000, "ms")
        time("timbre, M: BVH build", "timbre_M_build", 1000, "ms")
        time("bare Embree, M: BVH build (MEDIUM)", "embree_build_M", 1000, "ms")
        time("timbre, 10M-triangle binary PLY: loading", "sphere10m_load", 1000, "ms")
        time("timbre, 10M-triangle binary PLY: BVH build", "sphere10m_build", 1000, "ms")
    }' "$raw"
echo
echo "raw figures: $raw"
