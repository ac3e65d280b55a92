#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Checks the README's commands on a fresh Debian 13 (trixie) in a chroot, from a Debian host.
#
#   sudo bash scripts/debian13_check.sh [--root DIR] [--ref REF] [--logs DIR] [--mirror URL]
#                                       [--reuse] [--shell] [--] [COMMAND...]
#
# 1. Builds a minimal trixie tree in DIR (default /var/tmp/hf-trixie) with mmdebstrap
#    (variant minbase, plus git and ca-certificates: what a user needs to clone), unless DIR
#    already holds one (delete DIR for a fresh one; a kept tree keeps the packages and ccache
#    the previous run installed and filled).
# 2. Mounts /proc, /sys, /dev (with /dev/pts) and a fresh /dev/shm into it, copies the host's
#    resolv.conf, and unmounts all of them again on exit (also on Ctrl-C or an error).
# 3. Clones REF (default: this checkout's HEAD, committed work only) of this repository afresh
#    into /root/hapticfluid inside, with ../shared beside it (bind-mounted read-only from the
#    host's ../shared when there is one, as the project's CI has it). `--reuse` instead moves the
#    clone a previous run left to REF and keeps its build/ (to rerun after a fix; not fresh).
# 4. Runs COMMAND in the clone as root, with a clean environment (HOME=/root, Debian's PATH,
#    LANG=C.UTF-8, no DISPLAY): by default the README's two commands, `bash scripts/demo.sh`
#    then `bash scripts/test.sh`, each one timed; they install what trixie lacks with apt
#    themselves. Logs: LOGS (default DIR.logs)/demo.log, test.log and times.txt.
#    `--shell` opens a shell in the clone instead (same mounts).
#
# Needs root (chroot, mounts) and mmdebstrap (`apt-get install mmdebstrap` on the host; the
# host's debian-archive-keyring must know trixie's keys: Debian 12's does). Time measured on
# the project's 2-core machines (no GPU) under heavy load from other builds (load average ~28):
# the tree 90 s, the demo command 35 minutes from the bare tree (apt 503 packages, 526 MB: ~13;
# building _core: ~13), the test command 35 minutes more; README's setup notes have the results.
set -euo pipefail
{  # one compound command: bash reads it whole, so editing this file while it runs is safe
HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROOT=/var/tmp/hf-trixie
REF=HEAD
LOGS=
MIRROR=http://deb.debian.org/debian
SHELL_ONLY=0
REUSE=0
while [ $# -gt 0 ]; do
  case "$1" in
    --root) ROOT="$2"; shift 2 ;;
    --ref) REF="$2"; shift 2 ;;
    --logs) LOGS="$2"; shift 2 ;;
    --mirror) MIRROR="$2"; shift 2 ;;
    --shell) SHELL_ONLY=1; shift ;;
    --reuse) REUSE=1; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --) shift; break ;;
    -*) echo "error: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) break ;;
  esac
done
LOGS="${LOGS:-$ROOT.logs}"

[ "$(id -u)" -eq 0 ] || { echo "error: needs root (chroot and mounts): run it with sudo" >&2; exit 1; }
command -v mmdebstrap >/dev/null 2>&1 || [ -f "$ROOT/etc/debian_version" ] \
  || { echo "error: mmdebstrap is missing: apt-get install mmdebstrap" >&2; exit 1; }
case "$ROOT" in "$HF_ROOT"|"$HF_ROOT"/*)
  echo "error: --root must be outside the repository ($HF_ROOT)" >&2; exit 2 ;; esac
commit="$(git -C "$HF_ROOT" rev-parse --verify "$REF^{commit}")" \
  || { echo "error: '$REF' is not a commit of $HF_ROOT" >&2; exit 2; }
mkdir -p "$LOGS"
LOGS="$(cd "$LOGS" && pwd)"
times="$LOGS/times.txt"
stamp() { date -u +%H:%M:%S; }

# ---- 1. the tree -----------------------------------------------------------------------------
if [ ! -f "$ROOT/etc/debian_version" ]; then
  echo "== $(stamp) mmdebstrap trixie -> $ROOT"
  t0=$SECONDS
  mmdebstrap --variant=minbase --include=git,ca-certificates trixie "$ROOT" "$MIRROR" \
    >"$LOGS/mmdebstrap.log" 2>&1 || { tail -n 20 "$LOGS/mmdebstrap.log" >&2; exit 1; }
  echo "mmdebstrap: $((SECONDS - t0)) s" >>"$times"
fi
echo "== $(stamp) chroot: Debian $(cat "$ROOT/etc/debian_version") in $ROOT"

# ---- 2. mounts, undone on exit ---------------------------------------------------------------
mounted=()
cleanup() {
  local i
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    umount -l "${mounted[i]}" 2>/dev/null || echo "warning: could not unmount ${mounted[i]}" >&2
  done
}
trap cleanup EXIT
mnt() {  # mnt TARGET mount-args...: mounts unless something is mounted there already
  local target="$1"; shift
  mkdir -p "$target"
  if mountpoint -q "$target"; then return 0; fi
  mount "$@" "$target"
  mounted+=("$target")
}
mnt "$ROOT/proc" -t proc proc
mnt "$ROOT/sys" --rbind /sys
mount --make-rslave "$ROOT/sys"
mnt "$ROOT/dev" --bind /dev
mnt "$ROOT/dev/pts" --bind /dev/pts
mnt "$ROOT/dev/shm" -t tmpfs -o mode=1777,nosuid,nodev shm
cp -L /etc/resolv.conf "$ROOT/etc/resolv.conf"
# An installed Debian has /etc/mtab -> ../proc/self/mounts; a minbase tree lacks it (Blender
# then warns "could not get a list of mounted file-systems").
[ -e "$ROOT/etc/mtab" ] || ln -s ../proc/self/mounts "$ROOT/etc/mtab"
# CA certificates added on the host (/usr/local/share/ca-certificates: e.g. a TLS-inspecting
# proxy's) are trusted inside too, so pip reaches PyPI from the chroot as it does from the host.
if compgen -G "/usr/local/share/ca-certificates/*.crt" >/dev/null && [ -x "$ROOT/usr/sbin/update-ca-certificates" ]; then
  mkdir -p "$ROOT/usr/local/share/ca-certificates"
  cp /usr/local/share/ca-certificates/*.crt "$ROOT/usr/local/share/ca-certificates/"
  chroot "$ROOT" update-ca-certificates >/dev/null 2>&1 || echo "warning: update-ca-certificates failed in $ROOT" >&2
  # pip trusts its own bundle (certifi), not the system's: point it at the system's, which now
  # holds them (a CPython built in the tree, Debian 11's for the old-glibc wheel test, runs pip).
  [ -e "$ROOT/etc/pip.conf" ] || printf '[global]\ncert = /etc/ssl/certs/ca-certificates.crt\n' >"$ROOT/etc/pip.conf"
fi

# ---- 3. a fresh clone, ../shared beside it ---------------------------------------------------
clone="$ROOT/root/hapticfluid"
if [ "$REUSE" = 1 ] && [ -d "$clone/.git" ]; then
  git -C "$clone" fetch -q "$HF_ROOT" "+refs/heads/*:refs/remotes/host/*"
else
  rm -rf "$clone"
  git clone -q --no-hardlinks "$HF_ROOT" "$clone"
fi
git -C "$clone" checkout -q --detach "$commit"
echo "== $(stamp) clone: $(git -C "$clone" log -1 --format='%h %s' | cut -c1-100)"
if [ -d "$HF_ROOT/../shared" ]; then
  mnt "$ROOT/root/shared" --bind "$(cd "$HF_ROOT/../shared" && pwd)"
  mount -o remount,bind,ro "$ROOT/root/shared"
fi

# ---- 4. the commands -------------------------------------------------------------------------
in_chroot() {
  chroot "$ROOT" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM="${TERM:-dumb}" \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    /bin/bash -c 'cd /root/hapticfluid && exec "$@"' bash "$@"
}
if [ "$SHELL_ONLY" = 1 ]; then
  in_chroot /bin/bash -i
  exit $?
fi
if [ $# -gt 0 ]; then
  commands=("$*")
else
  commands=("bash scripts/demo.sh" "bash scripts/test.sh")
fi
rc_all=0
for cmd in "${commands[@]}"; do
  name="$(echo "$cmd" | sed 's/^bash scripts\///; s/\.sh.*//; s/[^A-Za-z0-9_.-]/_/g')"
  echo "== $(stamp) run: $cmd (log: $LOGS/$name.log)"
  t0=$SECONDS
  set +e
  in_chroot /bin/bash -c "$cmd" >"$LOGS/$name.log" 2>&1
  rc=$?
  set -e
  echo "$cmd: exit $rc, $((SECONDS - t0)) s" | tee -a "$times"
  [ "$rc" -eq 0 ] || { rc_all=$rc; tail -n 40 "$LOGS/$name.log" >&2; }
done
exit "$rc_all"
}
