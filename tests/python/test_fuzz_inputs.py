# SPDX-License-Identifier: GPL-3.0-or-later
"""The short fuzz run of the Python-facing inputs (tests/fuzz/fuzz_inputs.py): the seed corpus and
a few thousand seeded mutations each of the scene JSON, the pose CSV and the mesh checks must be
accepted or refused with the documented error, never anything else. The long run (>= 10 M inputs
each) is scripts/fuzz_long.sh."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fuzz"))
import fuzz_inputs  # noqa: E402

RUNS = {"scene": 3000, "csv": 3000, "mesh": 2000}


@pytest.mark.parametrize("target", sorted(RUNS))
def test_short_fuzz_run(tmp_path, target):
    result = fuzz_inputs.run(target, RUNS[target], seed=1, crashes=tmp_path)
    assert result["inputs"] == RUNS[target] + len(fuzz_inputs.load_corpus(target))


def test_the_mutator_changes_inputs_and_is_seeded():
    import random

    corpus = fuzz_inputs.load_corpus("scene")
    a = [fuzz_inputs.mutate(corpus[0], corpus, random.Random(7)) for _ in range(20)]
    b = [fuzz_inputs.mutate(corpus[0], corpus, random.Random(7)) for _ in range(20)]
    assert a == b
    assert sum(x != corpus[0] for x in a) >= 15


def test_mesh_encoding_round_trips():
    import numpy as np
    from hapticfluid import meshes

    v, t = meshes.box((0.2, 0.2, 0.2))
    v2, t2 = fuzz_inputs.decode_mesh(fuzz_inputs.encode_mesh(v, t))
    np.testing.assert_array_equal(v2, np.asarray(v, np.float32))
    np.testing.assert_array_equal(t2, np.asarray(t, np.int32))
