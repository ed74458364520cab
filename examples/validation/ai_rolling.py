"""Ai, Chen, Rotter & Ooi (2011) rolling-resistance benchmarks (spec validation-benchmarks §4.3):
a ball (R = 5 mm, ρ = 2500) rolling on a flat surface with `rolling_friction cdt` / `epsd`, and a
ball on a slope (gravity tilted by θ), with gran/hertz/history.

    python examples/validation/ai_rolling.py

The flat surface is one frozen sphere of radius PLANE_R = 1e5 m (`fix freeze`): over the 0.7 m the
ball rolls, its slope changes by < 1e-5 rad, i.e. a spurious tangential gravity < 7e-5 m/s² against
a rolling deceleration of 0.70 m/s² (< 0.01 %). R* = R/(1 + 5e-8). The ball starts at its static
Hertz overlap under m g cos θ, in pure rolling (ω = v0/R).
"""
import math

import numpy as np

from val_common import G, header, mass, out_path, print_fix, pyplot, read_record, rel, run_deck, e_star

R, RHO = 0.005, 2500.0
E, NU = 1.0e8, 0.3                 # stiff-but-coarse: static overlap 1.8 µm, contact period 2.2 ms
MU, E_REST = 0.5, 0.5              # sliding friction (no slip while rolling), restitution
MU_R, ETA_R = 0.1, 0.3             # coefficientRollingFriction, coefficientRollingViscousDamping
PLANE_R = 1.0e5
DT = 1.0e-5


def rolling_closed_slope(mu_r=MU_R, theta_deg=0.0):
    """Acceleration along the slope (positive downhill) of a ball rolling without slip against a CDT
    torque μ_r R* F_n: a = (5/7) g (sin θ − μ_r cos θ) (flat: −(5/7) μ_r g)."""
    th = math.radians(theta_deg)
    return 5.0 / 7.0 * G * (math.sin(th) - mu_r * math.cos(th))


def roll(model="cdt", v0=1.0, theta_deg=0.0, duration=1.0, every=100, mu_r=MU_R, name="roll"):
    m = mass(RHO, R)
    Rs = R * PLANE_R / (R + PLANE_R)
    Es = e_star(E, NU, E, NU)
    th = math.radians(theta_deg)
    delta0 = (3 * m * G * math.cos(th) / (4 * Es * math.sqrt(Rs))) ** (2.0 / 3.0)
    rec = out_path(name + ".txt")
    nsteps = int(round(duration / DT))
    lines = header(1.5 * PLANE_R) + [
        "create_box 2 box",
        f"create_atoms 1 single 0 0 {R - delta0!r} units box",
        f"create_atoms 2 single 0 0 {-PLANE_R!r} units box",
        f"set atom 1 diameter {2 * R!r}",
        f"set atom 2 diameter {2 * PLANE_R!r}",
        f"set group all density {RHO!r}",
        f"set atom 1 vx {v0!r} omega 0 {v0 / R!r} 0",
        "group ball id 1",
        "group plane id 2",
        "fix frz plane freeze",
        f"fix m1 all property/global youngsModulus peratomtype {E!r} {E!r}",
        f"fix m2 all property/global poissonsRatio peratomtype {NU!r} {NU!r}",
        f"fix m3 all property/global coefficientRestitution peratomtypepair 2 {' '.join([repr(E_REST)] * 4)}",
        f"fix m4 all property/global coefficientFriction peratomtypepair 2 {' '.join([repr(MU)] * 4)}",
        f"fix m5 all property/global coefficientRollingFriction peratomtypepair 2 {' '.join([repr(mu_r)] * 4)}",
        f"fix m6 all property/global coefficientRollingViscousDamping peratomtypepair 2 {' '.join([repr(ETA_R)] * 4)}",
        f"pair_style gran/hertz/history rolling_friction {model}",
        "pair_coeff * *",
        f"neighbor {0.01 * R!r} bin",
        "neigh_modify delay 0",
        "fix integ ball nve/sphere",
        f"fix grav ball gravity {G!r} vector {math.sin(th)!r} 0 {-math.cos(th)!r}",
        f"timestep {DT!r}",
        "compute om all property/atom omegay",
        "compute omb ball reduce sum c_om",
        print_fix(every, rec, ["step", "x[1]", "z[1]", "vx[1]", "vz[1]", "c_omb"]),
        f"run {nsteps}",
    ]
    lmp = run_deck(lines, name)
    lmp.close()
    d = read_record(rec)
    return dict(t=d[:, 0] * DT, x=d[:, 1], z=d[:, 2], vx=d[:, 3], vz=d[:, 4], wy=d[:, 5], v0=v0, theta=theta_deg,
                model=model)


def fit_slope(t, v, t0, t1):
    sel = (t >= t0) & (t <= t1)
    return np.polyfit(t[sel], v[sel], 1)


def flat():
    """cdt from v0 = 1 m/s for 1.0 s (closed-form stop 1.43 s): the deceleration slope; cdt and epsd
    from v0 = 0.2 m/s for 0.5 s (stop 0.285 s): epsd comes to rest, cdt chatters about rest."""
    a_cf = rolling_closed_slope()
    res = {}
    long = roll("cdt", 1.0, duration=1.0, name="ai_flat_cdt_v1")
    slope, icpt = fit_slope(long["t"], long["vx"], 0.02, 1.0)
    win = long["t"] >= 0.02
    vcf = 1.0 + a_cf * long["t"]
    res["cdt"] = dict(run=long, slope=slope, intercept=icpt, slope_closed=a_cf,
                      max_dev=np.max(np.abs(long["vx"][win] - vcf[win])) / 1.0,
                      t_stop_extrapolated=-icpt / slope, t_stop_closed=-1.0 / a_cf)
    short = {}
    for model in ("cdt", "epsd"):
        r = roll(model, 0.2, duration=0.5, name=f"ai_flat_{model}_v02")
        s, c = fit_slope(r["t"], r["vx"], 0.02, 0.25)
        tail = r["t"] >= 0.4
        short[model] = dict(run=r, slope=s, t_stop_extrapolated=-c / s, tail_vmax=np.max(np.abs(r["vx"][tail])),
                            tail_wmax=np.max(np.abs(r["wy"][tail])), tail_drift=r["x"][-1] - r["x"][tail][0])
    res["short"] = short
    res["t_stop_short_closed"] = -0.2 / a_cf

    plt = pyplot()
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.2))
    t = long["t"]
    ax[0].plot(t, long["vx"], label="cdt, dembridge")
    ax[0].plot(t, np.maximum(1.0 + a_cf * t, 0), "k--", lw=0.8, label="v0 − (5/7) μr g t")
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("ball velocity (m/s)")
    ax[0].set_title(f"Ai et al.: rolling on a plane, μr = {MU_R}, v0 = 1 m/s")
    ax[0].legend()
    for model, st in (("cdt", "-"), ("epsd", "-")):
        r = short[model]["run"]
        ax[1].plot(r["t"], r["vx"], st, lw=0.9, label=model)
    ax[1].plot(short["cdt"]["run"]["t"], np.maximum(0.2 + a_cf * short["cdt"]["run"]["t"], 0), "k--", lw=0.8,
               label="closed form")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("ball velocity (m/s)")
    ax[1].set_title("v0 = 0.2 m/s: stop at 7v0/(5 μr g) = %.3f s" % res["t_stop_short_closed"])
    ax[1].legend()
    for model in ("cdt", "epsd"):
        r = short[model]["run"]
        late = r["t"] >= 0.3
        ax[2].plot(r["t"][late], r["wy"][late], lw=0.8, label=model)
    ax[2].set_xlabel("t (s)")
    ax[2].set_ylabel("ball spin ω_y (rad/s)")
    ax[2].set_title("after the stop: cdt chatters, epsd rests")
    ax[2].legend()
    fig.tight_layout()
    fig.savefig(out_path("ai_rolling_flat.png"), dpi=110)
    plt.close(fig)
    return res


SLOPE_TAN = (0.05, 0.08, 0.095, 0.105, 0.12, 0.15)   # tan θ / μr = 0.5 ... 1.5


def slope(tans=SLOPE_TAN, models=("cdt", "epsd"), duration=0.3):
    """Ball released at rest on a slope: at rest iff tan θ ≤ μr; otherwise a = (5/7) g (sin θ − μr cos θ)."""
    rows = []
    for model in models:
        for tn in tans:
            th = math.degrees(math.atan(tn))
            r = roll(model, 0.0, theta_deg=th, duration=duration, every=50, name=f"ai_slope_{model}_{tn}")
            a_cf = rolling_closed_slope(theta_deg=th)
            s, _ = fit_slope(r["t"], r["vx"], 0.05, duration)
            rows.append(dict(model=model, tan=tn, theta=th, a=s, a_closed=max(a_cf, 0.0), rolls_closed=a_cf > 0,
                             dist=r["x"][-1] - r["x"][0], vmax_end=abs(r["vx"][-1]), run=r))
    plt = pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for model, mk in zip(models, "os"):
        sel = [w for w in rows if w["model"] == model]
        ax[0].plot([w["tan"] / MU_R for w in sel], [w["a"] for w in sel], mk, mfc="none", label=model)
    tt = np.linspace(0.4, 1.6, 200) * MU_R
    ax[0].plot(tt / MU_R, [max(rolling_closed_slope(theta_deg=math.degrees(math.atan(x))), 0) for x in tt], "k-",
               lw=0.8, label="closed form")
    ax[0].set_xlabel("tan θ / μr")
    ax[0].set_ylabel("downhill acceleration (m/s²)")
    ax[0].set_title(f"ball on a slope, μr = {MU_R}")
    ax[0].legend()
    for w in rows:
        if w["model"] == "epsd":
            ax[1].plot(w["run"]["t"], w["run"]["x"] - w["run"]["x"][0], label=f"tan θ/μr = {w['tan'] / MU_R:.2f}")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("downhill displacement (m), epsd")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out_path("ai_rolling_slope.png"), dpi=110)
    plt.close(fig)
    return rows


if __name__ == "__main__":
    f = flat()
    c = f["cdt"]
    print(f"flat cdt: slope {c['slope']:.6f} / {c['slope_closed']:.6f} ({rel(c['slope'], c['slope_closed']):+.2e}), "
          f"max |v - v_cf| {c['max_dev']:.2e} m/s, stop {c['t_stop_extrapolated']:.5f} / {c['t_stop_closed']:.5f}")
    for model, s in f["short"].items():
        print(f"flat {model} v0=0.2: slope {s['slope']:.6f}, stop {s['t_stop_extrapolated']:.5f} / "
              f"{f['t_stop_short_closed']:.5f}, tail |v| {s['tail_vmax']:.2e} |ω| {s['tail_wmax']:.2e} drift {s['tail_drift']:.2e}")
    for w in slope():
        print(f"slope {w['model']} tan/μr={w['tan'] / MU_R:.2f}: a {w['a']:.6f} / {w['a_closed']:.6f}, "
              f"dist {w['dist']:.3e}, |v_end| {w['vmax_end']:.2e}")
