#!/usr/bin/env bash
# End-to-end test of the Slurm scripts in cluster/slurm/ on a real, one-node Slurm cluster
# started here for the test and stopped after it:
#   1. installs Debian's slurm-wlm, munge and ffmpeg if they are missing;
#   2. starts munged, slurmctld and slurmd as plain background processes (no systemd, no
#      containers), all configured in a temporary directory: the machine's /etc/slurm and
#      /etc/munge are neither read nor changed, and the ports are free ones, so a real Slurm
#      installation on the machine is not disturbed;
#   3. renders a small image (128x512) with cluster/slurm/submit.sh (a 4-task render-tiles.sbatch array
#      and merge.sbatch with an afterok dependency), and while one task runs sends its batch
#      shell the SIGUSR1 that #SBATCH --signal=B:USR1@120 sends before a time limit: the task
#      must checkpoint, requeue itself and, when it runs again, resume from its checkpoint;
#   4. checks that every job ended COMPLETED with exit code 0, and that the merged image is
#      byte for byte a single `timbre render` of the same settings;
#   5. renders a 4-frame movie with cluster/slurm/submit-movie.sh (a render-frames.sbatch array,
#      one frame per task, and encode.sbatch after it), checks each frame against the movie
#      rendered here and the GIF's frame count, and renders one frame again with plain sbatch.
# Prints PASS or FAIL (with the logs that matter) and exits non-zero on failure. Idempotent;
# leaves no daemon running and no temporary files. About 30 s on 2 cores once the packages are
# installed.
#   TIMBRE=path          test this binary instead of building target/release/timbre
#   SLURM_E2E_KEEP=1     keep the temporary directory (configuration, logs, images)
set -euo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
started=$SECONDS
keep=${SLURM_E2E_KEEP:-} # read now: the SLURM_* variables are cleared below
say() { echo "slurm-e2e: $*"; }

# The image: 128x512, 4 tiles of 128 rows (4 checkpoint groups of 32 rows each), enough
# samples that a tile takes a few seconds, so that one can be interrupted halfway.
WIDTH=128 HEIGHT=512 SPP=1024 TILES=4
# The task that is signalled: tile 2 is the slowest (it holds most of the cylinders).
SIGNALLED=2

# --- the binary (built as the calling user, before any sudo) -------------------------------
if [[ -z ${TIMBRE:-} ]]; then
    TIMBRE=$repo/target/release/timbre
    # Built when missing or older than the sources. Not always: after `cargo test --release`
    # (scripts/test.sh) the binary is there, built with the test build's features, and
    # `cargo build --release` would build it again with the plain build's, for minutes.
    if [[ ! -x $TIMBRE || -n $(cd "$repo" && find src build.rs Cargo.toml Cargo.lock -newer "$TIMBRE" -print -quit) ]]; then
        say "building $TIMBRE"
        (cd "$repo" && cargo build --release --locked --quiet)
    fi
fi
[[ -x $TIMBRE ]] || { say "FAIL: no timbre binary at $TIMBRE (cargo build --release)"; exit 1; }
TIMBRE=$(realpath "$TIMBRE")

# --- root: Slurm's daemons run jobs as their submitters, so slurmd must be root ------------
if [[ $(id -u) != 0 ]]; then
    command -v sudo >/dev/null || { say "FAIL: needs root (or sudo) to install and run Slurm"; exit 1; }
    exec sudo TIMBRE="$TIMBRE" SLURM_E2E_KEEP="$keep" bash "$0" "$@"
fi

# --- packages --------------------------------------------------------------------------------
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in slurm-wlm munge ffmpeg; do installed "$p" || missing+=("$p"); done
if ((${#missing[@]})); then
    say "installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    # Installing would start the packages' own daemons (init scripts) where nothing forbids
    # it; this test starts its own, so forbid it for the install, as Docker images do.
    policy=/usr/sbin/policy-rc.d
    own_policy=0
    if [[ ! -e $policy ]]; then
        printf '#!/bin/sh\nexit 101\n' >"$policy" && chmod 755 "$policy" && own_policy=1
    fi
    apt_install() { apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; }
    # `apt-get update` only when the package lists are missing or too old to install from.
    ok=0
    apt_install 2>/dev/null || { apt-get update -qq && apt_install; } || ok=$?
    ((own_policy == 0)) || rm -f "$policy"
    ((ok == 0)) || { say "FAIL: could not install ${missing[*]} with apt-get"; exit 1; }
fi
for tool in munged munge slurmctld slurmd sbatch squeue sinfo scontrol scancel ffprobe; do
    command -v "$tool" >/dev/null || { say "FAIL: $tool not found after installing slurm-wlm, munge and ffmpeg"; exit 1; }
done

# --- the temporary cluster -------------------------------------------------------------------
# Nothing of a surrounding Slurm (a login node's SLURM_CONF, SBATCH_PARTITION, the variables of
# a job this test runs in) may reach the test cluster's commands, nor this test the real cluster.
while read -r var; do unset "$var"; done < <(compgen -e | grep -E '^(SLURM|SBATCH|SALLOC|SRUN|SQUEUE|SINFO|SCONTROL)_' || true)
work=$(mktemp -d /tmp/timbre-slurm-e2e.XXXXXX)
chmod 755 "$work" # munged refuses a socket in a directory others cannot enter
mkdir -p "$work/munge" "$work/run" "$work/state" "$work/spool" "$work/log" "$work/render"
chmod 700 "$work/munge" # the key's directory: munged refuses one others can write to

pids=()  # daemons started here, stopped on exit (newest first)
ctld=    # set once our slurmctld runs: then squeue and scancel reach it, and only it
single= # the comparison render, while it runs
cleanup() {
    local status=$?
    set +e
    if [[ -n $ctld ]]; then
        # Cancel what is left (after a failure), so that no job process outlives the test.
        local jobs
        jobs=$(squeue -h -o %A 2>/dev/null)
        if [[ -n $jobs ]]; then
            # shellcheck disable=SC2086
            scancel $jobs 2>/dev/null
            for _ in $(seq 50); do [[ -z $(squeue -h -o %A 2>/dev/null) ]] && break; sleep 0.2; done
        fi
    fi
    # The comparison render, if it is still running.
    [[ -z ${single:-} ]] || { kill "$single" 2>/dev/null; wait "$single" 2>/dev/null; }
    local i pid
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
        pid=${pids[i]}
        kill "$pid" 2>/dev/null || continue
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
        kill -KILL "$pid" 2>/dev/null && say "had to kill -KILL daemon $pid"
        wait "$pid" 2>/dev/null
    done
    if [[ $keep == 1 ]]; then
        say "kept $work"
    else
        rm -rf "$work"
    fi
    exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

fail() {
    say "FAIL: $*"
    local f
    for f in "$work"/log/*.log "$work"/render/logs/*.out "$work"/movie/logs/*.out; do
        [[ -f $f ]] || continue
        echo "----- tail of ${f#"$work"/}"
        tail -n 25 "$f"
    done
    say "FAIL after $((SECONDS - started)) s: $*"
    exit 1
}

# Two free TCP ports on this machine (nothing answers on them) for slurmctld and slurmd.
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
for _ in $(seq 100); do
    ctld_port=$((20000 + RANDOM % 20000))
    if port_free "$ctld_port" && port_free $((ctld_port + 1)); then break; fi
done
slurmd_port=$((ctld_port + 1))

# munged with its own key and socket, as root (allowed: the files are root's and private).
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
socket=$work/run/munge.socket
munged --foreground --key-file="$work/munge/munge.key" --socket="$socket" \
    --log-file="$work/log/munged.log" --pid-file="$work/run/munged.pid" \
    --seed-file="$work/munge/munged.seed" >>"$work/log/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do
    munge -S "$socket" -n 2>/dev/null | unmunge -S "$socket" >/dev/null 2>&1 && break
    sleep 0.1
done
munge -S "$socket" -n | unmunge -S "$socket" >/dev/null || fail "munged does not answer on $socket"

# slurm.conf. The node's line is what slurmd itself detects (CPUs, sockets, memory), so that
# the node is not drained for claiming more than it has.
host=$(hostname -s)
node=$(slurmd -C | head -n 1)
[[ $node == "NodeName=$host "* ]] || fail "slurmd -C says '$node', not NodeName=$host"
export SLURM_CONF=$work/slurm.conf # honoured by the daemons, the commands and the jobs
cat >"$SLURM_CONF" <<EOF
# A one-node cluster for scripts/slurm-e2e.sh, on the loopback address.
ClusterName=timbre-e2e
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# cred_expire is also how long a requeued job waits before it may start again (120 s by
# default); 5 s keeps the requeue test short.
AuthInfo=socket=$socket,cred_expire=5
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/run/slurmctld.pid
SlurmdPidFile=$work/run/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
# No cgroups (none to be had in containers and small VMs): processes are tracked through
# /proc, tasks are not bound to CPUs.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
# Test pending jobs every 2 s rather than every 60 s: a requeued task is otherwise only
# started again by the next event or the minute's pass.
SchedulerParameters=sched_interval=2
MpiDefault=none
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MailProg=/bin/true
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=e2e Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -D >>"$work/log/slurmctld.out" 2>&1 &
pids+=($!)
ctld=$!
slurmd -D >>"$work/log/slurmd.out" 2>&1 &
pids+=($!)
state=
for _ in $(seq 150); do
    state=$(sinfo -h -n "$host" -o %t 2>/dev/null || true)
    [[ $state == idle ]] && break
    sleep 0.2
done
[[ $state == idle ]] || fail "the node is not idle after 30 s (sinfo: '${state:-no answer}')"
say "Slurm is up ($(slurmctld -V), node $host, ports $ctld_port/$slurmd_port) after $((SECONDS - started)) s"

# --- the render, as a user would submit it ---------------------------------------------------
out=$work/render
submitted=$(
    OUT_DIR=$out TILES=$TILES TIMBRE=$TIMBRE WIDTH=$WIDTH HEIGHT=$HEIGHT SPP=$SPP \
        CPUS_PER_TASK=1 CHECKPOINT_INTERVAL=0.2 PROGRESS=bar \
        "$repo/cluster/slurm/submit.sh"
) || fail "submit.sh failed"
array=$(sed -n 's/^ARRAY_JOB_ID=//p' <<<"$submitted")
merge=$(sed -n 's/^MERGE_JOB_ID=//p' <<<"$submitted")
[[ $array =~ ^[0-9]+$ && $merge =~ ^[0-9]+$ ]] || fail "submit.sh printed no job ids: $submitted"
say "submitted array job $array ($TILES tiles) and merge job $merge"

# The time-limit warning, as --signal=B:USR1@120 would send it: to the batch shell only, once
# the task has saved part of its tile in its checkpoint.
checkpoint=$out/parts/tile-$SIGNALLED.exr.checkpoint
for i in $(seq 1200); do
    compgen -G "$checkpoint/rows-*.exr" >/dev/null && break
    # Once a second: give up early when the task is no longer queued or running.
    if ((i % 20 == 0)) && [[ -z $(squeue -h -j "${array}_$SIGNALLED" -o %A 2>/dev/null) ]]; then break; fi
    sleep 0.05
done
compgen -G "$checkpoint/rows-*.exr" >/dev/null ||
    fail "task ${array}_$SIGNALLED saved no checkpoint to interrupt (job state: $(scontrol -o show job "${array}_$SIGNALLED" | grep -o 'JobState=[A-Z_]*'))"
scancel --batch --signal=USR1 "${array}_$SIGNALLED" || fail "scancel --batch --signal=USR1 failed"
say "sent SIGUSR1 to the batch shell of task ${array}_$SIGNALLED after its first checkpoint"

# Meanwhile, the same image in one render, to compare with (on the CPUs the requeued task
# leaves idle while it waits to start again).
"$TIMBRE" render -o "$work/single.exr" --width "$WIDTH" --height "$HEIGHT" --spp "$SPP" -q \
    >"$work/log/single.log" 2>&1 &
single=$!

# Wait until the queue is empty: every task finished, the merge too (or was cancelled).
for _ in $(seq 900); do
    [[ -z $(squeue -h -o %A) ]] && break
    sleep 0.2
done
[[ -z $(squeue -h -o %A) ]] || fail "jobs still queued after 180 s: $(squeue -h -o '%i %T %r' | tr '\n' ';')"

job_field() { scontrol -o show job "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }
for job in "${array}_0" "${array}_1" "${array}_2" "${array}_3" "$merge"; do
    st=$(job_field "$job" JobState) code=$(job_field "$job" ExitCode)
    [[ $st == COMPLETED && $code == 0:0 ]] || fail "job $job ended $st with exit code $code"
done
restarts=$(job_field "${array}_$SIGNALLED" Restarts)
[[ $restarts == 1 ]] || fail "task ${array}_$SIGNALLED ran $((restarts + 1)) time(s), not 2 (requeued once)"
log=$out/logs/tile-${array}_$SIGNALLED.out
grep -q "requeueing job" "$log" || fail "task ${array}_$SIGNALLED did not requeue itself"
grep -Eq "resumed [1-9][0-9]* group" "$log" || fail "task ${array}_$SIGNALLED did not resume from its checkpoint"
[[ ! -e $checkpoint ]] || fail "the checkpoint $checkpoint is still there after the tile was written"
say "all jobs COMPLETED with exit code 0; task ${array}_$SIGNALLED was requeued and resumed: $(grep -Eo "resumed [0-9]+ group\(s\)" "$log")"

# --- the merged image against the single render -----------------------------------------------
status=0
wait "$single" || status=$?
single=
((status == 0)) || fail "the single render failed (exit status $status)"
[[ -f $out/render.exr ]] || fail "no merged image $out/render.exr"
cmp "$out/render.exr" "$work/single.exr" || fail "the merged image differs from the single render"
say "merged tiles == single render, byte for byte ($((SECONDS - started)) s)"

# --- a movie: one frame per task, then the encode -----------------------------------------
# Four frames of a camera that turns and moves, one frame per task of a render-frames.sbatch
# array and a GIF from encode.sbatch once the array has finished, as submit-movie.sh submits
# them; each frame must be byte for byte the one `timbre render` of the movie writes here.
movie=$work/movie
mkdir -p "$movie/here"
cat >"$movie/scene.toml" <<TOML
[render]
width = 64
height = 48
spp = 8

[animation]
frames = 4
fps = 5

[[animation.track]]
key = "camera.position"
keyframes = [{ frame = 0, value = [0, 0, -12] }, { frame = 3, value = [2, 1, -9] }]

[[animation.track]]
key = "camera.horizontal_view_angle_deg"
interpolation = "smooth"
keyframes = [{ frame = 0, value = 40 }, { frame = 3, value = 25 }]
TOML
submitted=$(
    OUT_DIR=$movie SCENE=$movie/scene.toml TIMBRE=$TIMBRE VIDEO=movie.gif CPUS_PER_TASK=1 \
        PROGRESS=bar "$repo/cluster/slurm/submit-movie.sh"
) || fail "submit-movie.sh failed"
array=$(sed -n 's/^ARRAY_JOB_ID=//p' <<<"$submitted")
encode=$(sed -n 's/^ENCODE_JOB_ID=//p' <<<"$submitted")
[[ $array =~ ^[0-9]+$ && $encode =~ ^[0-9]+$ ]] || fail "submit-movie.sh printed no job ids: $submitted"
say "submitted array job $array (4 frames) and encode job $encode"
"$TIMBRE" render "$movie/scene.toml" -o "$movie/here/frame-%04d.png" -q >"$work/log/movie.log" 2>&1 ||
    fail "the movie rendered here failed: $(cat "$work/log/movie.log")"
wait_for_queue() {
    for _ in $(seq 900); do
        [[ -z $(squeue -h -o %A) ]] && return
        sleep 0.2
    done
    fail "jobs still queued after 180 s: $(squeue -h -o '%i %T %r' | tr '\n' ';')"
}
wait_for_queue
for job in "${array}_0" "${array}_1" "${array}_2" "${array}_3" "$encode"; do
    st=$(job_field "$job" JobState) code=$(job_field "$job" ExitCode)
    [[ $st == COMPLETED && $code == 0:0 ]] || fail "job $job ended $st with exit code $code"
done
for k in 0 1 2 3; do
    cmp "$movie/frames/frame-000$k.png" "$movie/here/frame-000$k.png" ||
        fail "frame $k of the array differs from the movie rendered here"
done
cmp -s "$movie/frames/frame-0000.png" "$movie/frames/frame-0003.png" && fail "frames 0 and 3 are the same picture"
count=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames \
    -of csv=p=0 "$movie/movie.gif") || fail "ffprobe cannot read $movie/movie.gif"
[[ $count == 4 ]] || fail "$movie/movie.gif has $count frames, not 4"

# One frame again, submitted by hand with sbatch as docs/CLUSTER.md shows, without
# TIMBRE_SLURM_DIR: the task finds task.sh through the command Slurm recorded.
rm "$movie/frames/frame-0002.png"
again=$(env -u TIMBRE_SLURM_DIR OUT_DIR="$movie" SCENE="$movie/scene.toml" TIMBRE="$TIMBRE" \
    sbatch --parsable --export=ALL --array=2 --cpus-per-task=1 --output="$movie/logs/again-%A_%a.out" \
    "$repo/cluster/slurm/render-frames.sbatch") || fail "sbatch render-frames.sbatch failed"
again=${again%%;*}
wait_for_queue
st=$(job_field "${again}_2" JobState) code=$(job_field "${again}_2" ExitCode)
[[ $st == COMPLETED && $code == 0:0 ]] || fail "job ${again}_2 ended $st with exit code $code"
cmp "$movie/frames/frame-0002.png" "$movie/here/frame-0002.png" || fail "frame 2 rendered again differs"
say "PASS: merged tiles == single render; the movie's frames == a movie rendered here, GIF of 4 frames ($((SECONDS - started)) s)"
