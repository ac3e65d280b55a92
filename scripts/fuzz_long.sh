#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The long fuzz run (not run by CI): >= 10 M inputs for each target.
#   falcon_packet  libFuzzer + ASan + UBSan (build/tests/fuzz/fuzz_falcon_packet, from ctest's build),
#                  corpus tests/fuzz/corpus/falcon_packet (new inputs go to build/tests/fuzz/corpus)
#   scene, csv, mesh  tests/fuzz/fuzz_inputs.py, a seeded mutator over tests/fuzz/corpus/<target>
# Usage: scripts/fuzz_long.sh [TARGET...]   (default: all four, one after the other; start one
#        invocation per target to run them side by side); HF_FUZZ_RUNS=N to change 10000000,
#        HF_FUZZ_SEED=S the seed (default 1; a second process on one target needs another seed).
#        The Python targets log their input count and rate every minute; a SIGTERM (kill PID)
#        stops one cleanly and logs the count reached. Figures: docs/HARDENING.md, "Long fuzz runs".
# Rates measured on this machine (2 shared cores, llvmpipe), single process each:
#   scene ~630 inputs/s  -> 10 M in ~4.5 h
#   mesh  ~2700 inputs/s -> 10 M in ~1 h
#   csv   ~740 inputs/s (writes a file per input) -> 10 M in ~4 h
#   falcon_packet ~6400 inputs/s (200 k in 31 s, ASan + UBSan) -> 10 M in ~26 min
# A finding stops that target with exit status 1 and leaves the input in build/fuzz-findings/.
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
HF_BUILD="${HF_BUILD:-$HF_ROOT/build}"
RUNS="${HF_FUZZ_RUNS:-10000000}"
FINDINGS="$HF_BUILD/fuzz-findings"
mkdir -p "$FINDINGS"
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(falcon_packet scene csv mesh)

status=0
for t in "${targets[@]}"; do
  start=$SECONDS
  if [ "$t" = falcon_packet ]; then
    exe="$HF_BUILD/tests/fuzz/fuzz_falcon_packet"
    [ -x "$exe" ] || cmake --build "$HF_BUILD" --target fuzz_falcon_packet
    mkdir -p "$HF_BUILD/tests/fuzz/corpus"
    "$exe" -runs="$RUNS" -max_len=256 -seed="${HF_FUZZ_SEED:-1}" -print_final_stats=1 -artifact_prefix="$FINDINGS/" \
      "$HF_BUILD/tests/fuzz/corpus" "$HF_ROOT/tests/fuzz/seeds" "$HF_ROOT/tests/fuzz/corpus/falcon_packet" || status=1
  else
    PYTHONPATH="$HF_BUILD/python" /usr/bin/python3 "$HF_ROOT/tests/fuzz/fuzz_inputs.py" "$t" \
      --runs "$RUNS" --seed "${HF_FUZZ_SEED:-1}" --crashes "$FINDINGS" || status=1
  fi
  echo "== fuzz $t: ended after $((SECONDS - start)) s (the count reached is in the lines above)"
done
exit $status
