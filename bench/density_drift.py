#!/usr/bin/python3
"""Density drift and the time step: does a dam break converge as the step is lowered by hand?

The impact benchmark's dam break (bench/impact_pressure.py: a 0.2 x 0.4 m column, 0.1 m deep, in
a 0.8 m tank; DFSPH, Akinci walls, the default treatment) at one resolution, with maxTimeStep
lowered by hand, for each DFSPH `densityRelaxation` ("resolution", the default: a density excess
is removed over the step the resolution calls for; "step": within every step taken). Per run:
  energy     kinetic + m g y of every particle over its start at 10 ms and at 0.2 s (no viscosity:
             the walls are still, so nothing may add energy);
  front      the 99th percentile of x at 0.2 s (with StandardViscosity 0.001, as the impact bench);
  arrival    the first time the far wall's low probe (y = 0.03 m, radius 0.025 m) reads 0.1 rho0 g H.
Prints a markdown table (machine, threads, precision named).
Usage: /usr/bin/python3 bench/density_drift.py [--r 0.01] [--steps 0,0.0011,0.00055,0.00028,0.00014] [--threads 1]
"""
import argparse
import os
import subprocess
import sys
import json

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402


def scene(r, max_dt, relaxation, viscous):
    sim = {"particleRadius": r, "stopAt": 0.4, "pressureSolver": {"type": "DFSPH", "densityRelaxation": relaxation}}
    if max_dt:
        sim["maxTimeStep"] = max_dt
    return {"name": "DensityDrift", "simulation": sim,
            "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.001}] if viscous else [],
                        "blocks": [{"min": [0, 0, 0], "max": [0.2, 0.4, 0.1]}]}],
            "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [0.8, 0.8, 0.1]}, "inverted": True}],
            "probes": [{"name": "low", "kind": "pressure", "position": [0.8, 0.03, 0.05], "radius": 0.025}],
            "output": {"enabled": False}}


def measure(r, max_dt, relaxation, threads):
    import numpy as np
    import consph
    consph.set_num_threads(threads)
    out = {"precision": consph.precision}
    # Energy without viscosity.
    sim = consph.Simulation.from_dict(scene(r, max_dt, relaxation, False))
    fluid = sim.fluids[0]
    m = np.asarray(fluid["mass"]).copy()

    def energy():
        x, v = np.asarray(fluid["position"]), np.asarray(fluid["velocity"])
        return float(np.sum(m * (0.5 * np.sum(v * v, axis=1) + 9.81 * x[:, 1])))
    e0 = energy()
    for mark in (0.01, 0.2):
        while sim.time < mark - 1e-12:
            sim.step(1)
        out[f"energy_{mark}"] = energy() / e0
    # Front and arrival with the impact bench's viscosity.
    sim = consph.Simulation.from_dict(scene(r, max_dt, relaxation, True))
    fluid = sim.fluids[0]
    while sim.time < 0.2 - 1e-12:
        sim.step(1)
    out["front"] = float(np.percentile(np.asarray(fluid["position"])[:, 0], 99))
    while sim.time < 0.4 - 1e-12:
        sim.step(1)
        if sim.probes["low"] > 0.1 * 1000 * 9.81 * 0.4:
            out["arrival"] = sim.time
            break
    out["steps"] = sim.step_count
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--r", type=float, default=0.01)
    ap.add_argument("--steps", default="0,0.0011,0.00055,0.00028,0.00014", help="maxTimeStep values, s (0: the default cap)")
    ap.add_argument("--relaxations", default="step,resolution")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--build", default="build", help="build folder whose python/ module to run")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        max_dt, relaxation = args.child.split(",")
        print(json.dumps(measure(args.r, float(max_dt), relaxation, args.threads)))
        return
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, args.build, "python"), OMP_NUM_THREADS=str(args.threads))
    rows, precision = [], "?"
    for relaxation in args.relaxations.split(","):
        for max_dt in args.steps.split(","):
            res = subprocess.run([sys.executable, __file__, "--child", f"{max_dt},{relaxation}", "--r", str(args.r),
                                  "--threads", str(args.threads)], capture_output=True, text=True, env=env)
            if res.returncode != 0:
                rows.append(f"| {relaxation} | {max_dt} | {(res.stderr.strip().splitlines() or ['?'])[-1]} | | | | |")
                continue
            x = json.loads(res.stdout.strip().splitlines()[-1])
            precision = x["precision"]
            rows.append(f"| {relaxation} | {round(float(max_dt) * 1000, 4) or 'default'} | {x['energy_0.01']:.4f} | {x['energy_0.2']:.3f} | "
                        f"{x['front']:.3f} | {x.get('arrival', float('nan')):.4f} | {x['steps']} |")
            print(rows[-1], flush=True)
    print(f"\nMachine: {machine_line()}; {args.threads} thread(s); {precision}; DFSPH, Akinci walls, default treatment, r = {args.r}\n")
    print("| densityRelaxation | max dt, ms | energy at 10 ms | energy at 0.2 s | front at 0.2 s, m | arrival, s | steps to arrival |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
