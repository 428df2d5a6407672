# What the batch scripts of a timbre job array share, sourced by render-tiles.sbatch and
# render-frames.sbatch: the render's options from the environment, and running timbre so that
# it checkpoints, requeues and resumes across Slurm's signals. docs/CLUSTER.md explains it.
#
# The sourcing script defines log (a line to the task's log) before calling these.
# shellcheck shell=bash

# Appends to the array `args` the options every task's `timbre render` takes from the
# environment: --resume and --checkpoint-interval (CHECKPOINT_INTERVAL, default 300),
# --progress (PROGRESS, default json), WIDTH, HEIGHT, SPP and SEED when set, and --threads from
# the CPUs Slurm allocated.
add_render_options() {
    # --resume always: on the first run there is no checkpoint and it starts afresh; after a
    # requeue, a node failure or a resubmission it continues where the last checkpoint left off.
    args+=(--resume --checkpoint-interval "${CHECKPOINT_INTERVAL:-300}")
    args+=(--progress "${PROGRESS:-json}")
    [[ -z ${WIDTH:-} ]] || args+=(--width "$WIDTH")
    [[ -z ${HEIGHT:-} ]] || args+=(--height "$HEIGHT")
    [[ -z ${SPP:-} ]] || args+=(--spp "$SPP")
    [[ -z ${SEED:-} ]] || args+=(--seed "$SEED")
    # As many threads as CPUs allocated; without --cpus-per-task timbre takes all it can see.
    [[ -z ${SLURM_CPUS_PER_TASK:-} ]] || args+=(--threads "$SLURM_CPUS_PER_TASK")
}

# Runs "$@" (timbre) in the background and returns its exit status, passing Slurm's time-limit
# warning on and requeueing the task (REQUEUE, default 1; at most MAX_REQUEUES times, default 10).
#
# Slurm's own SIGTERM (scancel, time limit, requeue, preemption) reaches every process of the
# job, timbre included, which saves a checkpoint and stops. timbre takes a second SIGTERM as
# "stop at once, without saving", so this shell must not pass SIGTERM on as well: it only notes
# it and keeps waiting until timbre has finished its checkpoint. (A batch shell that exits first
# ends the job: Slurm kills what is left of it, with proctrack/cgroup, or loses track of it.)
# SIGUSR1 from --signal=B:USR1@120 reaches this shell only, so it is passed on: timbre saves a
# checkpoint and goes on. Then, with REQUEUE=1, the task is requeued: Slurm sends SIGTERM
# (timbre saves what it finished since and stops) and puts the task back in the queue, where it
# waits for a node again and resumes from the checkpoint instead of running into its limit and
# ending TIMEOUT, which would leave a dependent job's afterok unsatisfiable.
run_requeueable() {
    pid=
    signalled=0
    restarts=${SLURM_RESTART_COUNT:-0}
    trap on_usr1 USR1
    trap on_term TERM
    "$@" &
    pid=$!
    # `wait` returns early (status > 128) whenever a trapped signal arrives; then timbre is
    # still running, or has just exited, and waiting again gives its real exit status (bash
    # keeps the status of a finished background process, so a second wait returns it again).
    local status
    while true; do
        signalled=0
        status=0
        wait "$pid" || status=$?
        ((signalled)) || break
    done
    return "$status"
}

# shellcheck disable=SC2317 # (the handlers are called by trap)
on_usr1() {
    signalled=1
    log "SIGUSR1: the time limit is near; asking timbre for a checkpoint"
    [[ -z $pid ]] || kill -USR1 "$pid" 2>/dev/null || true
    if [[ ${REQUEUE:-1} == 1 ]]; then
        if ((restarts >= ${MAX_REQUEUES:-10})); then
            log "not requeued: already requeued $restarts time(s) (MAX_REQUEUES); the task will stop at its time limit with a checkpoint"
        elif [[ -n $pid ]] && kill -0 "$pid" 2>/dev/null; then
            # SLURM_JOB_ID is this task's own job id; SLURM_ARRAY_JOB_ID would requeue the
            # whole array.
            log "requeueing job $SLURM_JOB_ID (this task) to continue from its checkpoint"
            scontrol requeue "$SLURM_JOB_ID" ||
                log "scontrol requeue failed; the task will stop at its time limit with a checkpoint"
        fi
    fi
}

# shellcheck disable=SC2317
on_term() {
    signalled=1
    log "SIGTERM: the job is being stopped; timbre got the signal too and saves a checkpoint"
}
