#!/usr/bin/env bash
# Sanitizer builds (not run by CI: too slow for every run).
#   build-asan/: ASan + UBSan build of the C++ tests (hf_cpp_tests) and, with --python, of the
#                Python module, run under pytest with libasan preloaded.
#   build-tsan/: TSan build of the C++ tests, run on the haptics and session suites (the threads:
#                the 1 kHz haptic loop, the simulation thread, the mailboxes).
# Usage: scripts/sanitize.sh [asan|tsan|all] [--python]   (default: all)
# Time on this machine (2 shared cores, llvmpipe), measured: the TSan build of hf_cpp_tests 996 s,
# its haptics/session run (76 tests) 18 s, no reports. The ASan build is of the same size (~17 min
# expected); its full gtest run was not timed yet.
# Findings: any sanitizer report fails the run (halt_on_error / -fno-sanitize-recover).
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
JOBS="${HF_JOBS:-2}"
WHAT="${1:-all}"
PYTHON_TOO=0
for a in "$@"; do [ "$a" = "--python" ] && PYTHON_TOO=1; done

# The haptics and session suites (thread-heavy) for TSan.
TSAN_FILTER='Haptic*:FalconDevice*:FalconEnumeration*'

configure() {  # dir flags
  cmake -S "$HF_ROOT" -B "$1" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPython_EXECUTABLE=/usr/bin/python3 \
    -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF \
    -DCMAKE_CXX_FLAGS="$2 -fno-omit-frame-pointer" -DCMAKE_EXE_LINKER_FLAGS="$2" \
    -DCMAKE_SHARED_LINKER_FLAGS="$2" -DCMAKE_MODULE_LINKER_FLAGS="$2" >/dev/null
}

run_asan() {
  local dir="$HF_ROOT/build-asan"
  local t0=$SECONDS
  configure "$dir" "-fsanitize=address,undefined -fno-sanitize-recover=undefined"
  cmake --build "$dir" -j"$JOBS" --target hf_cpp_tests
  echo "== asan: built in $((SECONDS - t0)) s"
  # Leak checking is off: Mesa's llvmpipe and libEGL keep allocations until exit, outside our code.
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:strict_string_checks=1 \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$dir/tests/cpp/hf_cpp_tests" --gtest_brief=1
  echo "== asan: C++ tests passed, $((SECONDS - t0)) s in all"
  if [ "$PYTHON_TOO" = 1 ]; then
    cmake --build "$dir" -j"$JOBS" --target _core
    ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      LD_PRELOAD="$(gcc -print-file-name=libasan.so) $(gcc -print-file-name=libubsan.so)" \
      PYTHONPATH="$dir/python" /usr/bin/python3 -m pytest -q -p no:cacheprovider "$HF_ROOT/tests/python" \
      -k "not bench"
    echo "== asan: Python tests passed, $((SECONDS - t0)) s in all"
  fi
}

run_tsan() {
  local dir="$HF_ROOT/build-tsan"
  local t0=$SECONDS
  configure "$dir" "-fsanitize=thread"
  cmake --build "$dir" -j"$JOBS" --target hf_cpp_tests
  echo "== tsan: built in $((SECONDS - t0)) s"
  TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
    "$dir/tests/cpp/hf_cpp_tests" --gtest_filter="$TSAN_FILTER" --gtest_brief=1
  echo "== tsan: haptics and session tests passed, $((SECONDS - t0)) s in all"
}

case "$WHAT" in
  asan) run_asan ;;
  tsan) run_tsan ;;
  all) run_tsan; run_asan ;;
  *) echo "usage: $0 [asan|tsan|all] [--python]" >&2; exit 2 ;;
esac
