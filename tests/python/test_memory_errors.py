# SPDX-License-Identifier: GPL-3.0-or-later
"""A numpy copy the bindings cannot allocate is a MemoryError, never a crash.

pybind11's ensure() returned a null array on MemoryError and write_vdb used it: the issue's
`ulimit -v 3000000; hf.write_vdb('x.vdb', np.zeros((700, 700, 700)), 0.1)` segfaulted. Each
case runs in a child process whose address space is limited (setrlimit RLIMIT_AS, as `ulimit -v`
does) to what it holds plus a margin smaller than the float32 copy the call needs."""

import subprocess
import sys
import textwrap

import pytest

CHILD = textwrap.dedent("""
    import resource, sys
    import numpy as np
    import hapticfluid as hf

    def vm_bytes():
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
        raise RuntimeError("no VmSize")

    big = np.zeros((400, 400, 400))  # float64, 512 MB; its float32 Fortran copy needs 256 MB
    small = np.zeros((8, 8, 8), dtype=np.float32)
    limit = vm_bytes() + (96 << 20)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    try:
        {call}
    except MemoryError as exc:
        print("MemoryError:", exc)
        sys.exit(0)
    print("no error")
    sys.exit(3)
""")

CALLS = {
    "density": "hf.write_vdb(sys.argv[1], big, 0.1)",
    "pressure": "hf.write_vdb(sys.argv[1], small, 0.1, pressure=big)",
    "velocity": "hf.write_vdb(sys.argv[1], small, 0.1, velocity=(big, small, small))",
}


@pytest.mark.parametrize("case", sorted(CALLS))
def test_write_vdb_copy_that_cannot_be_allocated_is_a_memory_error(case, tmp_path):
    script = CHILD.replace("{call}", CALLS[case])
    proc = subprocess.run([sys.executable, "-c", script, str(tmp_path / "x.vdb")], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, (f"returncode {proc.returncode} (negative: killed by a signal)\n"
                                  f"{proc.stdout}\n{proc.stderr}")
    assert "MemoryError:" in proc.stdout and "allocate" in proc.stdout, proc.stdout
    assert not (tmp_path / "x.vdb").exists()
