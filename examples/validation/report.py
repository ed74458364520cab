"""Runs every validation benchmark and prints the markdown table of doc/validation.md
(closed form, measured, relative error); also writes it to out/validation_table.md.

    .venv/bin/python examples/validation/report.py
"""
import math

import ai_rolling
import chung_ooi
import cohesion_sjkr
from val_common import out_path, rel


def main():
    rows = []

    def add(bench, quantity, closed, measured, unit="", fmt="{:.6g}"):
        err = rel(measured, closed)
        rows.append(f"| {bench} | {quantity} | {fmt.format(closed)}{unit} | {fmt.format(measured)}{unit} | {err:+.1e} |")

    for r in chung_ooi.test1():
        c, b = r["closed"], f"C&O 1, {r['material']}"
        add(b, "α_max", c["amax"] * 1e6, r["amax"] * 1e6, " µm")
        add(b, "P_max", c["pmax"] / 1e3, r["pmax"] / 1e3, " kN")
        add(b, "t_c", c["tc"] * 1e6, r["tc"] * 1e6, " µs")
        rows.append(f"| {b} | max rel. dev. of F(α) from Hertz (δ > 0.05 α_max) | 0 | {r['curve_err']:.1e} | {r['curve_err']:.1e} |")
    for r in chung_ooi.test2():
        c, k, b = r["rigid"], r["closed"], f"C&O 2, {r['material']}"
        add(b, "α_max (rigid plane)", c["amax"] * 1e6, r["amax"] * 1e6, " µm")
        add(b, "P_max (rigid plane)", c["pmax"] / 1e3, r["pmax"] / 1e3, " kN")
        add(b, "t_c (rigid plane)", c["tc"] * 1e6, r["tc"] * 1e6, " µs")
        add(b, "P_max (setup's E*, R*)", k["pmax"] / 1e3, r["pmax"] / 1e3, " kN")
        add(b, "(2/5) P_max α_max / (½ m V²)", 1.0, r["energy_ratio"])
    rows3, limit3 = chung_ooi.test3()
    for r in rows3:
        add(f"C&O 3, {r['model']}, {r['material']}", f"e_out (e_in = {r['e_in']})", r["e_in"], r["e_out"])
    for r in limit3:
        add("C&O 3, hertz, 3.x `limitForce on`", f"e_out (e_in = {r['e_in']}) vs the spec's computed value (not a closed form)",
            r["spec"], r["e_out"], fmt="{:.4g}")
    t4 = chung_ooi.test4()
    for r in t4:
        tag = "" if r["sliding"] else " (below sliding threshold: not asserted)"
        add(f"C&O 4, θ = {r['theta']}°", "e_t" + tag, r["e_t_closed"], r["e_t"], fmt="{:.5f}")
        add(f"C&O 4, θ = {r['theta']}°", "ω" + tag, r["omega_closed"], r["omega"], " rad/s", fmt="{:.2f}")
    worst = max(t4, key=lambda r: abs(r["e_n"] - chung_ooi.E4))
    add(f"C&O 4, all angles (worst: θ = {worst['theta']}°)", "normal COR e_n", chung_ooi.E4, worst["e_n"], fmt="{:.5f}")
    f = ai_rolling.flat()
    c = f["cdt"]
    add("Ai, flat, cdt, v0 = 1 m/s", "dv/dt = −(5/7) μr g", c["slope_closed"], c["slope"], " m/s²")
    add("Ai, flat, cdt, v0 = 1 m/s", "stop time 7v0/(5μr g) (fit extrapolated)", c["t_stop_closed"], c["t_stop_extrapolated"], " s")
    rows.append(f"| Ai, flat, cdt, v0 = 1 m/s | max abs(v − v_cf)/v0 over 0.02–1 s | 0 | {c['max_dev']:.1e} | {c['max_dev']:.1e} |")
    for model, s in f["short"].items():
        add(f"Ai, flat, {model}, v0 = 0.2 m/s", "dv/dt", c["slope_closed"], s["slope"], " m/s²")
        add(f"Ai, flat, {model}, v0 = 0.2 m/s", "stop time" + (" (not asserted)" if model == "epsd" else ""),
            f["t_stop_short_closed"], s["t_stop_extrapolated"], " s")
        rows.append(f"| Ai, flat, {model}, v0 = 0.2 m/s | after stop (t ≥ 0.4 s): max abs(v), max abs(ω), drift | rest | "
                    f"{s['tail_vmax']:.1e} m/s, {s['tail_wmax']:.1e} rad/s, {s['tail_drift']:.1e} m | – |")
    for w in ai_rolling.slope():
        b = f"Ai, slope, {w['model']}, tan θ/μr = {w['tan'] / ai_rolling.MU_R:.2f}"
        if w["rolls_closed"]:
            add(b, "a = (5/7) g (sin θ − μr cos θ)", w["a_closed"], w["a"], " m/s²")
        else:
            rows.append(f"| {b} | at rest: fitted a, displacement in 0.3 s, final abs(v) | 0 | {w['a']:.1e} m/s², "
                        f"{w['dist']:.1e} m, {w['vmax_end']:.1e} m/s | – |")
    st, eq = cohesion_sjkr.run_all()
    worst = max(st, key=lambda w: abs(rel(w["F_coh"], w["F_coh_closed"])))
    add("sjkr static (14 overlaps, 2 size pairs)", "worst F_coh vs k π a²", worst["F_coh_closed"], worst["F_coh"], " N", fmt="{:.10g}")
    worst = max(st, key=lambda w: abs(w["F_total"] - w["F_total_closed"]) / abs(w["F_total_closed"]))
    add("sjkr static", "worst total F vs Hertz − k π a²", worst["F_total_closed"], worst["F_total"], " N", fmt="{:.10g}")
    for w in eq:
        add(f"sjkr settle, R = {w['r1'] * 1e3:g}/{w['r2'] * 1e3:g} mm", "equilibrium overlap", w["delta_eq_closed"] * 1e6,
            w["delta_eq"] * 1e6, " µm", fmt="{:.7g}")
    text = "| benchmark | quantity | closed form | measured | rel. error |\n|---|---|---|---|---|\n" + "\n".join(rows) + "\n"
    with open(out_path("validation_table.md"), "w") as fh:
        fh.write(text)
    print(text)


if __name__ == "__main__":
    main()
