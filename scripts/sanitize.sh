#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Sanitizer builds (not run by CI: too slow for every run).
#   build-asan/: ASan + UBSan build of every C++ test binary (hf_<layer>_tests) and of the Python
#                module; runs every gtest binary, then pytest (tests/python, not the benchmarks)
#                with libasan preloaded into /usr/bin/python3 (the module is a dlopen'ed library:
#                the ASan runtime must be the first library the process loads).
#   build-tsan/: TSan build of the haptics and session test binaries, run on the thread-heavy
#                suites (the 1 kHz haptic loop, the simulation thread, the mailboxes).
# Usage: scripts/sanitize.sh [asan|tsan|all]   (default: all; --python is accepted and ignored:
#        the ASan run always covers the Python module). HF_JOBS=N build jobs (default 2).
# Times measured on this machine (2 cores shared with other builds): see docs/HARDENING.md,
# "Sanitizer runs". Any sanitizer report fails the run (halt_on_error, -fno-sanitize-recover).
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
JOBS="${HF_JOBS:-2}"
WHAT="${1:-all}"
SUPP="$HF_ROOT/scripts/sanitizers"

# The haptics and session suites (thread-heavy) for TSan.
TSAN_FILTER='Haptic*:FalconDevice*:FalconEnumeration*'

configure() {  # dir flags
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S "$HF_ROOT" -B "$1" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPython_EXECUTABLE=/usr/bin/python3 \
    -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF "${launcher[@]}" \
    -DCMAKE_CXX_FLAGS="$2 -fno-omit-frame-pointer" -DCMAKE_EXE_LINKER_FLAGS="$2" \
    -DCMAKE_SHARED_LINKER_FLAGS="$2" -DCMAKE_MODULE_LINKER_FLAGS="$2" >/dev/null
}

test_binaries() {  # dir -> the hf_<layer>_tests targets this configure made
  cmake --build "$1" --target help | sed -n 's/^\.\.\. \(hf_[a-z]*_tests\)$/\1/p'
}

run_asan() {
  local dir="$HF_ROOT/build-asan"
  local t0=$SECONDS
  configure "$dir" "-fsanitize=address,undefined -fno-sanitize-recover=undefined"
  local bins
  mapfile -t bins < <(test_binaries "$dir")
  cmake --build "$dir" -j"$JOBS" --target "${bins[@]}" _core
  echo "== asan: built ${bins[*]} _core in $((SECONDS - t0)) s"
  # Leak checking is off: Mesa's llvmpipe and libEGL keep allocations until exit, outside our code.
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SUPP/ubsan.supp"
  local t1=$SECONDS
  for b in "${bins[@]}"; do
    echo "== asan: $b"
    "$dir/tests/cpp/$b" --gtest_brief=1
  done
  echo "== asan: C++ tests passed in $((SECONDS - t1)) s"
  # allocator_may_return_null: tests/python/test_memory_errors.py limits the address space and
  # expects a MemoryError from numpy's failed allocation; ASan would otherwise abort the child.
  local t2=$SECONDS
  ASAN_OPTIONS="$ASAN_OPTIONS:allocator_may_return_null=1" \
    LD_PRELOAD="$(gcc -print-file-name=libasan.so) $(gcc -print-file-name=libubsan.so)" \
    PYTHONPATH="$dir/python" /usr/bin/python3 -m pytest -q -p no:cacheprovider "$HF_ROOT/tests/python" \
    -k "not bench"
  echo "== asan: Python tests passed in $((SECONDS - t2)) s; $((SECONDS - t0)) s in all"
}

run_tsan() {
  local dir="$HF_ROOT/build-tsan"
  local t0=$SECONDS
  configure "$dir" "-fsanitize=thread"
  cmake --build "$dir" -j"$JOBS" --target hf_haptics_tests hf_session_tests
  echo "== tsan: built in $((SECONDS - t0)) s"
  for b in hf_haptics_tests hf_session_tests; do
    TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
      "$dir/tests/cpp/$b" --gtest_filter="$TSAN_FILTER" --gtest_brief=1
  done
  echo "== tsan: haptics and session tests passed, $((SECONDS - t0)) s in all"
}

case "$WHAT" in
  asan) run_asan ;;
  tsan) run_tsan ;;
  all) run_tsan; run_asan ;;
  *) echo "usage: $0 [asan|tsan|all]" >&2; exit 2 ;;
esac
