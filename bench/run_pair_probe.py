#!/usr/bin/env python3
"""Pair-loop CPU time of the plugin's AVX2 loop against its scalar loop, in one process (issue 12, P1/P2).

Opt-in bench tool, not run by CI. Each chute model runs a few steps with DEMBRIDGE_PAIR_PROBE=STEP,PASSES
(pair_styles/pair_gran_probe.cpp): at step STEP the pair style reruns that step's neighbour loop PASSES times with
each loop, alternating, from the same history and into scratch forces, and prints the thread CPU time of
every pass (minimum, median) and the AVX2 / scalar ratios. Both loops give bit-identical results; the
scalar loop is the reference that changes to the AVX2 loop are measured against, in the same process, so
the ratio holds up on a loaded machine far better than whole-run wall times do (pin it: --pin).

    .venv/bin/python bench/run_pair_probe.py [--models hooke,hertz,hookenh,hooke2xstiff,hertz2x,hertz2xrc]
                                             [--step 30] [--passes 200] [--pin 1] [--plugin build/dembridgeplugin.so]
"""
import argparse
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import run_chute_bench as chute  # noqa: E402  (deck paths and commands of the chute benchmark)

MODELS = {"hooke": "plg_hooke", "hertz": "plg_hertz", "hookenh": "plg_hookenh", "hooke2xstiff": "plg_hooke2xstiff",
          "hertz2x": "plg_hertz2x", "hertz2xrc": "plg_hertz2xrc"}
LINE = re.compile(r"DEMBRIDGE_PAIR_PROBE step (\d+) passes (\d+) avx2 min ([0-9.]+) median ([0-9.]+) us scalar min ([0-9.]+) "
                  r"median ([0-9.]+) us ratio of min ([0-9.]+) median of ratios ([0-9.]+)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--models", default=",".join(MODELS), help="comma-separated subset of " + ",".join(MODELS))
    ap.add_argument("--step", type=int, default=30, help="step whose loop is timed (default 30)")
    ap.add_argument("--passes", type=int, default=200, help="passes per loop (default 200)")
    ap.add_argument("--pin", default="1", help="taskset CPU list (default 1; empty: not pinned)")
    ap.add_argument("--plugin", default=os.path.join(chute.REPO, "build", "dembridgeplugin.so"))
    args = ap.parse_args()
    with open("/proc/loadavg") as fh:
        print("uptime load at start:", fh.read().split()[:3], flush=True)
    print(f"{'model':14s} {'AVX2 min us':>11s} {'scalar min us':>13s} {'AVX2/scalar min':>15s} {'median of ratios':>16s}")
    for model in args.models.split(","):
        key = MODELS[model]
        cmd = chute.deck_cmd(key, args.step + 1, "none", os.path.abspath(args.plugin))
        if args.pin:
            cmd = ["taskset", "-c", args.pin] + cmd
        env = chute.run_env(key)
        env["DEMBRIDGE_PAIR_PROBE"] = f"{args.step},{args.passes}"
        out = subprocess.run(cmd, cwd=HERE, env=env, capture_output=True, text=True)
        m = LINE.search(out.stdout)
        if out.returncode != 0 or not m:
            print(f"{model}: FAILED (rc={out.returncode})\n{out.stdout[-2000:]}{out.stderr[-2000:]}")
            continue
        print(f"{model:14s} {float(m.group(3)):11.1f} {float(m.group(5)):13.1f} {float(m.group(7)):15.4f} {float(m.group(8)):16.4f}",
              flush=True)
    with open("/proc/loadavg") as fh:
        print("uptime load at end:", fh.read().split()[:3])


if __name__ == "__main__":
    main()
