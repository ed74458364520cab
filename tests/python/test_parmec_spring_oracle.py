"""fix parmec/spring through LAMMPS against the dynamic Parmec oracle cases (issue 5, acceptance B) and
EQM / the Q8 compatibility flag (deliverable 3). Plugin from $DEMBRIDGE_PLUGIN.

Comparison (oracle README "what a row means"): a row labelled t_n = n h holds v_{n+1}, omega_{n+1}
(time (n+1) h). With the default start (velocity-Verlet) LAMMPS holds v(m h') after step m, so the row
of step n is LAMMPS step (n+1) h/h' for h' = h and h/2: velocities are compared at identical times and no
interpolation enters. Error = max |v - v_oracle| / max |v_oracle| over the rows used,
linear and angular velocity separately. Each case runs at the oracle's h and at h/2: the difference to
Parmec must fall at least as O(h) (ratio >= 1.8) unless it is already at round-off level.
"""
import csv
import gzip
import json
import math
import os

import pytest

from dembridge import new_lammps
from dembridge.outputs import read_dump_by_id as read_dump

ORACLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "parmec-kernels")  # copied from shared/oracle/parmec (tests/data/parmec-kernels/README.md)
R_CUBE = math.sqrt(5.0 / 12.0)  # sphere with the unit cube's inertia (m = 1000, J = 1000/6)
K7 = "table K -1 -1e7 1 1e7"
D8 = "table D -1 -8e5 1 8e5"


def oracle(case, variant=""):
    d = os.path.join(ORACLE, variant, case)
    meta = json.load(open(os.path.join(d, "meta.json")))
    for name in ("history.csv", "history.csv.gz", "history_thinned.csv.gz", "history_sampled.csv.gz"):
        p = os.path.join(d, name)
        if os.path.exists(p):
            f = gzip.open(p, "rt") if p.endswith(".gz") else open(p)
            with f:
                rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
            return meta, rows
    raise FileNotFoundError(d)


def cube_atoms(rows, prefixes):
    """create_atoms lines for unit cubes (bpm/sphere, m = 1000, J = 1000/6) at the oracle's row 0."""
    lines = []
    for p in prefixes:
        x = [rows[0][p + "P" + c] for c in "XYZ"]
        lines.append(f"create_atoms 1 single {x[0]!r} {x[1]!r} {x[2]!r} units box")
    lines += [f"set group all diameter {2 * R_CUBE!r}", "set group all mass 1000.0"]
    for i, p in enumerate(prefixes):
        v = [rows[0].get(p + "V" + c, 0.0) for c in "XYZ"]
        w = [rows[0].get(p + "O" + c, 0.0) for c in "XYZ"]
        lines.append(f"set atom {i + 1} vx {v[0]!r} vy {v[1]!r} vz {v[2]!r} omega {w[0]!r} {w[1]!r} {w[2]!r}")
    return lines


# ------------------------------------------------------------------------------------------------
# case decks: (prefixes, LAMMPS lines before the run) from the oracle's initial row; geometry as in the
# kernel replay tests (tests/unit/springs/test_oracle_dynamic.cpp) and the oracle README

def hung_cube(rows, law, extra=""):
    return [""], cube_atoms(rows, [""]) + [
        f"fix S all parmec/spring {K7} {D8} {extra} spring 0 1 1 1 1 -1 1 1 1 K {law}",
        "fix G all gravity 10.0 vector 0 0 -1"]


def chain(rows, link, top, extra=""):
    prefixes = [f"p{i}_" for i in range(10)]
    spr = [K7, D8, extra]
    for i in range(1, 10):  # spring i-1: cube i at (i,i,i) to cube i-1 at the same point
        spr.append(f"spring {i - 1} {i + 1} {i} {i} {i} {i} {i} {i} {i} K {link}")
    spr.append(f"spring 9 10 10 10 10 -1 10 10 10 K {top}")
    return prefixes, cube_atoms(rows, prefixes) + ["fix S all parmec/spring " + " ".join(spr),
                                                   "fix G all gravity 10.0 vector 0 0 -1"]


def contact(rows, plane, kskn=0.0):
    spr = ["table K 0 0 1 0 2 1e7" if not plane else "table K -1 1e7 0 0 1 0", D8]
    for s, (cx, cy) in enumerate([(0, 0), (1, 0), (1, 1), (0, 1)]):
        opt = f"plane 0 0 1 friction 0.1 kskn {kskn}" if plane else "direction 0 0 1"
        spr.append(f"spring {s} 1 {cx} {cy} 1 -1 {cx} {cy} 0 K dashpot D {opt}")
    return [""], cube_atoms(rows, [""]) + ["fix S all parmec/spring " + " ".join(spr),
                                           "fix G all gravity 10.0 vector 0 0 -1"]


def planar(rows):
    # RESTRAIN z-translation and all rotations: plain 'fix nve' (no rotation; the PLANAR force has no z
    # component, so z stays at its initial value)
    return [""], cube_atoms(rows, [""]) + [
        "fix S all parmec/spring table K -1 -1e5 1 1e5 table D -1 -8e3 1 8e3 "
        "spring 0 1 0.5 0.5 0 -1 0.5 0.5 0 K dashpot D direction 0 0 1 planar"]


def stroke_offset(rows, meta):
    ts = " ".join(repr(float(v)) for v in meta["offset_tseries"])
    return hung_cube(rows, "dashpot D offset O", f"tseries O {ts}")


def run_case(tmp, prefixes, lines, rows, h, refine, start="lammps", integrator="fix I all nve/bpm/sphere",
             tmax=None):
    """Run the deck at h' = h/refine up to the last oracle row used (rows up to tmax); returns ({LAMMPS step: {id: [v(3), omega(3)]}}, rows used). start = 'parmec': the fix's
    'start parmec' with the atoms moved back by h'/2 v0 and rotated back by h'/2 omega0 after the fix
    command (Parmec's initial half drift), so that LAMMPS runs Parmec's leap-frog recurrence."""
    hl = h / refine
    # a row's step is n = round(TIME/h) (labels are accumulated sums; Parmec's sampling phase drifts)
    use = [r for r in rows[1:] if tmax is None or r["TIME"] <= tmax]
    last = round(use[-1]["TIME"] / h)
    dump = tmp / f"v{refine}{start}.dump"
    lmp = new_lammps()
    try:
        for c in ["units si", "atom_style bpm/sphere", "boundary f f f", "atom_modify map array",
                  "comm_modify vel yes cutoff 3.0", "region box block -20 30 -20 30 -20 30", "create_box 1 box"]:
            lmp.command(c)
        for c in lines:
            if c.startswith("fix S ") and start == "parmec":
                c = c.replace("parmec/spring", "parmec/spring start parmec", 1)
            lmp.command(c)
        if start == "parmec":
            for i, p in enumerate(prefixes):
                x = [rows[0][p + "P" + c] - 0.5 * hl * rows[0].get(p + "V" + c, 0.0) for c in "XYZ"]
                lmp.command(f"set atom {i + 1} x {x[0]!r} y {x[1]!r} z {x[2]!r}")
                w = [rows[0].get(p + "O" + c, 0.0) for c in "XYZ"]
                nw = math.sqrt(sum(c * c for c in w))
                if nw > 0 and "bpm" in integrator:
                    ang = -0.5 * hl * nw * 180.0 / math.pi
                    lmp.command(f"set atom {i + 1} quat {w[0] / nw!r} {w[1] / nw!r} {w[2] / nw!r} {ang!r}")
        lmp.command(integrator)
        lmp.command(f"timestep {hl!r}")
        lmp.command(f"variable s equal stride({refine},{(last + 1) * refine},{refine})")
        lmp.command(f"dump D all custom 1 {dump} id vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz")
        lmp.command("dump_modify D every v_s sort id format float %.17g")
        lmp.command("thermo 0")
        lmp.command(f"run {(last + 1) * refine}")
    finally:
        lmp.close()
    d = read_dump(dump)
    if start == "parmec":
        # velocity-Verlet's full-step velocity is half a kick behind Parmec's: v_n = v + h'/2 f/m
        # (omega likewise with the cube's J = 1000/6 when the rotation is integrated)
        rot = 0.5 * hl / (1000.0 / 6.0) if "bpm" in integrator else 0.0
        for snap in d.values():
            for a in snap.values():
                a[:6] = [a[c] + 0.5 * hl * a[6 + c] / 1000.0 for c in range(3)] + [a[3 + c] + rot * a[9 + c]
                                                                                  for c in range(3)]
    return d, use


def error_vs_oracle(d, use, prefixes, h, refine):
    """(linear, angular) max |v - v_oracle| / max |v_oracle| over the rows used."""
    ev = ew = sv = sw = 0.0
    for r in use:
        step = (round(r["TIME"] / h) + 1) * refine
        for i, p in enumerate(prefixes):
            got = d[step][i + 1]
            for c in range(3):
                rv, rw = r.get(p + "V" + "XYZ"[c]), r.get(p + "O" + "XYZ"[c], 0.0)
                if rv is not None:  # spring_chain*: only VZ recorded
                    ev, sv = max(ev, abs(got[c] - rv)), max(sv, abs(rv))
                ew, sw = max(ew, abs(got[3 + c] - rw)), max(sw, abs(rw))
    return ev / sv, (ew / sw if sw > 0 else 0.0)


def difference(a, b):
    """max |a - b| / max |b| over all common dumped steps, linear and angular."""
    ev = ew = sv = sw = 0.0
    for step in b:
        if step not in a:
            continue
        for i in b[step]:
            for c in range(3):
                ev, sv = max(ev, abs(a[step][i][c] - b[step][i][c])), max(sv, abs(b[step][i][c]))
                ew, sw = max(ew, abs(a[step][i][3 + c] - b[step][i][3 + c])), max(sw, abs(b[step][i][3 + c]))
    return ev / sv, (ew / sw if sw > 0 else 0.0)


def measure(tmp, name, deck, rows, h, refines=(1, 2), **kw):
    """Default start at h' = h/r1 and h/r2 against the oracle, 'start parmec' at h/r1 against the oracle,
    and the default start against Parmec's recurrence ('start parmec') at the same step, for both."""
    res = {}
    for refine in refines:
        for start in ("lammps", "parmec"):
            d, use = run_case(tmp, *deck, rows, h, refine, start=start, **kw)
            res[refine, start] = d
    prefixes, (r1, r2) = deck[0], refines
    out = {
        "oracle_h": error_vs_oracle(res[r1, "lammps"], use, prefixes, h, r1),
        "oracle_h2": error_vs_oracle(res[r2, "lammps"], use, prefixes, h, r2),
        "parmec_start_h": error_vs_oracle(res[r1, "parmec"], use, prefixes, h, r1),
        "recurrence_h": difference(res[r1, "lammps"], res[r1, "parmec"]),
        "recurrence_h2": difference(res[r2, "lammps"], res[r2, "parmec"]),
    }
    f = lambda t: f"{t[0]:.2e}/{t[1]:.2e}"  # noqa: E731
    hs = lambda r: "h" if r == 1 else f"h/{r}"  # noqa: E731
    print(f"[agreement] {name} ({len(use)} rows), velocity/angular velocity relative: vs Parmec: default start "
          f"{hs(r1)} {f(out['oracle_h'])}, {hs(r2)} {f(out['oracle_h2'])}; start parmec {hs(r1)} "
          f"{f(out['parmec_start_h'])}; default start vs Parmec's recurrence at the same step: {hs(r1)} "
          f"{f(out['recurrence_h'])}, {hs(r2)} {f(out['recurrence_h2'])}")
    return out


# ------------------------------------------------------------------------------------------------
# Deliverable 3: EQM (local column 8) and CRITICAL against the numbers Parmec printed; the Q8 flag

def setup_only(lines, nrun=0):
    """Run the deck lines ('run nrun') and return the fix's local array rows and global vector."""
    from lammps import LMP_STYLE_GLOBAL, LMP_STYLE_LOCAL, LMP_TYPE_ARRAY, LMP_TYPE_VECTOR
    lmp = new_lammps()
    try:
        for c in ["units si", "atom_style bpm/sphere", "boundary f f f", "atom_modify map array",
                  "comm_modify vel yes cutoff 3.0", "region box block -20 30 -20 30 -20 30", "create_box 1 box"]:
            lmp.command(c)
        for c in lines + ["fix I all nve/bpm/sphere", "timestep 1e-4", "thermo 0", f"run {nrun}"]:
            lmp.command(c)
        loc = [list(r) for r in lmp.numpy.extract_fix("S", LMP_STYLE_LOCAL, LMP_TYPE_ARRAY)]
        crit = [lmp.extract_fix("S", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR, i) for i in (0, 1)]
        return {int(r[0]): r for r in loc}, crit
    finally:
        lmp.close()


def test_eqm_cube_corner_matches_parmec():
    """EQM of the unit cube's corner (1,1,1) (spring case): no direction yet (zero-length follower
    before its first step) = the largest point mass, Parmec 999.9999999999883; CONSTANT direction z:
    Parmec 250.00000000000006."""
    meta, rows = oracle("spring")
    lines = cube_atoms(rows, [""]) + [f"fix S all parmec/spring start parmec {K7} "
                                      "spring 0 1 1 1 1 -1 1 1 1 K spring 1 1 1 1 1 -1 1 1 1 K direction 0 0 1"]
    loc, _ = setup_only(lines)
    got = (loc[0][7], loc[1][7])
    print(f"[agreement] EQM cube corner: {got[0]!r} (Parmec {meta['eqm_p1_corner']!r}), along z {got[1]!r} "
          f"(Parmec {meta['eqm_p1_corner_dir_z']!r})")
    assert abs(got[0] - meta["eqm_p1_corner"]) <= 1e-12 * meta["eqm_p1_corner"]
    assert abs(got[1] - meta["eqm_p1_corner_dir_z"]) <= 1e-12 * meta["eqm_p1_corner_dir_z"]


def test_eqm_and_critical_chain_critical_match_parmec():
    """spring_chain_critical before the first step: EQM of the 9 cube-cube springs (no direction) equals
    Parmec's EQM_pairs_no_direction; CRITICAL per spring / per particle (with the damping ratios
    1/sqrt(2), 0.5) equal Parmec's CRITICAL lists (its eigen helper is accurate to ~1e-8)."""
    meta, rows = oracle("spring_chain_critical")
    _, lines = chain(rows, f"ratio {1 / math.sqrt(2)!r}", "ratio 0.5", "start parmec")
    loc, (per_spring, per_particle) = setup_only(lines)
    pairs = meta["EQM_pairs_no_direction"]
    err = max(abs(loc[s][7] - pairs[s]) / pairs[s] for s in range(9))
    ref_s = min(r[0] for r in meta["CRITICAL_perspring"])
    ref_p = meta["CRITICAL"]
    print(f"[agreement] spring_chain_critical: EQM pairs {err:.1e} relative; CRITICAL per spring {per_spring!r} "
          f"(Parmec {ref_s!r}), per particle {per_particle!r} (Parmec {ref_p!r}, "
          f"{abs(per_particle - ref_p) / ref_p:.1e})")
    assert err <= 1e-12
    assert abs(per_spring - ref_s) <= 1e-12 * ref_s
    assert abs(per_particle - ref_p) <= 2e-8 * ref_p


def test_eqm_q8_flag_values():
    """The hung cube's corner spring after its first step (direction z): EQM with the correct arm 250
    (Parmec's EQM() 250.00000000000006), with 'eqm parmec' the arm 2X - P = 0 of Parmec's force
    routine (quirk Q8): the full mass 1000."""
    meta, rows = oracle("spring_damping_factor")
    got = {}
    for flag in ("correct", "parmec"):
        _, lines = hung_cube(rows, "ratio 1.0", f"eqm {flag}")
        loc, _ = setup_only(lines, nrun=1)
        got[flag] = loc[0][7]
    ref = oracle("spring")[0]["eqm_p1_corner_dir_z"]
    print(f"[agreement] EQM corner along z after step 1: eqm correct {got['correct']!r} (Parmec EQM() {ref!r}), "
          f"eqm parmec {got['parmec']!r}")
    assert abs(got["correct"] - ref) <= 1e-12 * ref
    assert abs(got["parmec"] - 1000.0) <= 1e-12 * 1000.0


# ------------------------------------------------------------------------------------------------
# Acceptance B: the dynamic oracle cases through LAMMPS. Measured on the dev machine (velocity /
# angular velocity, relative; see doc/fix_parmec_spring.md "Validation"); the bounds are ~2-3x those.
# The oracle exists at one step h only, so "error vs Parmec" cannot be halved by halving LAMMPS's step
# alone (at h/2 it tends to Parmec's own discretisation error at h, e.g. 6e-5 for 'spring' where LAMMPS
# at h agrees to 2e-5). What falls as O(h) is the difference between the two integrators at the same
# step: LAMMPS's velocity-Verlet start vs Parmec's leap-frog recurrence, the latter run by the same fix
# with 'start parmec' (exactly Parmec's recurrence without rotation: spring_planar 1.3e-10; with
# rotation it also carries the fix nve/bpm/sphere vs Parmec rotation-update difference).
# The contact cases are impacts of a spinning cube: the max over the impacts is a few % at h.

def _chain_crit(eqm):
    return lambda r, m: chain(r, f"ratio {1 / math.sqrt(2)!r}", "ratio 0.5", f"eqm {eqm}")


# name: (oracle case, variant, deck, options, bound on the default-start error vs Parmec at the first step)
DYNAMIC = {
    "spring": ("spring", "", lambda r, m: hung_cube(r, "dashpot D"), dict(tmax=2.5), 6e-5),
    "spring_damping_factor_q8": ("spring_damping_factor", "", lambda r, m: hung_cube(r, "ratio 1.0", "eqm parmec"),
                                 {}, 3e-4),
    "spring_planar": ("spring_planar", "", lambda r, m: planar(r), dict(integrator="fix I all nve"), 0.1),
    "spring_chain": ("spring_chain", "", lambda r, m: chain(r, "dashpot D", "dashpot D"), dict(tmax=0.6), 2e-5),
    "spring_chain_critical_q8": ("spring_chain_critical", "", _chain_crit("parmec"), {}, 6e-3),
    # Q8 fixed: unstable at the oracle's step (the correct EQM of the links is far larger than Parmec's Q8
    # value ~1.6, so the link dashpots are much stiffer; kernel doc §6), so h/2 and h/4;
    # the error against Parmec is the documented Q8 difference, not an integration error
    "spring_chain_critical_fixed": ("spring_chain_critical", "", _chain_crit("correct"), dict(refines=(2, 4)), 0.6),
    "spring_contact": ("spring_contact", "fixedQ1Q3", lambda r, m: contact(r, False), dict(tmax=1.0), 0.1),
    "spring_contact_plane": ("spring_contact_plane", "fixedQ1Q3", lambda r, m: contact(r, True), dict(tmax=1.0), 0.1),
    "spring_contact_plane_kskn": ("spring_contact_plane_kskn", "", lambda r, m: contact(r, True, 0.5), dict(tmax=1.0),
                                  0.1),
    "spring_stroke_offset": ("spring_stroke_offset", "", lambda r, m: stroke_offset(r, m), dict(tmax=6.0), 3e-4),
}


@pytest.mark.parametrize("name", list(DYNAMIC))
def test_oracle_dynamic_through_lammps(tmp_path, name):
    """Default start at the oracle's step agrees with Parmec within the bound; the difference between
    LAMMPS's start (velocity-Verlet) and Parmec's recurrence ('start parmec', same step) falls as O(h)
    when the step is halved (ratio >= 1.8), linear and angular velocity."""
    case, variant, deck, kw, bound = DYNAMIC[name]
    meta, rows = oracle(case, variant)
    out = measure(tmp_path, name, deck(rows, meta), rows, meta["step"], **kw)
    assert max(out["oracle_h"]) <= bound, out["oracle_h"]
    for c in range(2):
        r1, r2 = out["recurrence_h"][c], out["recurrence_h2"][c]
        if r1 > 1e-12:
            assert r1 / r2 >= 1.8, (c, r1, r2)
    if name == "spring_planar":  # no rotation: 'start parmec' is Parmec's recurrence, to round-off
        assert max(out["parmec_start_h"]) <= 1e-9, out["parmec_start_h"]


def test_oracle_damping_factor_q8_difference(tmp_path):
    """spring_damping_factor with the correct EQM arm (default): the documented Q8 difference. Parmec's
    force routine used the mass 1000 (arm 2X - P = 0) where EQM gives 250: half the dashpot coefficient,
    so the history differs at the 1e-3 level, two orders above the 'eqm parmec' run."""
    meta, rows = oracle("spring_damping_factor")
    errs = {}
    for flag in ("correct", "parmec"):
        d = tmp_path / flag
        d.mkdir()
        res, use = run_case(d, *hung_cube(rows, "ratio 1.0", f"eqm {flag}"), rows, meta["step"], 1)
        errs[flag] = error_vs_oracle(res, use, [""], meta["step"], 1)
    print(f"[agreement] spring_damping_factor vs Parmec at h: eqm correct (Q8 fixed) {errs['correct'][0]:.2e}/"
          f"{errs['correct'][1]:.2e}, eqm parmec {errs['parmec'][0]:.2e}/{errs['parmec'][1]:.2e}")
    assert min(errs["correct"]) > 20 * max(errs["parmec"])


def test_oracle_spring_general_prescribed():
    """spring_general (unit cube, spring + unload + ylim, direction (-1,0,0), prescribed velocity
    schedule): per-step F, SF, STROKE, SS through LAMMPS equal Parmec's. The cube centre is
    0.5000000000000001 (mesh round-off) and the point 0.5: the 1e-16 arm is snapped to the centre, so
    atom_style sphere suffices (bpm/sphere gives the same numbers)."""
    from lammps import LMP_STYLE_LOCAL, LMP_TYPE_ARRAY
    d = os.path.join(ORACLE, "spring_general")
    meta = json.load(open(os.path.join(d, "meta.json")))
    with open(os.path.join(d, "history.csv")) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    h, P, V = meta["step"], [r["PX"] for r in rows], [r["VX"] for r in rows]
    # step 0 used x0 + h/2 v0, v0; step 1 x_{5/2} - h v_2 and v_0 (Q2); step n >= 2 row n-1
    motion = [(P[0] + 0.5 * h * V[0], V[0]), (P[1] - h * V[1], V[0])] + [(P[n - 1], V[n - 1]) for n in
                                                                        range(2, len(rows))]
    num = lambda a: " ".join(repr(float(x)) for x in a)  # noqa: E731
    lmp = new_lammps()
    out = []
    try:
        for c in ["units si", "atom_style sphere", "boundary f f f", "region box block -10 10 -10 10 -10 10",
                  "create_box 1 box", f"create_atoms 1 single {P[0]!r} 0.5 0.5 units box",
                  "set atom 1 diameter 1.0 mass 1000", f"timestep {h!r}", "thermo 0",
                  f"fix S all parmec/spring table K {num(meta['spring'])} table U {num(meta['unload'])} "
                  f"spring 0 1 0.5 0.5 0.5 -1 0.5 0.5 0.5 K unload U ylim {num(meta['ylim'])} direction -1 0 0"]:
            lmp.command(c)
        for x, v in motion:
            lmp.command(f"set atom 1 x {x!r} vx {v!r}")
            lmp.command("run 1 pre no post no")
            out.append(list(lmp.numpy.extract_fix("S", LMP_STYLE_LOCAL, LMP_TYPE_ARRAY)[0]))
    finally:
        lmp.close()
    scale = max(abs(r["spr0_F"]) for r in rows)
    dF = max(max(abs(o[3] - r["spr0_F"]), abs(o[4] - r["spr0_SF"])) for o, r in zip(out[1:], rows[1:])) / scale
    dS = max(abs(o[2] - r["spr0_STROKE"]) for o, r in zip(out[1:], rows[1:]))
    ss = all(o[6] == r["spr0_SS"] for o, r in zip(out[1:], rows[1:]))
    print(f"[agreement] spring_general prescribed through LAMMPS: F,SF {dF:.2e} relative, STROKE {dS:.1e} abs, "
          f"SS equal {ss}")
    assert dF <= 1e-12 and dS <= 1e-15 and ss
