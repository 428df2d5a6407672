#!/usr/bin/env bash
# Coverage-guided fuzzing of what timbre reads (docs/RELIABILITY.md): the targets of fuzz/
# (scene files with includes and meshes, OBJ, PLY, `--set` values) under libFuzzer, through
# cargo-fuzz on the stable toolchain (no sanitizer: safe Rust needs none; a panic, an abort, a
# hang (a run past 60 s, far above any honest one on a busy machine) or more than 2 GiB is a
# finding).
#
#   scripts/fuzz.sh SECONDS [TARGET...]   fuzz each target (default: all four) for SECONDS,
#                                         from the committed corpus and the project's own
#                                         scenes and meshes; findings go to fuzz/artifacts/
#   scripts/fuzz.sh --minimize            merge what fuzzing found into the committed corpus
#                                         tests/data/fuzz/TARGET/ (smallest set of inputs with
#                                         the same coverage)
#
# Working corpora live in fuzz/corpus/, logs in fuzz/logs/ (both ignored by git). Needs cargo-fuzz (installed here on
# first use).
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
targets=(scene obj ply set)
command -v cargo-fuzz >/dev/null || cargo install --locked cargo-fuzz@0.13.2
fuzz() { cargo fuzz "$@"; }

# The seeds: the committed corpus, then the project's own scenes and meshes.
seed() {
    local target=$1 dir="fuzz/corpus/$1"
    mkdir -p "$dir"
    [ -d "tests/data/fuzz/$target" ] && cp -n "tests/data/fuzz/$target"/* "$dir"/ 2>/dev/null || true
    case $target in
        obj) cp -n tests/data/meshes/*.obj scenes/meshes/*.obj "$dir"/ || true ;;
        ply)
            cp -n tests/data/meshes/*.ply "$dir"/ || true
            for e in ascii binary-little-endian binary-big-endian; do
                target/release/timbre generate-mesh --triangles 24 --encoding "$e" -o "$dir/sphere-$e.ply" >/dev/null
            done ;;
        scene)
            cp -n scenes/*.toml "$dir"/ || true
            # A scene that includes a file and uses both meshes: four files joined by 0xFF.
            {
                printf '[[include]]\nfile = "inc.toml"\ntransform = { scale = 2 }\n'
                printf '[[object]]\nshape = { type = "mesh", file = "m.ply" }\nsurface = { type = "mirror" }\n'
                printf '\xff[[object]]\nshape = { type = "mesh", file = "m.obj" }\nsurface = { type = "matt", colour = [1, 1, 1] }\n'
                printf '\xff'; cat scenes/meshes/prism.obj
                printf '\xff'; cat tests/data/meshes/empty.ply
            } > "$dir/include-and-meshes" ;;
        set)
            printf 'render.width=8\ncamera.beta=[0,0,0.9]\n' > "$dir/two"
            printf 'object.1.surface.index_ratio=-1\n' > "$dir/index"
            printf 'group.0.object.0.shape.radius=2\nstudio=empty\n' > "$dir/group"
            printf 'object.3.transform.matrix=[[1,0,0],[0,2,0],[0,0,1]]\ncamera.position=[0,0,-5]\n' > "$dir/matrix"
            printf 'device.0.lenses.number_of_lenses=7\ndevice.1.aid.axes=[[0,1,0],[1,0,0],[0,0,1]]\n' > "$dir/devices"
            printf 'object.4.shape.edges=[[1,0,0],[0,1,0],[0,0,1]]\nobject.5.shape.corners=[[0,0,11],[1,0,11],[1,1,11],[0,1,11]]\n' > "$dir/fixed-lengths" ;;
    esac
}

# Words of the scene format, so that the fuzzer finds keys and names without guessing them.
dictionary() {
    grep -o '`[a-z_0-9-]\+`' docs/SCENE_FORMAT.md | tr -d '`' | sort -u | sed 's/.*/"&"/'
    printf '"[[object]]"\n"[[group]]"\n"[[include]]"\n"[[group.object]]"\n"= {"\n"= ["\n"\\xff"\n'
}

# The fuzz crate's lock file holds timbre's own versions (Cargo.lock) and libFuzzer's. cargo-fuzz
# has no --locked, so a lock file that would change is refused here, not resolved anew (which
# would build other versions on every machine).
(cd fuzz && cargo metadata --locked --format-version 1 >/dev/null) || {
    echo "fuzz: fuzz/Cargo.lock is not up to date with Cargo.lock; make it anew with" \
        "cp Cargo.lock fuzz/Cargo.lock && (cd fuzz && cargo metadata --format-version 1 >/dev/null)" >&2
    exit 1
}
cargo build --release --locked --quiet
if [ "${1:-}" = "--minimize" ]; then
    for t in "${targets[@]}"; do
        mkdir -p "tests/data/fuzz/$t" "fuzz/corpus/$t"
        old=$(mktemp -d)
        cp -a "tests/data/fuzz/$t/." "$old/"
        rm -f "tests/data/fuzz/$t"/*
        # libFuzzer's set-cover merge: few inputs of both with all their features, into the first.
        fuzz build -s none --release "$t"
        "fuzz/target/x86_64-unknown-linux-gnu/release/$t" -set_cover_merge=1 -rss_limit_mb=2048 \
            -timeout=60 "tests/data/fuzz/$t" "$old" "fuzz/corpus/$t" 2>&1 | tail -n 1
        rm -rf "$old"
        echo "$t: $(ls "tests/data/fuzz/$t" | wc -l) inputs, $(du -sh "tests/data/fuzz/$t" | cut -f1)"
    done
    exit 0
fi

seconds=${1:?usage: scripts/fuzz.sh SECONDS [TARGET...] | --minimize}
shift
[ $# -gt 0 ] && targets=("$@")
dictionary > fuzz/scene.dict
findings=()
for t in "${targets[@]}"; do
    seed "$t"
    flags=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=60 -max_len=65536
           -print_final_stats=1)
    case $t in scene | set) flags+=(-dict="$root/fuzz/scene.dict") ;; esac
    echo "== $t: ${seconds} s from $(ls "fuzz/corpus/$t" | wc -l) inputs"
    mkdir -p fuzz/logs
    if ! fuzz run -s none --release "$t" "fuzz/corpus/$t" -- "${flags[@]}" > "fuzz/logs/$t.log" 2>&1; then
        findings+=("$t")
        grep -E -A12 'panicked|ERROR|SUMMARY' "fuzz/logs/$t.log" | head -n 40 || true
    fi
    grep -E 'INITED|DONE|stat::' "fuzz/logs/$t.log" || true
done
if [ ${#findings[@]} -gt 0 ]; then
    echo "findings in ${findings[*]}: the inputs are in fuzz/artifacts/, the logs in fuzz/logs/" >&2
    exit 1
fi
