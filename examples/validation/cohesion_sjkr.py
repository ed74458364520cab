"""A cohesive contact with `cohesion sjkr` (spec granular-models §6): the cohesive force equals
cohesionEnergyDensity × the area π a² of the lens-intersection circle.

    python examples/validation/cohesion_sjkr.py

(a) static: two spheres (R1 = 5 mm, R2 = 5 mm and 3 mm) held at a set overlap, at rest, `run 0`:
    F_coh = F(cohesion sjkr) − F(cohesion off), from the per-atom forces and from compute
    pair/gran/local (column Fn), against k π a², a² = [(−d+r1+r2)(d+r1−r2)(d−r1+r2)(d+r1+r2)]/(4 d²);
    and the total force against the closed form (4/3) E* sqrt(R*) δ^{3/2} − k π a².
(b) dynamic: the same two spheres touching at rest with no gravity are pulled together by the
    cohesion and settle (e = 0.3) at the overlap where Hertz balances k π a²(δ) (bisection).
"""
import math

import numpy as np

from val_common import e_star, header, hertz_force, mass, out_path, print_fix, pyplot, read_record, rel, run_deck

E, NU, RHO = 5.0e7, 0.3, 2500.0
K_COH = 3.0e5            # cohesionEnergyDensity (J/m³)
E_REST = 0.3


def lens_area(r1, r2, d):
    """π a² of the circle where two spheres at centre distance d intersect."""
    return math.pi * (-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2) / (4 * d * d)


def deck(r1, r2, d, cohesion, v=(0.0, 0.0), run=0, every=0, rec=None, dt=1e-6):
    lines = header(4 * max(r1, r2)) + [
        "create_box 1 box",
        f"create_atoms 1 single 0 0 0 units box",
        f"create_atoms 1 single {d!r} 0 0 units box",
        f"set atom 1 diameter {2 * r1!r}",
        f"set atom 2 diameter {2 * r2!r}",
        f"set group all density {RHO!r}",
        f"set atom 1 vx {v[0]!r}",
        f"set atom 2 vx {v[1]!r}",
        f"fix m1 all property/global youngsModulus peratomtype {E!r}",
        f"fix m2 all property/global poissonsRatio peratomtype {NU!r}",
        f"fix m3 all property/global coefficientRestitution peratomtypepair 1 {E_REST!r}",
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5",
        f"fix m5 all property/global cohesionEnergyDensity peratomtypepair 1 {K_COH!r}",
        f"pair_style gran/hertz/history cohesion {cohesion}",
        "pair_coeff * *",
        f"neighbor {0.01 * r2!r} bin",
        "neigh_modify delay 0",
        "fix integ all nve/sphere",
        f"timestep {dt!r}",
        "compute c all pair/gran/local",
        "compute fn all reduce sum c_c[4] inputs local",
        "thermo_style custom step c_fn",
    ]
    if rec:
        lines.append(print_fix(every, rec, ["step", "x[1]", "x[2]", "vx[1]", "vx[2]", "fx[1]"]))
    lines.append(f"run {run}")
    return lines


def static_force(r1, r2, delta, cohesion):
    d = r1 + r2 - delta
    lmp = run_deck(deck(r1, r2, d, cohesion), f"cohesion_static_{cohesion}")
    f = np.array(lmp.numpy.extract_atom("f")[:2])
    ids = np.array(lmp.numpy.extract_atom("id")[:2])
    f1 = f[np.argsort(ids)][0]
    fn_local = lmp.last_thermo()["c_fn"]
    lmp.close()
    return -f1[0], fn_local  # Fn along n = (x1 − x2)/r = −x̂ on atom 1


def static(pairs=((0.005, 0.005), (0.005, 0.003)), rel_overlaps=(1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1)):
    rows = []
    for r1, r2 in pairs:
        Rs = r1 * r2 / (r1 + r2)
        Es = e_star(E, NU, E, NU)
        for q in rel_overlaps:
            delta = q * Rs
            d = r1 + r2 - delta
            fc, fc_local = static_force(r1, r2, delta, "sjkr")
            f0, f0_local = static_force(r1, r2, delta, "off")
            A = lens_area(r1, r2, d)
            rows.append(dict(r1=r1, r2=r2, delta=delta, F_coh=f0 - fc, F_coh_local=f0_local - fc_local,
                             F_coh_closed=K_COH * A, F_total=fc, F_total_closed=float(hertz_force(Es, Rs, delta)) - K_COH * A))
    return rows


def equilibrium_closed(r1, r2):
    Rs = r1 * r2 / (r1 + r2)
    Es = e_star(E, NU, E, NU)

    def g(delta):
        return float(hertz_force(Es, Rs, delta)) - K_COH * lens_area(r1, r2, r1 + r2 - delta)
    lo, hi = 1e-12 * Rs, 0.5 * Rs   # g < 0 just after touching (area ~ δ beats δ^{3/2}), > 0 deep
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def settle(r1, r2, duration=0.02, dt=2e-7):
    """The pair touching (δ = 1e-9 m) at rest, no gravity: settles at the equilibrium overlap."""
    rec = out_path(f"cohesion_settle_{r2}.txt")
    nsteps = int(round(duration / dt))
    lmp = run_deck(deck(r1, r2, r1 + r2 - 1e-9, "sjkr", run=nsteps, every=50, rec=rec, dt=dt), f"cohesion_settle_{r2}")
    lmp.close()
    d = read_record(rec)
    t = d[:, 0] * dt
    delta = r1 + r2 - (d[:, 2] - d[:, 1])
    return dict(t=t, delta=delta, delta_eq=delta[-1], delta_eq_closed=equilibrium_closed(r1, r2), r1=r1, r2=r2,
                vrel_end=abs(d[-1, 4] - d[-1, 3]))


def run_all():
    rows = static()
    eq = [settle(0.005, 0.005), settle(0.005, 0.003)]
    plt = pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for (r1, r2), mk in (((0.005, 0.005), "o"), ((0.005, 0.003), "s")):
        sel = [w for w in rows if w["r2"] == r2]
        dl = np.array([w["delta"] for w in sel])
        ax[0].loglog(dl, [w["F_coh"] for w in sel], mk, mfc="none", label=f"F_coh, R = {r1*1e3:g}/{r2*1e3:g} mm")
        dd = np.geomspace(dl.min(), dl.max(), 100)
        ax[0].loglog(dd, [K_COH * lens_area(r1, r2, r1 + r2 - x) for x in dd], "k-", lw=0.7)
    ax[0].set_xlabel("overlap δ (m)")
    ax[0].set_ylabel("cohesive force (N)")
    ax[0].set_title(f"sjkr: F_coh vs k·π a² (black), k = {K_COH:g} J/m³")
    ax[0].legend()
    for w in eq:
        ax[1].plot(w["t"] * 1e3, w["delta"] * 1e6, label=f"R = {w['r1']*1e3:g}/{w['r2']*1e3:g} mm")
        ax[1].axhline(w["delta_eq_closed"] * 1e6, color="k", lw=0.7, ls="--")
    ax[1].set_xlabel("t (ms)")
    ax[1].set_ylabel("overlap (µm)")
    ax[1].set_title("pulled into contact; dashed: Hertz = k π a²(δ)")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(out_path("cohesion_sjkr.png"), dpi=110)
    plt.close(fig)
    return rows, eq


if __name__ == "__main__":
    rows, eq = run_all()
    for w in rows:
        print(f"static R={w['r1']}/{w['r2']} δ={w['delta']:.3e}: F_coh {w['F_coh']:.8g} (local {w['F_coh_local']:.8g}) / "
              f"{w['F_coh_closed']:.8g} ({rel(w['F_coh'], w['F_coh_closed']):+.1e}); total {w['F_total']:.6g} / "
              f"{w['F_total_closed']:.6g} ({rel(w['F_total'], w['F_total_closed']):+.1e})")
    for w in eq:
        print(f"settle R={w['r1']}/{w['r2']}: δ_eq {w['delta_eq']:.6e} / {w['delta_eq_closed']:.6e} "
              f"({rel(w['delta_eq'], w['delta_eq_closed']):+.2e}), |v_rel| end {w['vrel_end']:.1e}")
