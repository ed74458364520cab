"""The site built once per session (sphinx -W), shared by the build test and the rendering test."""
import importlib.util
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.dirname(__file__))
from doc_blocks import DOC  # noqa: E402


@pytest.fixture(scope="session")
def built_site(tmp_path_factory):
    """(html folder, the sphinx CompletedProcess)."""
    missing = [m for m in ("sphinx", "myst_parser", "furo") if importlib.util.find_spec(m) is None]
    assert not missing, f"{missing} not installed in {sys.prefix}: ./dembridge test installs requirements.txt"
    out = tmp_path_factory.mktemp("site") / "html"
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", DOC, str(out)]
    return out, subprocess.run(cmd, capture_output=True, text=True, timeout=600)
