"""Chung & Ooi (2011) particle-impact benchmarks 1-4 (spec validation-benchmarks §4.1) with the
dembridge LIGGGHTS-compatible pair styles.

    python examples/validation/chung_ooi.py        # runs tests 1-4, prints the figures, writes plots

The "rigid plane" (tests 2-4) is a frozen sphere of radius WALL_RATIO·R (1e4 R) under `fix freeze`
(m* = m_ball, R* = R/(1 + 1e-4)); in test 2 its Young's modulus is 1000 × the ball's (the Yade
convention), in tests 3 and 4 it has the material of the benchmark.
"""
import math

import numpy as np

from val_common import (WALL_RATIO, contact_interval, e_star, header, hertz_force, hertz_impact, mass,
                        material_lines, out_path, print_fix, pyplot, read_record, rel, run_deck)

GLASS = dict(name="glass", E=48e9, nu=0.20, rho=2800.0)
LIMESTONE = dict(name="limestone", E=20e9, nu=0.25, rho=2500.0)
AL_ALLOY = dict(name="Al alloy", E=70e9, nu=0.30, rho=2699.0)
MG_ALLOY = dict(name="Mg alloy", E=40e9, nu=0.35, rho=1800.0)
AL_OXIDE = dict(name="Al oxide", E=380e9, nu=0.23, rho=4000.0)
CAST_IRON = dict(name="cast iron", E=100e9, nu=0.25, rho=7000.0)
AL_ALLOY_T4 = dict(name="Al alloy", E=70e9, nu=0.33, rho=2700.0)


def impact(ball, R, vn, vt=0.0, partner="sphere", wall=None, model="hertz", e=1.0, mu=0.3, steps_per_tc=2000,
           name="impact", pair_style=None):
    """One impact. partner = 'sphere': an identical sphere, the two approach at ±vn along x (V_rel = 2 vn);
    'wall': the ball hits a frozen sphere of radius WALL_RATIO·R (material `wall`) at normal speed vn
    with tangential speed vt along x. Returns the record and the effective parameters."""
    m = mass(ball["rho"], R)
    if partner == "sphere":
        Rw, wall_mat = R, ball
        Es = e_star(ball["E"], ball["nu"], ball["E"], ball["nu"])
        Rs, ms, Vrel = R / 2, m / 2, 2 * vn
    else:
        Rw, wall_mat = WALL_RATIO * R, wall
        Es = e_star(ball["E"], ball["nu"], wall["E"], wall["nu"])
        Rs, ms, Vrel = R * Rw / (R + Rw), m, vn
    amax, pmax, tc = hertz_impact(Es, Rs, ms, Vrel)
    dt = tc / steps_per_tc
    gap = 20 * dt * Vrel
    nsteps = int(1.3 * steps_per_tc) + 60
    rec = out_path(name + ".txt")
    lines = header(4 * R if partner == "sphere" else 1.5 * Rw)
    types = [(ball["E"], ball["nu"])] if partner == "sphere" else [(ball["E"], ball["nu"]), (wall_mat["E"], wall_mat["nu"])]
    lines += [f"create_box {len(types)} box"]
    if partner == "sphere":
        lines += [
            f"create_atoms 1 single {-(R + gap / 2)!r} 0 0 units box",
            f"create_atoms 1 single {R + gap / 2!r} 0 0 units box",
            f"set group all diameter {2 * R!r}",
            f"set group all density {ball['rho']!r}",
            f"set atom 1 vx {vn!r}",
            f"set atom 2 vx {-vn!r}",
            "group ball id 1",
            "group moving id 1 2",
        ]
    else:
        lines += [
            f"create_atoms 1 single 0 0 {R + gap!r} units box",
            f"create_atoms 2 single 0 0 {-Rw!r} units box",
            f"set atom 1 diameter {2 * R!r}",
            f"set atom 2 diameter {2 * Rw!r}",
            f"set group all density {ball['rho']!r}",
            f"set atom 1 vx {vt!r} vz {-vn!r}",
            "group ball id 1",
            "group moving id 1",
            "group wall id 2",
            "fix frz wall freeze",
        ]
    extra = [f"fix m5 all property/global characteristicVelocity scalar {Vrel!r}"] if model == "hooke" else []
    lines += material_lines(types, mu, e, extra)
    lines += [
        f"pair_style {pair_style or f'gran/{model}/history'}",
        "pair_coeff * *",
        f"neighbor {0.01 * R!r} bin",
        "neigh_modify delay 0",
        "fix integ moving nve/sphere",
        f"timestep {dt!r}",
        "compute om all property/atom omegax omegay omegaz",
        "compute omb ball reduce sum c_om[1] c_om[2] c_om[3]",
        print_fix(1, rec, ["step", "x[1]", "y[1]", "z[1]", "x[2]", "y[2]", "z[2]", "vx[1]", "vy[1]", "vz[1]",
                           "vx[2]", "vy[2]", "vz[2]", "fx[1]", "fy[1]", "fz[1]", "c_omb[1]", "c_omb[2]",
                           "c_omb[3]"]),
        f"run {nsteps}",
    ]
    lmp = run_deck(lines, name)
    lmp.close()
    d = read_record(rec)
    t = d[:, 0] * dt
    x1, x2 = d[:, 1:4], d[:, 4:7]
    dx = x1 - x2
    r = np.linalg.norm(dx, axis=1)
    n = dx / r[:, None]
    delta = R + Rw - r
    v1, v2, f1, om = d[:, 7:10], d[:, 10:13], d[:, 13:16], d[:, 16:19]
    Fn = np.einsum("ij,ij->i", f1, n)
    vrel_n = np.einsum("ij,ij->i", v1 - v2, n)
    t0, t1, i0, i1 = contact_interval(t, delta)
    return dict(t=t, delta=delta, Fn=Fn, v=v1, omega=om, vrel_n=vrel_n, n=n, tc=t1 - t0, i0=i0, i1=i1,
                amax=delta.max(), pmax=Fn.max(), closed=dict(amax=amax, pmax=pmax, tc=tc), Es=Es, Rs=Rs, ms=ms,
                Vrel=Vrel, dt=dt, R=R, m=m)


def plot_impacts(results, tc_from, title_overlap, title_history, png):
    """Tests 1 and 2's figure: force against overlap with Hertz's curve (black), and force against time with
    the contact time res[tc_from]["tc"] dashed."""
    plt = pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for res in results:
        on = slice(res["i0"] - 5, res["i1"] + 5)
        a = np.linspace(0, res["amax"], 200)
        ax[0].plot(res["delta"][on] * 1e6, res["Fn"][on] / 1e3, ".", ms=2, label=f"{res['material']} (dembridge)")
        ax[0].plot(a * 1e6, hertz_force(res["Es"], res["Rs"], a) / 1e3, "k-", lw=0.8)
        ax[1].plot((res["t"][on] - res["t"][res["i0"]]) * 1e6, res["Fn"][on] / 1e3, label=res["material"])
        ax[1].axvline(res[tc_from]["tc"] * 1e6, color="k", lw=0.6, ls="--")
    ax[0].set_xlabel("overlap α (µm)")
    ax[0].set_ylabel("normal force (kN)")
    ax[0].set_title(title_overlap)
    ax[0].legend()
    ax[1].set_xlabel("time since first contact (µs)")
    ax[1].set_ylabel("normal force (kN)")
    ax[1].set_title(title_history)
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(out_path(png), dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------------------------------------
# Test 1: two identical spheres, V_rel = 20 m/s, e = 1

def test1(materials=(GLASS, LIMESTONE)):
    results = []
    for mat in materials:
        res = impact(mat, 0.01, 10.0, partner="sphere", e=1.0, name=f"chung1_{mat['name']}")
        on = (res["delta"] > 0.05 * res["amax"])
        F_hz = hertz_force(res["Es"], res["Rs"], res["delta"][on])
        res["curve_err"] = np.max(np.abs(res["Fn"][on] - F_hz) / F_hz)
        res["material"] = mat["name"]
        results.append(res)
    plot_impacts(results, "closed", "Chung & Ooi test 1: force–overlap vs Hertz (black)",
                 "force history; dashed: closed-form t_c", "chung_ooi_test1.png")
    return results


# ---------------------------------------------------------------------------------------------
# Test 2: sphere vs rigid plane, R = 0.1 m, V = 0.2 m/s

def rigid_plane_closed(mat, R, V):
    """Closed forms for a truly rigid plane: E* = E/(1-ν²), R* = R, m* = m."""
    return hertz_impact(mat["E"] / (1 - mat["nu"]**2), R, mass(mat["rho"], R), V)


def test2(materials=(AL_ALLOY, MG_ALLOY)):
    results = []
    for mat in materials:
        wall = dict(name="wall", E=1000 * mat["E"], nu=mat["nu"])
        res = impact(mat, 0.1, 0.2, partner="wall", wall=wall, e=1.0, name=f"chung2_{mat['name'].replace(' ', '_')}")
        res["material"] = mat["name"]
        res["rigid"] = dict(zip(("amax", "pmax", "tc"), rigid_plane_closed(mat, 0.1, 0.2)))
        res["energy_ratio"] = (0.4 * res["pmax"] * res["amax"]) / (0.5 * res["ms"] * res["Vrel"]**2)
        results.append(res)
    plot_impacts(results, "rigid", "test 2: sphere on plane (frozen R=1e4 R sphere, E×1000)",
                 "force history; dashed: rigid-plane t_c", "chung_ooi_test2.png")
    return results


# ---------------------------------------------------------------------------------------------
# Test 3: e_out vs e_in, R = 2.5 mm, V = 3.9 m/s, sphere on a plane of the same material

E_IN = (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
LIMIT_FORCE_REF = {0.2: 0.325, 0.4: 0.472, 0.6: 0.632, 0.8: 0.808}


def test3(materials=(AL_OXIDE, CAST_IRON), models=("hertz", "hooke"), e_in=E_IN):
    rows = []
    for model in models:
        for mat in materials:
            for e in e_in:
                res = impact(mat, 0.0025, 3.9, partner="wall", wall=mat, model=model, e=e, steps_per_tc=1000,
                             name=f"chung3_{model}_{mat['name'].replace(' ', '_')}_{e}")
                v_in, v_out = res["vrel_n"][0], res["vrel_n"][-1]
                rows.append(dict(model=model, material=mat["name"], e_in=e, e_out=-v_out / v_in))
    # not a closed form: LIGGGHTS 3.x `limitForce on` (no attraction at the end of the contact) raises
    # e_out; spec validation-benchmarks §4.1 records 0.325/0.472/0.632/0.808 for e_in 0.2/0.4/0.6/0.8
    limit = []
    for e in LIMIT_FORCE_REF:
        res = impact(AL_OXIDE, 0.0025, 3.9, partner="wall", wall=AL_OXIDE, e=e, steps_per_tc=1000,
                     name=f"chung3_limitForce_{e}", pair_style="gran model hertz tangential history limitForce on")
        limit.append(dict(model="hertz limitForce on", material=AL_OXIDE["name"], e_in=e,
                          e_out=-res["vrel_n"][-1] / res["vrel_n"][0], spec=LIMIT_FORCE_REF[e]))
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 5))
    ax.plot([0, 1], [0, 1], "k-", lw=0.8, label="e_out = e_in")
    ax.plot([r["e_in"] for r in limit], [r["e_out"] for r in limit], "x", color="C3",
            label="hertz, 3.x limitForce on (not a closed form)")
    for model, mk in zip(models, "os"):
        for mat, c in zip(materials, ("C0", "C1")):
            sel = [r for r in rows if r["model"] == model and r["material"] == mat["name"]]
            ax.plot([r["e_in"] for r in sel], [r["e_out"] for r in sel], mk, mfc="none", color=c,
                    label=f"{model}, {mat['name']}")
    ax.set_xlabel("input coefficientRestitution e_in")
    ax.set_ylabel("measured e_out = −v_n'/v_n")
    ax.set_title("Chung & Ooi test 3 (R = 2.5 mm, V = 3.9 m/s)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out_path("chung_ooi_test3.png"), dpi=110)
    plt.close(fig)
    return rows, limit


# ---------------------------------------------------------------------------------------------
# Test 4: oblique impact, |V| = 3.9 m/s, Al oxide sphere on Al alloy plane, μ = 0.092, e = 0.98

MU4, E4, V4, R4 = 0.092, 0.98, 3.9, 0.0025
ANGLES = tuple(range(5, 90, 5))


def sliding_threshold_deg(mu=MU4, e=E4):
    return math.degrees(math.atan(3.5 * mu * (1 + e)))


def rigid_body(theta_deg, mu=MU4, e=E4, V=V4, R=R4):
    """Rigid-body limits: (e_t, ω). Gross sliding above the threshold, rolling (e_t = 5/7) below."""
    th = math.radians(theta_deg)
    vn, vt = V * math.cos(th), V * math.sin(th)
    if math.tan(th) > 3.5 * mu * (1 + e):
        return 1 - mu * (1 + e) / math.tan(th), 2.5 * mu * (1 + e) * vn / R
    return 5.0 / 7.0, (5.0 / 7.0) * vt / R


def test4(angles=ANGLES):
    rows = []
    for th in angles:
        rad = math.radians(th)
        vn, vt = V4 * math.cos(rad), V4 * math.sin(rad)
        res = impact(AL_OXIDE, R4, vn, vt, partner="wall", wall=AL_ALLOY_T4, e=E4, mu=MU4, steps_per_tc=1000,
                     name=f"chung4_{th}")
        v, om = res["v"][-1], res["omega"][-1]
        et_cf, om_cf = rigid_body(th)
        rows.append(dict(theta=th, e_t=v[0] / vt, omega=abs(om[1]), e_n=v[2] / vn, e_t_closed=et_cf,
                         omega_closed=om_cf, sliding=math.tan(rad) > 3.5 * MU4 * (1 + E4)))
    plt = pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    fine = np.linspace(1, 89, 300)
    rb = np.array([rigid_body(t) for t in fine])
    ths = [r["theta"] for r in rows]
    ax[0].plot(fine, rb[:, 0], "k-", lw=0.8, label="rigid body")
    ax[0].plot(ths, [r["e_t"] for r in rows], "o", mfc="none", label="dembridge hertz/history")
    ax[1].plot(fine, rb[:, 1], "k-", lw=0.8, label="rigid body")
    ax[1].plot(ths, [r["omega"] for r in rows], "o", mfc="none", label="dembridge hertz/history")
    for a in ax:
        a.axvline(sliding_threshold_deg(), color="gray", ls="--", lw=0.6)
        a.set_xlabel("impact angle θ from the normal (deg)")
        a.legend()
    ax[0].set_ylabel("tangential COR e_t = v_t'/v_t")
    ax[1].set_ylabel("rebound ω (rad/s)")
    ax[0].set_title("Chung & Ooi test 4: μ = 0.092, e = 0.98")
    ax[1].set_title("dashed: gross-sliding threshold 3.5μ(1+e)")
    fig.tight_layout()
    fig.savefig(out_path("chung_ooi_test4.png"), dpi=110)
    plt.close(fig)
    return rows


if __name__ == "__main__":
    for res in test1():
        c = res["closed"]
        print(f"test1 {res['material']}: amax {res['amax']:.6g} / {c['amax']:.6g} ({rel(res['amax'], c['amax']):+.2e}), "
              f"pmax {res['pmax']:.6g} / {c['pmax']:.6g} ({rel(res['pmax'], c['pmax']):+.2e}), "
              f"tc {res['tc']:.6g} / {c['tc']:.6g} ({rel(res['tc'], c['tc']):+.2e}), curve {res['curve_err']:.1e}")
    for res in test2():
        c = res["rigid"]
        print(f"test2 {res['material']}: amax {res['amax']:.6g} / {c['amax']:.6g} ({rel(res['amax'], c['amax']):+.2e}), "
              f"pmax {res['pmax']:.6g} / {c['pmax']:.6g} ({rel(res['pmax'], c['pmax']):+.2e}), "
              f"tc {res['tc']:.6g} / {c['tc']:.6g} ({rel(res['tc'], c['tc']):+.2e}), energy {res['energy_ratio']:.6f}")
    rows3, limit3 = test3()
    for r in rows3:
        print(f"test3 {r['model']} {r['material']}: e_in {r['e_in']} e_out {r['e_out']:.6f} ({rel(r['e_out'], r['e_in']):+.2e})")
    for r in limit3:
        print(f"test3 limitForce on: e_in {r['e_in']} e_out {r['e_out']:.6f} (spec {r['spec']})")
    for r in test4():
        print(f"test4 θ={r['theta']}: e_t {r['e_t']:.5f} / {r['e_t_closed']:.5f}, ω {r['omega']:.2f} / {r['omega_closed']:.2f}, "
              f"e_n {r['e_n']:.5f}, sliding={r['sliding']}")
