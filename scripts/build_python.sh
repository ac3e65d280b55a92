#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Prints the path of a CPython 3.11 or 3.13 (the two Pythons that Blender 4.2 to 5.3 embed) with
# venv and ensurepip, building it once from Debian's source package when this system has none.
#
#   bash scripts/build_python.sh 3.11|3.13        # stdout: the interpreter's path, nothing else
#
# 1. An installed one first: python3.X on PATH, then /usr/bin/python3.X (Debian 12 has 3.11,
#    Debian 13 has 3.13), when it can make a venv with pip.
# 2. Else the one built earlier in ${HF_PYTHON_CACHE:-~/.cache/hapticfluid}/cpython-3.X.
# 3. Else it builds it there: the upstream tarball of Debian's source package (3.11 from
#    bookworm, 3.13 from trixie; apt fetches and checks it against the signed .dsc, through a
#    private source list, so the system's apt sources stay as they are), then ./configure
#    --prefix=<cache> --disable-test-modules (no PGO: a test interpreter, built in about 6 minutes
#    on 2 busy cores), make, make
#    install. Debian's own patches are not applied: this is CPython as python.org ships it, which
#    is what blender.org's Blender and the bpy wheels embed. The compile runs under `nice -n 19`.
#    The build needs C headers for the modules pip and bpy use (ssl, ctypes, lzma, bz2, zlib,
#    sqlite3, readline): Debian packages, installed as root when missing.
# Progress goes to stderr; the build's own output to <cache>.log.
# Exit status: 0 (path printed); 77 none can be had here (reason on stderr: not Debian, no root
# for the missing headers, the archive unreachable); other: the build failed (see the log).
set -euo pipefail
{
VERSION="${1:-}"
case "$VERSION" in
  3.11) SUITE=bookworm ;;
  3.13) SUITE=trixie ;;
  -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
  *) echo "error: give the version to provide, 3.11 or 3.13 (got '$VERSION')" >&2; exit 2 ;;
esac
say() { echo "$*" >&2; }
cannot() { say "SKIP: no CPython $VERSION here: $*"; exit 77; }
usable() {  # usable PY: a CPython $VERSION that can make a venv with pip
  "$1" -c "import sys, venv, ensurepip, ssl; sys.exit('%d.%d' % sys.version_info[:2] != '$VERSION')" 2>/dev/null
}

for c in "python$VERSION" "/usr/bin/python$VERSION"; do
  if command -v "$c" >/dev/null 2>&1 && usable "$c"; then "$c" -c 'import sys; print(sys.executable)'; exit 0; fi
done
PREFIX="${HF_PYTHON_CACHE:-$HOME/.cache/hapticfluid}/cpython-$VERSION"
if [ -f "$PREFIX/.hf-ok" ] && usable "$PREFIX/bin/python$VERSION"; then echo "$PREFIX/bin/python$VERSION"; exit 0; fi

# ---- build it -----------------------------------------------------------------------------------
[ -f /etc/debian_version ] || cannot "this system is not Debian (install CPython $VERSION and put python$VERSION on PATH)"
command -v apt-get >/dev/null && command -v make >/dev/null && command -v gcc >/dev/null \
  || cannot "apt-get, make and gcc are needed to build it (apt-get install make gcc)"
HEADERS=(libssl-dev zlib1g-dev libffi-dev libbz2-dev liblzma-dev libsqlite3-dev uuid-dev
         libreadline-dev libncurses-dev libexpat1-dev xz-utils)
missing=()
for p in "${HEADERS[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  [ "$(id -u)" -eq 0 ] || cannot "run as root, or first: sudo apt-get install ${missing[*]}"
  say "== python $VERSION: installing ${missing[*]}"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" >&2 \
    || { apt-get update -q >&2 && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" >&2; }
fi

SRC="$PREFIX.src"
LOG="$PREFIX.log"
rm -rf "$PREFIX" "$SRC"
mkdir -p "$SRC/lists/partial" "$SRC/cache/archives/partial"
t0=$SECONDS
say "== python $VERSION: fetching Debian $SUITE's python$VERSION source (log: $LOG)"
echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian $SUITE main" >"$SRC/sources.list"
apt_opts=(-q -o Dir::Etc::SourceList="$SRC/sources.list" -o Dir::Etc::SourceParts=/dev/null
          -o Dir::State::Lists="$SRC/lists" -o Dir::Cache="$SRC/cache" -o APT::Sandbox::User=root)
( cd "$SRC" && apt-get "${apt_opts[@]}" update && apt-get "${apt_opts[@]}" source --download-only "python$VERSION" ) >"$LOG" 2>&1 \
  || { tail -n 5 "$LOG" >&2; cannot "could not fetch Debian $SUITE's python$VERSION source (is the Debian archive reachable?)"; }
orig=("$SRC"/python"$VERSION"_*.orig.tar.[gx]z)  # trixie's python3.13 is .xz, bookworm's python3.11 .gz
[ -f "${orig[0]}" ] || { say "error: no python${VERSION}_*.orig.tar.gz/.xz came with the source package (see $LOG)"; exit 1; }
tar -C "$SRC" -xf "${orig[0]}"
tree=("$SRC"/Python-"$VERSION".*/)
say "== python $VERSION: building $(basename "${tree[0]}") into $PREFIX (nice -n 19, about 5 minutes on 2 free cores)"
(
  cd "${tree[0]}"
  nice -n 19 ./configure --prefix="$PREFIX" --with-ensurepip=install --disable-test-modules
  nice -n 19 make -j "$(nproc)"
  nice -n 19 make install
) >>"$LOG" 2>&1 || { tail -n 20 "$LOG" >&2; say "error: building CPython $VERSION failed (log: $LOG)"; exit 1; }
PY="$PREFIX/bin/python$VERSION"
if ! err="$("$PY" -c 'import ssl, ctypes, lzma, bz2, zlib, sqlite3, readline, venv, ensurepip' 2>&1)"; then
  say "error: the CPython $VERSION built in $PREFIX lacks modules: $err (log: $LOG)"; exit 1
fi
rm -rf "$SRC"
touch "$PREFIX/.hf-ok"
say "   built $("$PY" -V) in $((SECONDS - t0)) s"
echo "$PY"
}
