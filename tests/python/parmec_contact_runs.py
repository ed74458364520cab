"""Shared harness of the fix parmec/granular tests (test_parmec_granular.py, test_parmec_mesh_contact.py): a Parmec
script's HISTORY lists on 1 and 2 MPI ranks, the ERROR of a bad fix definition, per-atom arrays in atom-ID order."""
import json
import os
import subprocess
import sys

import pytest

from dembridge import mpiexec, new_lammps

HERE = os.path.dirname(os.path.abspath(__file__))


def histories_on_ranks(tmp_path, body, argv=(), name="H", ranks=(1, 2)):
    """{n: the script's global `name` (HISTORY lists) after run_script on n ranks}, each run in its own process."""
    driver = tmp_path / "driver.py"
    script = tmp_path / "ranks_model.py"
    script.write_text("import math\n" + body)
    driver.write_text(
        "import json, sys\nfrom mpi4py import MPI\nfrom dembridge.parmec import run_script\n"
        f"H = run_script(sys.argv[1], {list(argv)!r})[{name!r}]\n"
        "if MPI.COMM_WORLD.Get_rank() == 0:\n    json.dump(H, open(sys.argv[2], 'w'))\n")
    env = dict(os.environ, PYTHONPATH=os.path.join(HERE, "..", "..", "python"))
    out = {}
    for n in ranks:
        res = tmp_path / f"h{n}.json"
        cmd = [sys.executable, str(driver), str(script), str(res)]
        if n > 1:
            cmd = [mpiexec(), "-n", str(n)] + cmd
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
        assert r.returncode == 0, r.stdout + r.stderr
        out[n] = json.load(open(res))
    return out


def fix_error(defs):
    """The error of 'fix G all parmec/granular DEFS' in a one-sphere deck (it must fail, naming the fix)."""
    lmp = new_lammps()
    for c in ["units si", "atom_style sphere", "region b block -1 1 -1 1 -1 1", "create_box 1 b",
              "create_atoms 1 single 0 0 0", "pair_style zero 0.1", "pair_coeff * *", "comm_modify vel yes"]:
        lmp.command(c)
    with pytest.raises(Exception) as e:
        lmp.command("fix G all parmec/granular " + defs)
    lmp.close()
    assert "fix G parmec/granular" in str(e.value), str(e.value)
    return str(e.value)


def atoms_by_id(lmp, *names):
    """The per-atom arrays `names` ("x", "v", ...) of a serial LAMMPS side by side, rows in atom-ID order (the
    restart tests compare whole states bitwise)."""
    import numpy as np
    n = lmp.get_natoms()
    order = np.argsort(lmp.numpy.extract_atom("id")[:n])
    return np.hstack([lmp.numpy.extract_atom(a)[:n][order] for a in names])
