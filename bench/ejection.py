#!/usr/bin/python3
"""Fast particles in a dam break: how many, how fast, where and why (the stability issue, item 4).

The bound: sqrt(2 g H) is the speed of a particle that falls the column's height H; the issue asks
that particles stay below 1.5 sqrt(2 g H) except during the impact splash, and that the splash be
reported. Runs data/scenes/DamBreak.json (a 1 m column, so the bound is 6.64 m/s) through the
consph Python module at the scene's settings, changing only the particle radius and the boundary
model, and follows every particle by id through every step. Each step of a particle faster than
the bound is put into one class, by what its last step did to it:
  in flight  |a - g| < 2 g over the step: ballistic, gravity alone moves it (a droplet an impact threw
             up, rising or coming down: its speed is set by the height it fell from or the jet that
             threw it, not by a kick in this step);
  at a wall  pushed (|a - g| >= 2 g) within 2 h of a tank wall: a run-up or impact jet;
  interior   pushed away from every wall: a jet in the fluid or a single particle kicked out of it.
Per run and per 0.1 s window: particles above the bound (distinct ids), the fastest, and the
particle-steps of each class; and the particles that crossed the bound in a step where the
pressure changed their speed by more than 20 g dt while they had fewer than half a neighbourhood
(density < 0.6 rho0): single particles kicked out, the artefact the issue names.
Usage: /usr/bin/python3 bench/ejection.py [--threads 2] [--radii 0.025,0.0125] [--models Akinci2012,VolumeMap]
       [--stop-at 4.0,1.0] [--build build]
Prints markdown tables (machine, threads, precision named) and writes bench/results/ejection.md.
"""
import argparse
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402

SCENE = os.path.join(ROOT, "data", "scenes", "DamBreak.json")
G = 9.81
WINDOW = 0.1  # s


def run(consph, np, model, r, stop_at):
    sim = consph.Simulation.from_file(SCENE, output=False, log=lambda level, message: None,
                                      overrides={"simulation.particleRadius": r, "simulation.boundaryModel.type": model,
                                                 "simulation.stopAt": stop_at})
    scene = sim.scene
    block = scene["fluids"][0]["blocks"][0]
    height = block["max"][1] - block["min"][1]
    bound = 1.5 * math.sqrt(2 * G * height)
    tank = next(b for b in scene["boundaries"] if b.get("inverted"))
    lo, hi = np.array(tank["box"]["min"], float), np.array(tank["box"]["max"], float)
    gravity = np.array(scene["simulation"].get("gravity", [0, -G, 0]), float)
    rho0 = scene["fluids"][0].get("density0", 1000.0)
    h = 4 * r  # the cubic spline's support (2 r spacing lattice, h = 4 r)
    fluid = sim.fluid()
    ids_prev = fluid.ids.copy()
    v_prev = fluid.velocities.copy()
    windows = {}
    kicked = []
    fastest = (0.0, 0.0, None)
    started = time.time()
    while sim.time < stop_at - 1e-9:
        sim.step()
        dt, t = sim.dt, sim.time
        ids, v = fluid.ids, fluid.velocities
        if len(ids) != len(ids_prev):
            ids_prev, v_prev = ids.copy(), v.copy()
            continue
        if not np.array_equal(ids, ids_prev):  # the particles were re-sorted (Z order)
            where = np.empty(int(ids_prev.max()) + 1, dtype=np.int64)
            where[ids_prev] = np.arange(len(ids_prev))
            v_prev = v_prev[where[ids]]
        speed = np.linalg.norm(v, axis=1)
        fast = np.nonzero(speed > bound)[0]
        if len(fast):
            x = fluid.positions[fast]
            push = np.linalg.norm(v[fast] - v_prev[fast] - gravity * dt, axis=1) / dt
            wall = np.minimum((x - lo).min(axis=1), (hi - x).min(axis=1))
            w = windows.setdefault(int(t / WINDOW), {"ids": set(), "peak": 0.0, "flight": 0, "wall": 0, "interior": 0})
            w["ids"].update(int(i) for i in ids[fast])
            w["peak"] = max(w["peak"], float(speed[fast].max()))
            flight = push < 2 * G
            w["flight"] += int(flight.sum())
            w["wall"] += int((~flight & (wall < 2 * h)).sum())
            w["interior"] += int((~flight & (wall >= 2 * h)).sum())
            before = np.linalg.norm(v_prev[fast], axis=1)
            rho = fluid.densities[fast]
            for k in np.nonzero((before <= bound) & (push > 20 * G) & (rho < 0.6 * rho0))[0]:
                kicked.append((t, int(ids[fast[k]]), float(before[k]), float(speed[fast[k]]), float(rho[k] / rho0),
                               float(wall[k])))
            k = int(np.argmax(speed[fast]))
            if speed[fast[k]] > fastest[0]:
                fastest = (float(speed[fast[k]]), t, tuple(round(float(c), 3) for c in x[k]))
        ids_prev, v_prev = ids.copy(), v.copy()
    return {"bound": bound, "particles": len(ids_prev), "steps": sim.step_count, "windows": windows, "kicked": kicked,
            "fastest": fastest, "wall_s": time.time() - started}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--radii", default="0.025,0.0125")
    ap.add_argument("--stop-at", default="4.0,1.0", help="simulated seconds per radius")
    ap.add_argument("--models", default="Akinci2012,VolumeMap")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = ap.parse_args()
    sys.path.insert(0, os.path.join(os.path.abspath(args.build), "python"))
    import numpy as np
    import consph
    consph.set_num_threads(args.threads)
    radii = [float(s) for s in args.radii.split(",")]
    stops = [float(s) for s in args.stop_at.split(",")]
    lines = [f"machine: {machine_line()}, threads: {args.threads}, precision: {consph.precision}; "
             f"data/scenes/DamBreak.json at its own settings but r and the boundary model", ""]
    lines.append("| walls | r, m | simulated s | particles | steps | bound m/s | particles ever above it | fastest m/s (t s, at) | "
                 "particle-steps above: in flight / at a wall / interior | single particles kicked above it | wall s |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
    details = []
    for model in args.models.split(","):
        for r, stop in zip(radii, stops):
            res = run(consph, np, model, r, stop)
            ever = set().union(*(w["ids"] for w in res["windows"].values())) if res["windows"] else set()
            sums = [sum(w[c] for w in res["windows"].values()) for c in ("flight", "wall", "interior")]
            speed, t, at = res["fastest"]
            lines.append(f"| {model} | {r} | {stop} | {res['particles']} | {res['steps']} | {res['bound']:.2f} | {len(ever)} "
                         f"({100 * len(ever) / res['particles']:.2f} %) | {speed:.2f} ({t:.3f}, {at}) | "
                         f"{sums[0]} / {sums[1]} / {sums[2]} | {len(res['kicked'])} | {res['wall_s']:.0f} |")
            details.append(f"{model}, r = {r}: per {WINDOW} s window with any particle above {res['bound']:.2f} m/s")
            details.append("")
            details.append("| window, s | particles above | fastest m/s | in flight | at a wall | interior |")
            details.append("|---|---|---|---|---|---|")
            for k in sorted(res["windows"]):
                w = res["windows"][k]
                details.append(f"| {k * WINDOW:.1f}-{(k + 1) * WINDOW:.1f} | {len(w['ids'])} | {w['peak']:.2f} | {w['flight']} | "
                               f"{w['wall']} | {w['interior']} |")
            if res["kicked"]:
                details.append("")
                details.append("Single particles kicked above the bound (t s, id, m/s before -> after, rho / rho0, distance to "
                               "the nearest wall m): " + "; ".join(f"{t:.3f} #{i} {a:.2f} -> {b:.2f}, {rho:.2f}, {d:.3f}"
                                                                   for t, i, a, b, rho, d in res["kicked"][:20]))
            details.append("")
            print(lines[-1], flush=True)
    text = "\n".join(lines + [""] + details)
    print(text)
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "ejection.md"), "w") as f:
        f.write(text + "\n")


if __name__ == "__main__":
    main()
