"""Cost of a force written in Python: the per-step call overhead (a no-op force) and a NumPy force
(constant acceleration on every particle), against the same step without it.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_force_overhead.py [--threads 1] [--steps 200]
"""
import argparse
import time

import numpy as np

import consph

import sys
import os
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import cpu_model  # noqa: E402


def scene(r):
    return {"simulation": {"particleRadius": r, "maxTimeStep": 0.002, "pressureSolver": {"type": "DFSPH"}},
            "fluids": [{"name": "water", "blocks": [{"min": [0.05, 0.05, 0.05], "max": [0.45, 0.45, 0.45]}]}],
            "boundaries": [{"box": {"min": [0, 0, 0], "max": [0.5, 1.0, 0.5]}, "inverted": True}],
            "output": {"enabled": False}}


def seconds_per_step(r, force, steps):
    sim = consph.Simulation.from_dict(scene(r))
    if force is not None:
        sim.fluid().add_force(force)
    sim.step(5)  # warm-up
    start = time.perf_counter()
    sim.step(steps)
    s = sim.summary()
    return (time.perf_counter() - start) / steps, s["phaseSeconds"]["nonPressureForces"] / s["steps"], len(sim.fluid())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--steps", type=int, default=200)
    args = ap.parse_args()
    consph.set_num_threads(args.threads)
    print(f"machine: {cpu_model()}; threads: {consph.get_num_threads()}; precision: {consph.precision}")
    print("| particles | force | ms/step | force phase ms/step |")
    print("|---:|---|---:|---:|")
    for r in (0.025, 0.0125):
        for name, force in (("none", None), ("no-op Python", lambda ctx, fluid: None),
                            ("NumPy a += const", lambda ctx, fluid: fluid.accelerations.__iadd__(np.array([1.0, 0, 0])))):
            per_step, force_phase, n = seconds_per_step(r, force, args.steps)
            print(f"| {n} | {name} | {1000 * per_step:.3f} | {1000 * force_phase:.4f} |")


if __name__ == "__main__":
    main()
