#!/usr/bin/env bash
# The fresh-machine check: runs the README's two quick-start commands as a new user would, on a
# fresh Debian 12 with only the Rust toolchain, from a fresh clone of this repository's HEAD.
# Run it before every change to the scripts, the dependencies or the README (CI runs on a
# machine with caches, where a missing install step does not show).
#   the machine    a Debian 12 root made by debootstrap (variant minbase, with ca-certificates
#                  and curl, which installing the Rust toolchain with rustup takes), entered with
#                  chroot in new mount and PID namespaces: what the commands install stays in
#                  it, and every daemon a test starts ends with it
#   the toolchain  this machine's rustup toolchain (the one `rustc` here is), read-only, with
#                  rustup; nothing else of cargo's (an empty CARGO_HOME: no registry cache, no
#                  installed tools); empty pip and npm caches; no target/
#   the clone      HEAD, committed changes only (uncommitted ones are not checked: a warning)
#   the user       root, with an environment of its own (none of this shell's variables, such
#                  as CARGO_TARGET_DIR, RUSTFLAGS, EMBREE_DIR or PIP_FIND_LINKS)
#   the network    this machine's: its DNS settings, and the certificate authorities it trusts
#                  beyond Debian's (a proxy between it and the registries) are trusted there too
# The two commands are read from the README's quick start (its first shell block), so that it
# is the README that is checked. Prints how long each took and PASS, or FAIL with the end of
# its log; exits non-zero on failure.
#
# Usage: scripts/fresh-check.sh [--busy] [--keep] [DIR]
#   --busy   keeps every core busy with another process (one `yes` per core) the whole time:
#            no test may depend on how loaded the machine is
#   --keep   keeps DIR afterwards (the root, the clone with its target/, the logs)
#   DIR      the work directory, which must not exist yet (default: a new one under /var/tmp);
#            it needs about 20 GB
# Needs root (debootstrap, chroot, mounts), rustup, git and the package registries; installs
# debootstrap when missing. Takes about as long as the two commands on a fresh machine (about
# 50 minutes on 2 cores) and a few minutes more to make the root.
set -euo pipefail

busy=0 keep=0 dir=""
for arg in "$@"; do
    case $arg in
        --busy) busy=1 ;;
        --keep) keep=1 ;;
        -*) echo "usage: scripts/fresh-check.sh [--busy] [--keep] [DIR]" >&2; exit 2 ;;
        *) [ -z "$dir" ] || { echo "fresh-check: one DIR only" >&2; exit 2; }; dir=$arg ;;
    esac
done
say() { echo "fresh-check: $*" >&2; }

repo="$(cd "$(dirname "$0")/.." && pwd)"
[ "$(id -u)" -eq 0 ] || { say "needs root (debootstrap, chroot and mounts)"; exit 1; }
command -v rustup >/dev/null || { say "needs the Rust toolchain installed with rustup"; exit 1; }
sysroot="$(cd "$repo" && rustc --print sysroot)"
toolchain="$(basename "$sysroot")"
[ "$(basename "$(dirname "$sysroot")")" = toolchains ] ||
    { say "rustc's sysroot $sysroot is not a rustup toolchain"; exit 1; }
command -v debootstrap >/dev/null || "$repo/scripts/apt-install.sh" debootstrap

# The README's two commands: the first two lines of its quick start's first shell block that
# are not comments.
mapfile -t commands < <(awk '/^## Quick start/ { q = 1 } q && /^```sh/ { b = 1; next }
    b && /^```/ { exit } b && !/^ *#/ && NF' "$repo/README.md" | head -n 2)
[ "${#commands[@]}" -eq 2 ] || { say "no two commands in README.md's quick start"; exit 1; }

commit="$(git -C "$repo" rev-parse HEAD)"
[ -z "$(git -C "$repo" status --porcelain)" ] ||
    say "warning: uncommitted changes in $repo are not checked (the clone is of HEAD)"

if [ -z "$dir" ]; then
    dir="$(mktemp -d /var/tmp/timbre-fresh-check.XXXXXX)"
else
    [ ! -e "$dir" ] || { say "$dir exists; name a new directory"; exit 2; }
    mkdir -p "$dir"
    dir="$(cd "$dir" && pwd)"
fi
root="$dir/root"
loads=()
finish() {
    local status=$?
    for p in "${loads[@]}"; do kill "$p" 2>/dev/null || true; done
    # The mounts were made in the namespaces, which are gone: nothing is mounted under $root
    # here. --one-file-system guards against removing through one that somehow is.
    if ((keep == 0)); then
        rm -rf --one-file-system "$dir"
    else
        say "kept $dir"
    fi
    exit "$status"
}
trap finish EXIT

if ((busy)); then
    for _ in $(seq "$(nproc)"); do
        yes >/dev/null &
        loads+=($!)
    done
    say "keeping $(nproc) cores busy"
fi

start=$SECONDS
say "making a Debian 12 root in $root"
debootstrap --variant=minbase --include=ca-certificates,curl bookworm "$root" \
    http://deb.debian.org/debian >"$dir/debootstrap.log" 2>&1 ||
    { tail -n 20 "$dir/debootstrap.log" >&2; say "FAIL: debootstrap"; exit 1; }
# A Debian 12 install's package sources (debootstrap writes only the release's own).
cat >"$root/etc/apt/sources.list" <<EOF
deb http://deb.debian.org/debian bookworm main
deb http://deb.debian.org/debian bookworm-updates main
deb http://deb.debian.org/debian-security bookworm-security main
EOF
cp /etc/resolv.conf /etc/hosts "$root/etc/"
# The certificate authorities this machine trusts that a fresh Debian 12 lacks (those of a
# proxy between it and the registries), so that the root reaches the registries as it does.
python3 - /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/certs/ca-certificates.crt" \
    "$root/usr/local/share/ca-certificates" <<'PYTHON'
import pathlib, re, sys
def certificates(path):
    text = pathlib.Path(path).read_text()
    return re.findall(r"-----BEGIN CERTIFICATE-----.*?-----END CERTIFICATE-----", text, re.S)
fresh = set(certificates(sys.argv[2]))
extra = [c for c in certificates(sys.argv[1]) if c not in fresh]
for n, certificate in enumerate(extra):
    pathlib.Path(sys.argv[3], f"fresh-check-{n}.crt").write_text(certificate + "\n")
print(f"fresh-check: {len(extra)} certificate authorities of this machine's trusted there too", file=sys.stderr)
PYTHON
chroot "$root" update-ca-certificates >>"$dir/debootstrap.log" 2>&1

# The toolchain: rustup, its proxies, its settings naming the one toolchain (mounted below).
mkdir -p "$root/root/.cargo/bin" "$root/root/.rustup/toolchains/$toolchain"
cp "$(readlink -f "$(command -v rustup)")" "$root/root/.cargo/bin/rustup"
for tool in cargo cargo-clippy cargo-fmt clippy-driver rustc rustdoc rustfmt; do
    ln -s rustup "$root/root/.cargo/bin/$tool"
done
printf 'version = "12"\ndefault_toolchain = "%s"\nprofile = "default"\n' "$toolchain" \
    >"$root/root/.rustup/settings.toml"

git clone --quiet --no-hardlinks "$repo" "$root/root/timbre"
git -C "$root/root/timbre" checkout --quiet "$commit"
say "root ready in $((SECONDS - start)) s; checking $commit"

# Runs the README's command $1 (numbered $2) in the root, logged to $dir/command-$2.log.
run() {
    local begin=$SECONDS
    # shellcheck disable=SC2016 # expanded in the namespaces
    if unshare --mount --pid --fork --propagation private bash -c '
        set -e
        root=$1 sysroot=$2 toolchain=$3 command=$4
        # /sys (with the cgroup file system, which slurmd needs) and /dev as on this machine,
        # and a /proc of the new PID namespace.
        mount -t proc proc "$root/proc"
        mount --rbind /sys "$root/sys"
        mount --rbind /dev "$root/dev"
        mount -t tmpfs -o mode=1777 tmpfs "$root/dev/shm"
        mount --bind -o ro "$sysroot" "$root/root/.rustup/toolchains/$toolchain"
        exec chroot "$root" /usr/bin/env -i HOME=/root USER=root LOGNAME=root SHELL=/bin/bash \
            PATH=/root/.cargo/bin:/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
            /bin/bash -c "cd /root/timbre && $command"
    ' fresh-check "$root" "$sysroot" "$toolchain" "$1" </dev/null >"$dir/command-$2.log" 2>&1; then
        say "command $2 passed in $(((SECONDS - begin) / 60)) min $(((SECONDS - begin) % 60)) s: $1"
    else
        tail -n 60 "$dir/command-$2.log" >&2
        say "FAIL: command $2 after $(((SECONDS - begin) / 60)) min: $1 (log: $dir/command-$2.log)"
        keep=1
        exit 1
    fi
}
run "${commands[0]}" 1
run "${commands[1]}" 2
say "PASS: $commit on a fresh Debian 12$( ((busy)) && echo ", every core kept busy")," \
    "$(((SECONDS - start) / 60)) min in all"
