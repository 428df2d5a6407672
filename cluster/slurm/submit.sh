#!/usr/bin/env bash
# Submits a tiled timbre render to Slurm: the job array of cluster/slurm/render-tiles.sbatch
# (one task per tile) and cluster/slurm/merge.sbatch, which waits for the whole array
# (afterok) and merges the parts. See docs/CLUSTER.md.
#
#   OUT_DIR=/shared/run1 TILES=16 SCENE=/shared/scene.toml WIDTH=3840 HEIGHT=2160 SPP=256 \
#       cluster/slurm/submit.sh [extra `timbre render` arguments...]
#
# Settings, from the environment (everything render-tiles.sbatch and merge.sbatch read):
#   OUT_DIR (required), TILES (default 8), TIMBRE, SCENE, WIDTH, HEIGHT, SPP, SEED,
#   CHECKPOINT_INTERVAL, REQUEUE, MAX_REQUEUES, PROGRESS, OUTPUT (default $OUT_DIR/render.exr)
#   CPUS_PER_TASK  CPUs (timbre threads) per tile task (default: the script's #SBATCH line, 4)
#   TASKS          the array's tasks (default 0-(TILES-1)); give a subset such as 3,5 to render
#                  only those tiles again (the merge then waits for them only)
# sbatch's own input variables (SBATCH_PARTITION, SBATCH_ACCOUNT, SBATCH_TIMELIMIT, ...) apply
# to both jobs; options on the command line of this script go to timbre, not sbatch.
# Prints ARRAY_JOB_ID=... and MERGE_JOB_ID=... on standard output.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
die() { echo "submit: error: $*" >&2; exit 2; }

[[ -n ${OUT_DIR:-} ]] || die "set OUT_DIR to a directory on a filesystem shared by all nodes"
TILES=${TILES:-8}
[[ $TILES =~ ^[1-9][0-9]*$ ]] || die "TILES must be a positive whole number, not '$TILES'"
TASKS=${TASKS:-0-$((TILES - 1))}

# Absolute paths: the jobs may start in another directory, on another node.
OUT_DIR=$(realpath -m "$OUT_DIR")
[[ -z ${SCENE:-} ]] || SCENE=$(realpath -e "$SCENE") || die "no scene file $SCENE"
if [[ ${TIMBRE:-} == */* ]]; then
    TIMBRE=$(realpath -e "$TIMBRE") || die "no timbre binary $TIMBRE"
fi
OUTPUT=${OUTPUT:-$OUT_DIR/render.exr}
mkdir -p "$OUT_DIR/parts" "$OUT_DIR/logs"
export OUT_DIR TILES SCENE TIMBRE OUTPUT TIMBRE_SLURM_DIR=$here

# --export=ALL passes the variables above to the jobs even where a site sets SBATCH_EXPORT.
array_opts=(--parsable --export=ALL --array="$TASKS" --output="$OUT_DIR/logs/tile-%A_%a.out")
[[ -z ${CPUS_PER_TASK:-} ]] || array_opts+=(--cpus-per-task="$CPUS_PER_TASK")
# --parsable prints "ID" or "ID;CLUSTER".
array_id=$(sbatch "${array_opts[@]}" "$here/render-tiles.sbatch" "$@")
array_id=${array_id%%;*}
echo "ARRAY_JOB_ID=$array_id"

# afterok on the array's id waits for every task of it; --kill-on-invalid-dep cancels the
# merge when a task fails for good, instead of leaving it pending for ever.
merge_id=$(sbatch --parsable --export=ALL --dependency="afterok:$array_id" \
    --kill-on-invalid-dep=yes --output="$OUT_DIR/logs/merge-%j.out" "$here/merge.sbatch")
merge_id=${merge_id%%;*}
echo "MERGE_JOB_ID=$merge_id"
