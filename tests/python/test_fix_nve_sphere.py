"""fix nve/sphere with the plugin loaded (doc/fix_nve_sphere.md): the plugin's loop over the flat per-atom arrays
(four atoms at a time with AVX2) must give bitwise the numbers of LAMMPS's own fix nve/sphere, run in a separate
process without the plugin: positions, velocities, angular velocities, and the thermo at every 100th step.
The nve/sphere group holds about 70 % of the atoms, scattered, so that most 4-atom blocks hold atoms outside it
(the atom-by-atom path) and some do not (the four-lane path); contacts give every atom torques.
Also: 'disc' in 2d, 'update dipole' (the built-in's form, passed to it), respa, the plugin fix's errors."""
import subprocess

import pytest

import dembridge

COLUMNS = "id x y z vx vy vz omegax omegay omegaz"


def deck(dim=3, atom_style="sphere", integrator="nve/sphere", extra=(), before=(), gravity=None):
    z = "0 8" if dim == 3 else "-0.5 0.5"
    lines = [*before, "units lj", f"atom_style {atom_style}", f"dimension {dim}", "boundary p p p",
             f"region box block 0 8 0 8 {z}", "create_box 2 box", f"lattice {'sc' if dim == 3 else 'sq'} 1.0",
             "create_atoms 1 box", "set group all type/fraction 2 0.3 4321",
             "variable d atom 0.9+0.15*sin(12.9898*x+78.233*y+37.719*z)", "set group all diameter v_d",
             "set group all density 1.3", f"displace_atoms all random 0.05 0.05 {0.05 if dim == 3 else 0} 1234",
             "velocity all create 0.5 5678 loop geom", "variable w atom 0.5*sin(39.346*x+11.135*y+83.155*z)",
             "set group all omega 0.1 -0.2 v_w", *extra, "comm_modify vel yes", "pair_style granular",
             "pair_coeff * * hooke 1000.0 50.0 tangential linear_history 700.0 0.5 0.4", "group moving type 1",
             f"fix G all gravity {gravity or f'1.0 vector 0 {-1 if dim == 2 else 0} {0 if dim == 2 else -1}'}",
             "fix_modify G energy yes", "thermo_style custom step ke pe f_G", "thermo_modify format float %.17g", "thermo 100",
             f"fix I moving {integrator}", *(("fix E all enforce2d",) if dim == 2 else ()), "timestep 0.001", "run 200",
             f"write_dump all custom final.dump {COLUMNS}{' mux muy muz' if 'dipole' in atom_style else ''} "
             "modify sort id format float %.17g"]
    return lines


def run(d, lines, plugin, expect_error=False):
    d.mkdir()
    text = ([f"plugin load {dembridge.plugin_path()}"] if plugin else []) + lines
    (d / "in.deck").write_text("\n".join(text) + "\n")
    p = subprocess.run([dembridge.lmp_executable(), "-in", "in.deck", "-log", "log.lammps", "-screen", "none", "-nocite"],
                       cwd=d, capture_output=True, text=True, timeout=300)
    log = (d / "log.lammps").read_text() if (d / "log.lammps").exists() else ""
    if expect_error:
        assert p.returncode != 0
        return log + p.stdout + p.stderr
    assert p.returncode == 0 and "ERROR" not in log, p.stdout[-2000:] + p.stderr[-2000:] + log[-2000:]
    thermo = [line for line in log.splitlines() if len(line.split()) == 4 and line.split()[0] in ("0", "100", "200")]
    assert len(thermo) == 3
    return (d / "final.dump").read_text().split("ITEM: ATOMS")[-1] + "\n".join(thermo)


CASES = {
    "sphere_3d": dict(),
    "disc_2d": dict(dim=2, integrator="nve/sphere disc"),
    "dipole_builtin": dict(atom_style="hybrid sphere dipole", integrator="nve/sphere update dipole",
                           extra=("set group all dipole/random 97 1.0",)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_bitwise_builtin(tmp_path, case):
    ref = run(tmp_path / "builtin", deck(**CASES[case]), plugin=False)
    got = run(tmp_path / "plugin", deck(**CASES[case]), plugin=True)
    rows = [line.split() for line in ref.strip().split("\n")[1:-3]]
    assert len(rows) == 512 if case != "disc_2d" else len(rows) == 64
    # contacts turned atoms: omega differs from its initial (0.1, -0.2, w) for many (torque reached the integrator)
    turned = [r for r in rows if abs(float(r[7]) - 0.1) > 1e-6]
    assert len(turned) > len(rows) // 4
    assert got == ref  # bit for bit (%.17g)


def test_disc_needs_2d(tmp_path):
    out = run(tmp_path / "r", deck(integrator="nve/sphere disc"), plugin=True, expect_error=True)
    assert "fix I nve/sphere: keyword 'disc' requires a 2d simulation" in out


def test_respa_after_the_fix(tmp_path):
    lines = deck()
    lines.insert(lines.index("timestep 0.001"), "run_style respa 2 2")
    out = run(tmp_path / "r", lines, plugin=True, expect_error=True)
    assert "fix I nve/sphere: run_style respa must come before the fix nve/sphere line" in out


def test_respa_before_the_fix_is_the_builtin(tmp_path):
    lines = deck()
    lines.insert(lines.index("fix I moving nve/sphere"), "run_style respa 2 2")
    ref = run(tmp_path / "builtin", lines, plugin=False)
    assert run(tmp_path / "plugin", lines, plugin=True) == ref
