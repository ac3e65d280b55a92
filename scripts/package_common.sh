# Sourced by build_wheel.sh, build_extension.sh and tests/package/*.sh.
# hf_python311: prints the CPython 3.11 to make venvs with (Blender 4.2 to 5.0 embed 3.11, so
# the wheel is cp311 and the bpy wheels need 3.11): $HF_WHEEL_PYTHON, else the first python3.11
# on PATH, else /usr/bin/python3.11, that has venv and ensurepip. Returns 1 when there is none.
hf_python311() {
  local c
  for c in "${HF_WHEEL_PYTHON:-}" python3.11 /usr/bin/python3.11; do
    [ -n "$c" ] && command -v "$c" >/dev/null 2>&1 || continue
    if "$c" -c 'import sys, venv, ensurepip; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
      "$c" -c 'import sys; print(sys.executable)'; return 0
    fi
  done
  return 1
}

# hf_wheel_python: prints the CPython to build the wheel with: $HF_WHEEL_PYTHON when set (any
# CPython 3.11 or newer with venv and ensurepip, as pyproject.toml's requires-python allows: e.g.
# Debian 13's /usr/bin/python3, 3.13, the Python Blender 5.1 embeds, for a cp313 wheel), else
# hf_python311's choice. Returns 1, with the reason on stderr, when there is none.
hf_wheel_python() {
  local c="${HF_WHEEL_PYTHON:-}"
  if [ -z "$c" ]; then hf_python311 && return 0
    echo "no CPython 3.11 with venv and ensurepip (set HF_WHEEL_PYTHON to another CPython 3.11+)" >&2; return 1
  fi
  command -v "$c" >/dev/null 2>&1 || { echo "HF_WHEEL_PYTHON='$c' is not a program" >&2; return 1; }
  if ! "$c" -c 'import sys, venv, ensurepip; sys.exit(sys.version_info[:2] < (3, 11))' 2>/dev/null; then
    echo "HF_WHEEL_PYTHON='$c' is not a CPython 3.11+ with venv and ensurepip (Debian: python3-venv)" >&2; return 1
  fi
  "$c" -c 'import sys; print(sys.executable)'
}

# pip's output without the "Location ... is ignored" lines that a pip.conf naming missing
# local indexes adds to every look-up.
hf_pip_quiet() { grep -v '^WARNING: Location ' || true; }
