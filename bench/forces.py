#!/usr/bin/python3
"""Cost of the non-pressure forces on the dam break (data/scenes/DamBreak.json).

Runs the scene with no forces, with each registered force alone (default parameters) and with
all of them together; optionally the same no-force and standard-viscosity runs with a baseline
binary (e.g. main before the force plugins). Prints a table with the machine, thread count and
precision: median ms/step, median force ms/step (the simulation's own non-pressure-force phase
timer), steps, pressure iterations per step and peak resident memory (/usr/bin/time -v).

usage: /usr/bin/python3 bench/forces.py [--consph build/consph] [--baseline PATH] [--stop-at 1.0]
                                        [--threads 2] [--reps 3]
The runs set OMP_WAIT_POLICY=passive (for both binaries): on a shared, oversubscribed machine
OpenMP's default spin-waiting made a 2-thread run up to 30x slower and the figures meaningless.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile

import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import cpu_model  # noqa: E402

FORCES = ["XSPH", "StandardViscosity", "Weiler2018", "Micropolar", "VorticityConfinement", "Gissler2017",
          "Macklin2014", "Akinci2013"]


def run(binary, forces, args):
    with tempfile.NamedTemporaryFile(suffix=".json") as summary:
        cmd = ["/usr/bin/time", "-v", binary, args.scene, "--stop-at", str(args.stop_at), "--threads", str(args.threads),
               "--no-output", "--quiet", "--summary-json", summary.name]
        if forces is not None:
            cmd += ["--set", "fluids.0.forces=" + json.dumps([{"type": f} for f in forces])]
        env = dict(os.environ, OMP_WAIT_POLICY="passive")
        p = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if p.returncode != 0:
            raise SystemExit(f"{' '.join(cmd)} failed:\n{p.stderr}")
        s = json.load(open(summary.name))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1))
    steps = s["steps"]
    return {"msPerStep": s["msPerStep"], "forceMsPerStep": 1000 * s["phaseSeconds"]["nonPressureForces"] / steps,
            "steps": steps, "iterations": s["averagePressureIterations"], "rssMB": rss / 1024,
            "precision": s["precision"], "threads": s["threads"], "particles": s["fluidParticles"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--consph", default="build/consph")
    ap.add_argument("--baseline", default=None, help="binary to compare the no-force and default scene with")
    ap.add_argument("--scene", default="data/scenes/DamBreak.json")
    ap.add_argument("--stop-at", type=float, default=1.0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()

    configs = [("no forces", args.consph, [])] + [(f, args.consph, [f]) for f in FORCES] + [("all together", args.consph, FORCES)]
    if args.baseline:
        configs += [("baseline: no forces", args.baseline, []), ("baseline: StandardViscosity", args.baseline, ["StandardViscosity"])]
    results = {name: [] for name, _, _ in configs}
    for rep in range(args.reps):  # interleaved, so slow phases of the machine hit every row alike
        for name, binary, forces in configs:
            results[name].append(run(binary, forces, args))
    first = results["no forces"][0]
    load = open("/proc/loadavg").read().split()[:3]
    print(f"machine: {cpu_model()}, {os.cpu_count()} cores; load average {' '.join(load)} at the end")
    print(f"threads: {first['threads']}, precision: {first['precision']}, scene: {args.scene} to {args.stop_at} s, "
          f"{first['particles']} fluid particles, median of {args.reps} runs, OMP_WAIT_POLICY=passive")
    print()
    print("| forces | ms / step | force ms / step | steps | pressure iters / step | peak RSS MB |")
    print("|---|---|---|---|---|---|")
    for name, _, _ in configs:
        r = results[name]
        med = lambda k: statistics.median(x[k] for x in r)
        spread = max(x["msPerStep"] for x in r) - min(x["msPerStep"] for x in r)
        print(f"| {name} | {med('msPerStep'):.2f} (±{spread / 2:.2f}) | {med('forceMsPerStep'):.3f} | {med('steps'):.0f} | "
              f"{med('iterations'):.2f} | {med('rssMB'):.1f} |")


if __name__ == "__main__":
    main()
