#!/usr/bin/env python3
"""Mutation check of the fast tests: apply one-line physics changes, one at a time, to a scratch copy of the
tree, rebuild incrementally (ccache) and run the fast tests that should notice; report killed/survived.

    .venv/bin/python tests/mutation/run_mutations.py [--list] [--only NAME[,NAME]] [--scratch DIR] [--jobs 2]

The copy holds the tracked files of the working tree as they are (uncommitted edits included), under
/tmp/dembridge-mutants by default; the real tree is only read. Its build uses the tree's venv (.venv) and
CCACHE_DIR (default /work/ccache), so a rebuild after one changed file is a few compiles. Each mutation
replaces one exact line fragment that must occur once in its file (a changed upstream line is reported
as "stale", never silently skipped); the file is restored before the next one. Before any mutation, the
listed tests run on the unchanged copy and must pass. Run it with `nice`: it compiles and runs LIGGGHTS.

killed: at least one listed test fails (the unit tests run first; a mutant they kill is not built into the
plugin); survived: all pass; build-error: the mutant does not compile.
Exit status 0 when every mutation marked `must_kill` is killed.
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import List

ROOT = Path(__file__).resolve().parents[2]

# fast test selections (a few seconds each): ctest entries ("unit.x") or "pytest:" + pytest arguments (node ids
# or a -k filter, shell-quoted) relative to the repository root
ORACLE = "pytest:tests/oracle/"
HISTORY_FAST = ORACLE + "test_oracle_history.py -k '(hooke_oblique or hertz_oblique or hooke_stiffness_oblique) and -1'"
ROLLING_FAST = ORACLE + "test_oracle_rolling_cohesion.py -k 'rolling_ and not multipair and 3x and -1'"
COHESION_FAST = ORACLE + "test_oracle_rolling_cohesion.py -k 'cohesion_sjkr and 3x and -1'"
WALLS_FAST = "pytest:" + " ".join(f"'tests/oracle/test_oracle_walls.py::test_wall_case_matches_liggghts[{c}-1]'"
                               for c in ("zplane_hertz_oblique_epsd_sjkr", "zplane_hooke_oblique_cdt_sjkr2_walltype2"))
MESH_FAST = "pytest:" + " ".join(f"'tests/oracle/test_oracle_walls.py::test_wall_case_matches_liggghts[{c}-1]'"
                              for c in ("mesh_plate_corners_edges", "mesh_box_edges_corner", "mesh_move_rotate_paddle"))


@dataclasses.dataclass
class Mutation:
    name: str
    path: str       # file, relative to the repository root
    old: str        # exact fragment, unique in the file
    new: str
    tests: List[str]
    must_kill: bool = False  # True: a change the suite once let through; a fast test must kill it


MUTATIONS = [
    # the changes an audit found the suite let through
    Mutation("ktToKnUser 0.285714286 -> 2/7", "pair_styles/contact/normal_models.h",
             "c.kn * 0.285714286", "c.kn * (2.0 / 7.0)",
             ["unit.granular", ORACLE + "test_oracle_history.py -k kt_to_kn_user"], must_kill=True),
    Mutation("obtuse-corner edge barycentric sign", "walls/mesh/triangle_contact.cpp",
             "b[in] = 1.0 + dfn / m.edge_len(t, ipp);", "b[in] = 1.0 - dfn / m.edge_len(t, ipp);",
             ["unit.mesh", "unit.walls", MESH_FAST], must_kill=True),
    Mutation("epsd2 stiffness kt*reff*reff -> kt*(reff*reff) (1 ulp)", "pair_styles/contact/rolling_models.h",
             "kr = in.kt * g.reff * g.reff;", "kr = in.kt * (g.reff * g.reff);",
             ["unit.granular", ORACLE + "test_oracle_rolling_cohesion.py -k epsd2"], must_kill=True),
    Mutation("joint off-diagonal sign", "fixes/rigid/joint_solver.cpp",
             "if ((b == d.body1 && b == dj.body2) || (b == d.body2 && b == dj.body1)) Wij = -Wij;",
             "if ((b == d.body1 && b == dj.body1) || (b == d.body2 && b == dj.body2)) Wij = -Wij;",
             ["unit.rigid"], must_kill=True),
    Mutation("MBDyn wire order orientation <-> velocity", "coupling/protocol/nodal_message.cpp",
             "{&k.x, &k.orientation, &k.v, &k.omega, &k.a, &k.omega_dot}",
             "{&k.x, &k.v, &k.orientation, &k.omega, &k.a, &k.omega_dot}",
             ["unit.mbdyn"], must_kill=True),
    Mutation("3.8 shear projection removed", "pair_styles/contact/tangential_models.h",
             "for (int k = 0; k < 3; ++k) shear[k] -= sn * g.n[k];", "for (int k = 0; k < 3; ++k) shear[k] -= 0.0 * sn * g.n[k];",
             ["unit.granular", HISTORY_FAST], must_kill=True),
    # ordinary one-line errors
    Mutation("hertz kn 4/3 -> 3/4", "pair_styles/contact/normal_models.h",
             "c.kn = 4. / 3. * pc.Yeff * sqrtval;", "c.kn = 3. / 4. * pc.Yeff * sqrtval;", ["unit.granular", HISTORY_FAST]),
    Mutation("hertz gamma_t from the normal stiffness", "pair_styles/contact/normal_models.h",
             "c.gammat = -2. * sqrt56 * pc.beta * lane_sqrt(St * meff);",
             "c.gammat = -2. * sqrt56 * pc.beta * lane_sqrt(Sn * meff);", ["unit.granular", HISTORY_FAST]),
    Mutation("hooke gamma_n 3.8 form loses pi^2", "pair_styles/contact/normal_models.h",
             "return lane_sqrt(4. * meff * kn * lsq / (lsq + kPi * kPi));",
             "return lane_sqrt(4. * meff * kn * lsq / (lsq + kPi));", ["unit.granular", HISTORY_FAST]),
    Mutation("tangential damping sign", "pair_styles/contact/tangential_models.h",
             "Ft[k] - gammat * g.vtr[k]);", "Ft[k] + gammat * g.vtr[k]);", ["unit.granular", HISTORY_FAST]),
    Mutation("lever arm R + delta/2", "pair_styles/contact/contact_geometry.h",
             "g.cri = contact_radius_lever ? radi - 0.5 * g.delta : radi;",
             "g.cri = contact_radius_lever ? radi + 0.5 * g.delta : radi;", ["unit.granular", HISTORY_FAST]),
    Mutation("sjkr2 area without the factor 2", "pair_styles/contact/cohesion_models.h",
             "A = kPi * 2. * (2. * ri * rj / (ri + rj)) * (ri + rj - r);",
             "A = kPi * (2. * ri * rj / (ri + rj)) * (ri + rj - r);", ["unit.granular", COHESION_FAST]),
    Mutation("epsd rolling stiffness 2.25 -> 2.5", "pair_styles/contact/rolling_models.h",
             "kr = 2.25 * in.kn * in.mu_r * in.mu_r * g.reff * g.reff;",
             "kr = 2.5 * in.kn * in.mu_r * in.mu_r * g.reff * g.reff;", ["unit.granular", ROLLING_FAST]),
    Mutation("rolling torque limit on the centre distance", "pair_styles/contact/rolling_models.h",
             "const R mx = lane_fabs(in.Fn_limit) * g.reff * in.mu_r;",
             "const R mx = lane_fabs(in.Fn_limit) * g.r * in.mu_r;", ["unit.granular", ROLLING_FAST]),
    Mutation("wall sjkr cap area doubled", "pair_styles/contact/cohesion_models.h",
             "if (model == CohesionModel::Sjkr) A = (ri * ri - r * r) * kPi;",
             "if (model == CohesionModel::Sjkr) A = (ri * ri - r * r) * 2. * kPi;", ["unit.walls", WALLS_FAST]),
    Mutation("edge barycentric of the far node", "walls/mesh/triangle_contact.cpp",
             "b[(ie + 1) % 3] = 1.0 - b[ie];", "b[(ie + 1) % 3] = b[ie];", ["unit.mesh", MESH_FAST]),
    Mutation("Parmec critical step 2/omega -> 1/omega", "fixes/springs/critical_step.cpp",
             "return {(2.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi), omega, xi};",
             "return {(1.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi), omega, xi};",
             ["unit.springs", "pytest:tests/python/test_parmec_critical.py"]),
    Mutation("rigid half-step torque kick doubled", "fixes/rigid/body_rotation.cpp",
             "macro_mv(J, W)) + 0.5 * h * T;", "macro_mv(J, W)) + h * T;",
             ["unit.rigid", "pytest:tests/python/test_parmec_front_end.py -k ball_joint_chain_exact"]),
]


def sh(cmd, cwd, env=None, log=None, timeout=3600):
    t0 = time.monotonic()
    p = subprocess.run(cmd, cwd=str(cwd), env=env, shell=isinstance(cmd, str), stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=timeout)
    if log is not None:
        log.write(f"$ {cmd}\n{p.stdout}\n")
        log.flush()
    return p.returncode, p.stdout, time.monotonic() - t0


def copy_tree(scratch: Path) -> Path:
    """The tracked files of the working tree (as they are on disk) into scratch/src; unchanged files keep
    their time stamps so that the scratch build stays incremental from run to run."""
    src = scratch / "src"
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout.split(b"\0")
    for f in (x.decode() for x in files if x):
        a, b = ROOT / f, src / f
        if a.is_symlink() or not a.is_file():
            continue
        if b.is_file() and b.read_bytes() == a.read_bytes():
            continue
        b.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(a, b)
    venv = src / ".venv"
    if not venv.exists():
        venv.symlink_to((ROOT / ".venv").resolve())
    return src


def targets_of(tests):
    out = set()
    for t in tests:
        if t.startswith("unit."):
            out.add("unit_" + t.split(".")[1])
        else:
            out.add("dembridgeplugin")
        if "mbdyn" in t:
            out.add("mbdyn_testpeer")
    return sorted(out)


def run_tests(src: Path, tests, env, log):
    """Names of the failing selections."""
    failed = []
    for t in tests:
        if t.startswith("pytest:"):
            cmd = f"{src}/.venv/bin/python -m pytest -q -x -p no:cacheprovider {t[len('pytest:'):]}"
            rc, out, _ = sh(cmd, src, env, log)
            if rc == 5:
                raise SystemExit(f"the selection {t!r} collects no test: fix the list")
        else:
            rc, out, _ = sh(["ctest", "-R", f"^{t}$", "--output-on-failure"], src / "build", env, log)
            if "No tests were found" in out:
                raise SystemExit(f"no ctest entry {t!r}: fix the list")
        if rc != 0:
            failed.append(t)
    return failed


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--list", action="store_true", help="print the mutations and exit")
    ap.add_argument("--only", help="comma-separated substrings of mutation names")
    ap.add_argument("--scratch", default="/tmp/dembridge-mutants")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args(argv)
    muts = [m for m in MUTATIONS if not a.only or any(s in m.name for s in a.only.split(","))]
    if a.list:
        for m in muts:
            print(f"{m.name}: {m.path}: {m.old!r} -> {m.new!r}; tests {m.tests}")
        return 0
    scratch = Path(a.scratch).resolve()
    if ROOT == scratch or ROOT in scratch.parents:
        raise SystemExit("the scratch copy must be outside the repository")
    src = copy_tree(scratch)
    env = dict(os.environ, CCACHE_DIR=os.environ.get("CCACHE_DIR", "/work/ccache"), CCACHE_BASEDIR=str(scratch),
               DEMBRIDGE_ROOT=str(src), DEMBRIDGE_PLUGIN=str(src / "build" / "dembridgeplugin.so"),
               DEMBRIDGE_VENV=str(src / ".venv"), OMP_NUM_THREADS="1")
    log = open(scratch / f"mutations-{time.strftime('%Y%m%d-%H%M%S')}.log", "w")  # one log per run
    build = src / "build"
    if not (build / "CMakeCache.txt").is_file():
        rc, out, _ = sh(["cmake", "-S", str(src), "-B", str(build), f"-DPython3_EXECUTABLE={src}/.venv/bin/python",
                         "-DCMAKE_BUILD_TYPE=Release", "-DDEMBRIDGE_WERROR=ON", "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache",
                         "-DCMAKE_C_COMPILER_LAUNCHER=ccache"], src, env, log)
        if rc:
            raise SystemExit("cmake failed:\n" + out[-3000:])
    all_tests = sorted({t for m in muts for t in m.tests})

    def build_for(tests):
        return sh(["cmake", "--build", str(build), f"-j{a.jobs}", "--target", *targets_of(tests)], src, env, log)

    rc, out, secs = build_for(all_tests)
    if rc:
        raise SystemExit("the unchanged copy does not build:\n" + out[-3000:])
    failed = run_tests(src, all_tests, env, log)
    if failed:
        raise SystemExit(f"on the unchanged copy these selections fail already: {failed} (see {log.name})")
    rows = []
    for m in muts:
        f = src / m.path
        text = f.read_text()
        if text.count(m.old) != 1:
            rows.append((m, "stale", f"fragment found {text.count(m.old)} times", 0.0))
            continue
        f.write_text(text.replace(m.old, m.new))
        t0 = time.monotonic()
        try:
            # the unit tests first: a mutant they kill needs no plugin build and no LAMMPS run
            failed, error = [], ""
            for stage in ([t for t in m.tests if t.startswith("unit.")], [t for t in m.tests if not t.startswith("unit.")]):
                if not stage or failed:
                    continue
                rc, out, _ = build_for(stage)
                if rc:
                    error = out.strip().splitlines()[-1] if out.strip() else "build failed"
                    break
                failed = run_tests(src, stage, env, log)
            result = "build-error" if error else "killed" if failed else "survived"
            rows.append((m, result, error or ", ".join(failed), time.monotonic() - t0))
        finally:
            f.write_text(text)
        print(f"{rows[-1][1]:>11}  {m.name}  {rows[-1][2]}", flush=True)
    build_for(all_tests)  # leave the copy built unchanged
    print("\n| mutation | file | result | failing selections | s |\n|---|---|---|---|---|")
    for m, res, detail, secs in rows:
        print(f"| {m.name} | `{m.path}` | {res} | {detail} | {secs:.0f} |")
    bad = [m.name for m, res, _, _ in rows if m.must_kill and res != "killed"]
    if bad:
        print(f"\nnot killed by the fast tests: {bad}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
