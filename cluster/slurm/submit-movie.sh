#!/usr/bin/env bash
# Submits a timbre movie to Slurm: the job array of cluster/slurm/render-frames.sbatch (one task
# per frame) and, when VIDEO is set, cluster/slurm/encode.sbatch, which waits for the whole
# array (afterok) and encodes the frames. See docs/CLUSTER.md.
#
#   OUT_DIR=/shared/movie1 SCENE=/shared/scene.toml VIDEO=movie.mp4 SPP=64 \
#       cluster/slurm/submit-movie.sh [extra `timbre render` arguments...]
#
# Settings, from the environment (everything render-frames.sbatch and encode.sbatch read):
#   OUT_DIR, SCENE (required), FRAMES, FORMAT, TIMBRE, WIDTH, HEIGHT, SPP, SEED,
#   CHECKPOINT_INTERVAL, REQUEUE, MAX_REQUEUES, PROGRESS
#   VIDEO          the video to encode, its extension the format (.mp4, .webm, .gif, ...); a
#                  bare name is put in OUT_DIR. Unset: frames only, no encode job
#   CPUS_PER_TASK  CPUs (timbre threads) per frame (default: the script's #SBATCH line, 4)
#   TASKS          the array's tasks (default: the movie's frames, first_frame to last_frame,
#                  as `timbre check` reads them); give a subset such as 3,7 to render only
#                  those frames (a frame already written is skipped: delete it to render it
#                  again)
# sbatch's own input variables (SBATCH_PARTITION, SBATCH_ACCOUNT, SBATCH_TIMELIMIT, ...) apply
# to both jobs; options on the command line of this script go to timbre, not sbatch.
# Prints ARRAY_JOB_ID=... and, with VIDEO, ENCODE_JOB_ID=... on standard output.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
die() { echo "submit-movie: error: $*" >&2; exit 2; }

[[ -n ${OUT_DIR:-} ]] || die "set OUT_DIR to a directory on a filesystem shared by all nodes"
[[ -n ${SCENE:-} ]] || die "set SCENE to the movie's scene file"
FORMAT=${FORMAT:-png}
[[ $FORMAT == png || $FORMAT == exr ]] || die "FORMAT is png or exr, not '$FORMAT'"
[[ -z ${VIDEO:-} || $FORMAT == png ]] || die "a video is made of PNG frames: FORMAT=png, or no VIDEO"
[[ -z ${FRAMES:-} || $FRAMES =~ ^[1-9][0-9]*$ ]] || die "FRAMES must be a positive whole number, not '$FRAMES'"

# Absolute paths: the jobs may start in another directory, on another node.
OUT_DIR=$(realpath -m "$OUT_DIR")
SCENE=$(realpath -e "$SCENE") || die "no scene file $SCENE"
if [[ ${TIMBRE:-} == */* ]]; then
    TIMBRE=$(realpath -e "$TIMBRE") || die "no timbre binary $TIMBRE"
fi
TIMBRE=${TIMBRE:-timbre}
if [[ -n ${VIDEO:-} ]]; then
    [[ $VIDEO == */* ]] || VIDEO=$OUT_DIR/$VIDEO
    VIDEO=$(realpath -m "$VIDEO")
fi

# The movie's frames, as timbre reads them: the scene checked with the --set options of the
# command line (which may change the [animation]) and FRAMES.
check=(check "$SCENE")
[[ -z ${FRAMES:-} ]] || check+=(--set "animation.frames=$FRAMES")
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
    case ${args[i]} in
    --set) check+=(--set "${args[i + 1]:-}") ;;
    --set=*) check+=("${args[i]}") ;;
    --frames | --frames=* | --frame | --frame=*)
        die "${args[i]%%=*} is for one render: set FRAMES (the movie's frames) or TASKS (those to render)" ;;
    esac
done
summary=$("$TIMBRE" "${check[@]}") || die "timbre check ${check[*]} failed (above)"
read -r FIRST LAST < <(sed -n 's/^ *movie: *frames \([0-9]*\) to \([0-9]*\) .*/\1 \2/p' <<<"$summary") || true
[[ -n ${FIRST:-} ]] || die "$SCENE has no [animation]: give it one, or set FRAMES"
TASKS=${TASKS:-$FIRST-$LAST}
mkdir -p "$OUT_DIR/frames" "$OUT_DIR/logs"
export OUT_DIR SCENE TIMBRE FORMAT FRAMES FIRST LAST VIDEO TIMBRE_SLURM_DIR=$here

# --export=ALL passes the variables above to the jobs even where a site sets SBATCH_EXPORT.
array_opts=(--parsable --export=ALL --array="$TASKS" --output="$OUT_DIR/logs/frame-%A_%a.out")
[[ -z ${CPUS_PER_TASK:-} ]] || array_opts+=(--cpus-per-task="$CPUS_PER_TASK")
# --parsable prints "ID" or "ID;CLUSTER".
array_id=$(sbatch "${array_opts[@]}" "$here/render-frames.sbatch" "$@")
array_id=${array_id%%;*}
echo "ARRAY_JOB_ID=$array_id"

if [[ -n ${VIDEO:-} ]]; then
    # afterok on the array's id waits for every task of it; --kill-on-invalid-dep cancels the
    # encode when a frame fails for good, instead of leaving it pending for ever.
    encode_id=$(sbatch --parsable --export=ALL --dependency="afterok:$array_id" \
        --kill-on-invalid-dep=yes --output="$OUT_DIR/logs/encode-%j.out" "$here/encode.sbatch" "$@")
    encode_id=${encode_id%%;*}
    echo "ENCODE_JOB_ID=$encode_id"
fi
