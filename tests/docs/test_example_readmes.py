"""Every command an example README tells a user to type runs, as written, and writes what the README says
(readme_commands.py: the markers; long runs made short only through options the README documents).

A block runs from the top of a scratch copy of the source tree: the example's folder copied fresh, the
repository's .venv, build folder and python package linked in, the venv's bin on PATH with the console
script pip installs (dembridge-liggghts), so nothing is written into the repository."""
import os
import shutil
import subprocess
import time

import pytest

from doc_blocks import ROOT
import readme_commands

COMMANDS = readme_commands.commands()
HOW_TO_MARK = ("Put <!-- docs-test: run | short FILE ARGS | writes PATH --> (this test runs the block) or "
               "<!-- docs-test: run by tests/python/test_x.py::test_name --> (that test runs the same command) "
               "on the line before the ```bash fence (tests/docs/readme_commands.py).")


def test_every_example_has_a_readme_with_a_command():
    ex = os.path.join(ROOT, "examples")
    have = {e for _, e, _, _ in COMMANDS}
    missing = [d for d in sorted(os.listdir(ex)) if os.path.isdir(os.path.join(ex, d)) and d not in have]
    assert not missing, f"examples without a README that shows its command in a ```bash block: {missing}"


def test_every_readme_command_is_run_by_a_test():
    bad = []
    for where, example, _, what in COMMANDS:
        try:
            if what is None:
                raise ValueError("no docs-test marker")
            how = readme_commands.parse(what)
        except ValueError as e:
            bad.append(f"{where}: {e}")
            continue
        if how[0] == "by":
            path = os.path.join(ROOT, how[1])
            text = open(path).read() if os.path.isfile(path) else ""
            if f"def {how[2]}(" not in text or example not in text:
                bad.append(f"{where}: {how[1]} has no {how[2]} about examples/{example}")
    assert not bad, HOW_TO_MARK + "\n" + "\n".join(bad)


def scratch_tree(top, example):
    """A source tree as a fresh clone after the build: the example copied, the rest linked."""
    venv = os.environ.get("DEMBRIDGE_VENV") or os.path.join(ROOT, ".venv")
    build = os.path.dirname(os.environ["DEMBRIDGE_PLUGIN"]) if os.environ.get("DEMBRIDGE_PLUGIN") else os.path.join(ROOT, "build")
    for name, target in ((".venv", venv), ("build", build), ("python", os.path.join(ROOT, "python")),
                         ("CMakeLists.txt", os.path.join(ROOT, "CMakeLists.txt")), ("dembridge", os.path.join(ROOT, "dembridge"))):
        os.symlink(target, os.path.join(top, name))
    shutil.copytree(os.path.join(ROOT, "examples", example), os.path.join(top, "examples", example),
                    ignore=shutil.ignore_patterns("out", "post", "__pycache__"))
    scripts = os.path.join(top, ".scripts")  # the console script `pip install .` puts in the venv's bin
    os.makedirs(scripts)
    with open(os.path.join(scripts, "dembridge-liggghts"), "w") as fh:
        fh.write(f"#!{venv}/bin/python\nimport sys\nfrom dembridge.liggghts import main\nsys.exit(main())\n")
    os.chmod(os.path.join(scripts, "dembridge-liggghts"), 0o755)
    env = {k: v for k, v in os.environ.items() if not k.startswith("DEMBRIDGE_")}
    env.update(PATH=f"{scripts}:{venv}/bin:{os.environ['PATH']}", PYTHONPATH=os.path.join(top, "python"),
               MPLBACKEND="Agg", OMP_NUM_THREADS="1")
    return env


RUNS = [(where, example, body, readme_commands.parse(what)) for where, example, body, what in COMMANDS
        if what and not what.startswith("run by")]


@pytest.mark.parametrize("where,example,body,how", RUNS, ids=[r[0] for r in RUNS])
def test_readme_command_runs_as_written(where, example, body, how, tmp_path):
    _, short, writes = how
    env = scratch_tree(str(tmp_path), example)
    script = readme_commands.shortened(body, short)
    start = time.time()
    p = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", script], cwd=tmp_path, env=env, text=True,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, timeout=300)
    print(f"{where}: {time.time() - start:.1f} s")
    assert p.returncode == 0 and "Traceback" not in p.stdout and "ERROR" not in p.stdout, (
        f"the commands of {where} failed, run as\n{script}\n{p.stdout[-3000:]}")
    folder = tmp_path / "examples" / example
    stale = [w for w in writes if not (folder / w).is_file() or (folder / w).stat().st_mtime < start - 1
             or (folder / w).stat().st_size == 0]
    assert not stale, f"{where}: not written by the commands: {stale}\n{p.stdout[-2000:]}"
