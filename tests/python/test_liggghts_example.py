"""examples/liggghts_deck: the LIGGGHTS deck runs unchanged through dembridge-liggghts (a shorter run),
its frames hold every inserted particle inside the box, and render.py draws them."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

from dembridge import read_vtk_particles

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "liggghts_deck"


def test_example_deck_runs_through_the_launcher_and_renders(tmp_path):
    """The commands of examples/liggghts_deck/README.md (and of the top README) in a fresh copy of the
    folder: dembridge-liggghts -in in.deck (its console-script entry, dembridge.liggghts:main; -var nsteps
    2000, the README's short run), then python render.py."""
    shutil.copy(EXAMPLE / "in.deck", tmp_path)
    shutil.copy(EXAMPLE / "render.py", tmp_path)
    shutil.copytree(EXAMPLE / "meshes", tmp_path / "meshes")
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"), MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, "-c", "import sys; from dembridge.liggghts import main; sys.exit(main())",
                        "-in", "in.deck", "-var", "nsteps", "2000"],
                       cwd=tmp_path, capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0 and "ERROR" not in p.stdout, p.stdout[-2000:]
    assert p.stdout.count("atom_style granular -> atom_style sphere 1") == 1
    frames = [read_vtk_particles(tmp_path / "post" / f"funnel_{s}.vtk") for s in (1000, 2000)]
    for f in frames:
        assert len(f["id"]) == 1059
        lo, hi = f["points"].min(axis=0), f["points"].max(axis=0)
        assert (lo > [-0.06, -0.06, -0.02]).all() and (hi < [0.06, 0.06, 0.16]).all()
    # falling: every particle lower at step 2000 than at 1000 (none has reached the funnel yet)
    assert (frames[1]["points"][:, 2] < frames[0]["points"][:, 2]).all()
    assert sorted(set(frames[0]["radius"])) == [0.0025, 0.0035]
    p = subprocess.run([sys.executable, "render.py"], cwd=tmp_path, capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    assert (tmp_path / "funnel.png").stat().st_size > 10000
