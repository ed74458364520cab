"""pair_modify timestep_check: off by default (a LIGGGHTS deck prints only what LIGGGHTS prints, even at a
time step far beyond the Rayleigh time); when on, a WARNING at run setup whose Rayleigh fraction is
fix check/timestep/gran's f_ID[1] (one computation); bad values are ERRORs."""
import os
import re
import tempfile

import pytest

from bad_input_check import assert_error
from dembridge import new_lammps
from test_heat_timestep_bad_input import BASE


def run(extra, dt, steps=10):
    """Log text of a run of the two-sphere deck at time step dt (the log is read from a file)."""
    lmp = new_lammps()
    with tempfile.TemporaryDirectory() as d:
        log = os.path.join(d, "log")
        lmp.command(f"log {log}")
        for c in BASE + ["pair_style gran model hertz tangential history", "pair_coeff * *", f"timestep {dt}",
                         "velocity all set 0.5 0 0", "fix ts all check/timestep/gran 1 1.0 1.0 warn no",
                         "fix i all nve/sphere", "thermo_style custom step f_ts[1] f_ts[2]", "thermo_modify format float %.17g"] + extra:
            lmp.command(c)
        lmp.command(f"run {steps}")
        f1 = lmp.extract_fix("ts", 0, 1, 0)
        lmp.close()
        return open(log).read(), f1


def test_off_by_default_even_far_beyond_the_rayleigh_time():
    text, f1 = run([], 5e-4)  # 2.6 times the Rayleigh time
    assert f1 > 0.5 and "timestep_check" not in text and "contacts may blow up" not in text


def test_on_warns_with_the_check_fixs_rayleigh_fraction():
    text, f1 = run(["pair_modify timestep_check yes"], 5e-4, steps=1)
    m = re.search(r"WARNING: pair_style gran: the time step 0.0005 is (\S+) % of the Rayleigh time (\S+) of the particles "
                  r"\(pair_modify timestep_check 0.2\): contacts may blow up; use a time step below (\S+)", text)
    assert m, text[-2000:]
    assert float(m.group(1)) == float(f"{100 * f1:.6g}")
    assert float(m.group(3)) == float(f"{0.2 * 5e-4 / f1:.6g}")


def test_on_is_silent_below_the_fraction():
    text, f1 = run(["pair_modify timestep_check 0.5"], 1e-6)
    assert f1 < 0.01 and "contacts may blow up" not in text


@pytest.mark.parametrize("value,frag", [("2", "'2'"), ("maybe", "'maybe'"), ("", "expected yes, no or a fraction")])
def test_bad_values(value, frag):
    assert_error("timestep_check " + value, BASE + ["pair_style gran model hertz tangential history", "pair_coeff * *",
                                                    f"pair_modify timestep_check {value}".strip()],
                 ["pair_modify timestep_check", frag])


def test_needs_youngs_modulus():
    assert_error("numeric", BASE + ["pair_style gran/hooke/history 2000 NULL 50 NULL 0.5 0", "pair_coeff * *",
                                    "pair_modify timestep_check yes", "run 0"],
                 ["pair_modify timestep_check needs youngsModulus and poissonsRatio"])
