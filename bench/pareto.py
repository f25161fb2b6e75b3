#!/usr/bin/python3
"""Run time against error: which configuration is cheapest for a given accuracy (issue 19).

Cases, each with an exact or published answer and reduced to one error number per run (%):
  tank        a block n x n x 2n drawn up to the walls of its tank (w = 0.371 m; n = 8 / 12 / 16,
              r = 0.025 / 0.0167 / 0.0125), rests 2 s: RMS of p - rho0 g d over every particle
              deeper than 3r (raw solver pressure; d below the level gauge's surface), % of
              rho0 g H, at t = 2 s  -> "tank_rms";
              |floor force / weight - 1| (force probe, mean over 1.5-2 s)  -> "tank_floor";
  martinmoyce the Martin & Moyce (1952) dam break, n^2 = 2 (data/validation/), a slab 4
              particles deep, column a = nx d (nx = 11 / 22 / 44, r = 0.01 / 0.005 / 0.0025):
              RMS of (Z_sim - Z_exp) / Z_exp over the measured points with T <= 3;
  buoyancy    a 0.5 rho0 box (0.2 x 0.1 x 0.2 m) floating in a 0.4 m tank filled 0.25 m deep,
              r = 0.02 / 0.0133 / 0.01, 3 s: |submerged fraction - 0.5| in points (the fraction
              under a level gauge's surface in a corner of the tank, mean over 2-3 s);
  jet         a 2 m/s round jet (radius a = 0.04 m) without gravity onto a plate, r = a/4, a/8,
              a/12 (as bench/wall_pressure.py): |plate force / (mdot U) - 1|, mean over 0.3-0.6 s;
  spheredrop  (full sweep) the paper's experiment, data/scenes/SphereDrop.json, DFSPH, Akinci
              walls, each treatment, at rest over the last second of 4 s, the particles within
              3.5 r of the sphere against p_h (hydrostatic, surface fitted on the bulk), split in
              two because they are different failures: the near-wall level k (least squares
              p ~ k p_h per snapshot) -> "spheredrop_bias" = |k - 1|; the noise around it, RMS of
              p - k p_h / mean p_h -> "spheredrop_noise" (the paper's "mirroring is noisier").

The sweep (each point: one child process, 2 threads by default, wall time of the stepping only;
machine and load average printed):
  DFSPH, IISPH   x Akinci2012, VolumeMap x consistent, mirroring, extrapolation x 3 radii, at
                 the default tolerance (maxError 0.01 %);
  tolerance      DFSPH, IISPH x Akinci2012 x auto x maxError 0.1 / 0.05 % x 3 radii (0.01 % is in
                 the row above);
  WCSPH          x Akinci2012, VolumeMap x auto x 3 radii (it has no tolerance: its stiffness
                 sets the compression);
  float          DFSPH x Akinci2012 x auto x 3 radii, when --float-build names a float build.
Pruned, and why: the tolerance and precision axes only around the default configuration (their
effect on the others is the same solve run longer or in float); WCSPH with the default treatment
only (it is the explicit baseline, not a candidate for tight errors); mirroring on VolumeMap stays
(it is not extrapolation there since the fit was widened).
--quick: DFSPH, IISPH x Akinci2012 x consistent, extrapolation x the two coarse radii, plus WCSPH
auto, no spheredrop and no feature costs (under 5 minutes on 2 cores).

Also measured on the same machine, in the full sweep: what an unused feature costs per step (the
tank at n = 12, DFSPH defaults, against the same scene with an emitter that starts after the end,
an animated body at rest out of the fluid's reach, a zero drag force, a probe), interleaved
repetitions.

Output: bench/results/pareto.csv (every point), bench/results/pareto_<case>.png (log-log error
against wall time, colour = solver, marker = boundary model, the Pareto front drawn),
bench/results/pareto.md (the fronts, the cheapest configuration per error level, the feature
costs), printed as well; --quick writes bench/results/pareto_quick.* instead, so that it never
overwrites the full sweep's files.
--cases tank,spheredrop re-measures only those cases (the full sweep's points for them) and keeps
every other case's points, and the feature costs, from the bench/results files already there
("features" in the list re-measures the feature costs); --replot measures nothing and writes the
plots and tables again from pareto.csv.
Usage: /usr/bin/python3 bench/pareto.py [--quick] [--threads 2] [--build build] [--float-build DIR]
                                        [--cases CASE,...] [--replot]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402
import wall_pressure  # noqa: E402

RHO0, G, SPACING = 1000.0, 9.81, 1.8566
TANK_W = 8 * SPACING * 0.025
CASES = ["tank", "martinmoyce", "buoyancy", "jet"]
METRICS = {"tank": ["tank_rms", "tank_floor"], "martinmoyce": ["martinmoyce"], "buoyancy": ["buoyancy"], "jet": ["jet"],
           "spheredrop": ["spheredrop_noise", "spheredrop_bias"]}
RADII = {"tank": [0.025, 0.025 * 8 / 12, 0.0125], "martinmoyce": [0.01, 0.005, 0.0025],
         "buoyancy": [0.02, 0.02 * 2 / 3, 0.01], "jet": [0.01, 0.005, 0.04 / 12]}
DEFAULT_TOLERANCE = 0.01


def simulation_block(cfg, r, stop_at, gravity=True):
    ps = {"type": cfg["solver"]}
    if cfg["solver"] != "WCSPH":
        ps["maxError"] = cfg["tolerance"]
    if cfg["solver"] == "IISPH":
        ps["maxIterations"] = 300  # 0.01 % under a deep column needs more than the default 100
    sim = {"particleRadius": r, "stopAt": stop_at, "boundaryPressure": cfg["treatment"],
           "boundaryModel": {"type": cfg["model"]}, "pressureSolver": ps}
    if not gravity:
        sim["gravity"] = [0, 0, 0]
    return sim


def tank_scene(cfg, r):
    n = int(round(TANK_W / (SPACING * r)))
    w, hb = TANK_W, 2 * TANK_W
    return {"simulation": simulation_block(cfg, r, 2.0),
            "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                        "blocks": [{"min": [0, 0, 0], "max": [w + 1e-9, hb + 1e-9, w + 1e-9]}]}],
            "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [w, 3 * hb, w]}, "inverted": True}],
            "probes": [{"name": "level", "kind": "level", "position": [w / 2, 0, w / 2]},
                       {"name": "tank", "kind": "force", "boundary": "tank"}],
            "output": {"enabled": False}}, n


def martin_moyce_scene(cfg, r):
    d, wall = SPACING * r, 2 * r
    nx = {0.01: 11, 0.005: 22, 0.0025: 44}[r]  # a = nx d = 0.204 m at every radius
    up = 5e-7
    return {"simulation": simulation_block(cfg, r, 1.0),
            "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 1e-6}],
                        "blocks": [{"min": [wall, wall, wall], "max": [wall + nx * d + up, wall + 2 * nx * d + up, wall + 4 * d + up]}]}],
            "boundaries": [{"box": {"min": [0, 0, 0], "max": [1.2, 0.6, 2 * wall + 4 * d]}, "inverted": True}],
            "output": {"enabled": False}}, nx


def buoyancy_scene(cfg, r):
    W, depth, side, height = 0.4, 0.25, 0.2, 0.1
    lo = (W - side) / 2
    bottom = depth - 0.5 * height
    return {"simulation": simulation_block(cfg, r, 3.0),
            "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                        "blocks": [{"min": [0, 0, 0], "max": [W, depth, W]}]}],
            "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [W, 0.6, W]}, "inverted": True},
                           {"name": "box", "box": {"min": [lo, bottom, lo], "max": [lo + side, bottom + height, lo + side]},
                            "dynamic": True, "density": 500}],
            "probes": [{"name": "level", "kind": "level", "position": [0.04, 0, 0.04]}],
            "output": {"enabled": False}}, None


def jet_scene(cfg, r):
    # bench/wall_pressure.py's jet (the test Jet's scene) at radius r and this point's solver block.
    scene = wall_pressure.jet_scene(cfg["solver"], cfg["model"], cfg["treatment"])
    scene["simulation"].update(simulation_block(cfg, r, 0.6, gravity=False))
    return scene, None


def read_martin_moyce():
    pts = []
    with open(os.path.join(ROOT, "data", "validation", "martin_moyce_1952_front_n2.csv")) as f:
        for line in f:
            if not line.strip() or line[0] in "#T":
                continue
            T, Z = (float(v) for v in line.split(","))
            pts.append((T, Z))
    return pts


def measure(case, cfg, r, threads):
    """One point, in this (child) process: error(s), wall seconds of the stepping, steps, iterations."""
    import numpy as np
    import consph
    consph.set_num_threads(threads)
    out = {"precision": consph.precision}
    if case == "tank":
        scene, n = tank_scene(cfg, r)
        sim = consph.Simulation.from_dict(scene)
        f = sim.fluid("water")
        weight = len(f.positions) * float(f.masses[0]) * G
        t0 = time.perf_counter()
        sim.run(until=1.5)
        rows, dts = [], []
        while sim.time < 2.0 - 1e-9:
            sim.step(1)
            rows.append(sim.probes)
            dts.append(sim.dt)
        wall = time.perf_counter() - t0
        H = wall_pressure.time_mean([x["level"] for x in rows], dts)
        depth = H - f.positions[:, 1]
        deep = depth > 3 * r
        p = f.solver_pressures  # the per-particle solver pressure (the sweep was recorded with it; the field "pressure" averages it)
        out["tank_rms"] = 100 * float(np.sqrt(np.mean((p[deep] - RHO0 * G * depth[deep]) ** 2)) / (RHO0 * G * H))
        out["tank_floor"] = 100 * abs(-wall_pressure.time_mean([x["tank.fy"] for x in rows], dts) / weight - 1)
    elif case == "martinmoyce":
        scene, nx = martin_moyce_scene(cfg, r)
        sim = consph.Simulation.from_dict(scene)
        f = sim.fluid("water")
        d, wall = SPACING * r, 2 * r
        a = nx * d
        scale = math.sqrt(2 * G / a)
        measured = [(T, Z) for T, Z in read_martin_moyce() if T <= 3.0]
        t_end = measured[-1][0] / scale
        times, fronts = [0.0], [1.0]
        t0 = time.perf_counter()
        while sim.time < t_end:
            sim.step(1)
            times.append(sim.time)
            fronts.append((float(f.positions[:, 0].max()) + 0.5 * d - wall) / a)
        wall_s = time.perf_counter() - t0
        zs = np.interp([T / scale for T, _ in measured], times, fronts)
        out["martinmoyce"] = 100 * float(np.sqrt(np.mean([((z - Z) / Z) ** 2 for z, (_, Z) in zip(zs, measured)])))
        wall = wall_s
    elif case == "buoyancy":
        scene, _ = buoyancy_scene(cfg, r)
        sim = consph.Simulation.from_dict(scene)
        t0 = time.perf_counter()
        sim.run(until=2.0)
        fractions, dts = [], []
        while sim.time < 3.0 - 1e-9:
            sim.step(1)
            y = sim.bodies[0]["position"][1]
            fractions.append((sim.probes["level"] - (y - 0.05)) / 0.1)
            dts.append(sim.dt)
        wall = time.perf_counter() - t0
        out["buoyancy"] = 100 * abs(wall_pressure.time_mean(fractions, dts) - 0.5)
    elif case == "jet":
        scene, _ = jet_scene(cfg, r)
        sim = consph.Simulation.from_dict(scene)
        f = sim.fluid("water")
        t0 = time.perf_counter()
        sim.run(until=0.3)
        e0, ts, fy, dts = sim.summary()["particlesEmitted"], sim.time, [], []
        while sim.time < 0.6 - 1e-9:
            sim.step(1)
            fy.append(sim.probes["plate.fy"])
            dts.append(sim.dt)
        wall = time.perf_counter() - t0
        mdot = (sim.summary()["particlesEmitted"] - e0) * float(f.masses[0]) / (sim.time - ts)
        out["jet"] = 100 * abs(-wall_pressure.time_mean(fy, dts) / (mdot * 2.0) - 1)
    elif case == "spheredrop":
        scene = json.load(open(os.path.join(ROOT, "data", "scenes", "SphereDrop.json")))
        scene["boundaries"][0]["mesh"] = os.path.join(ROOT, "data", "meshes", "sphere.obj")
        scene["simulation"].update(simulation_block(cfg, scene["simulation"]["particleRadius"], 4.0))
        scene["output"] = {"enabled": False}
        sim = consph.Simulation.from_dict(scene)
        f = sim.fluid("water")
        rr = scene["simulation"]["particleRadius"]
        t0 = time.perf_counter()
        sim.run(until=3.0)
        noise, bias = [], []
        while sim.time < 4.0 - 1e-9:
            sim.step(10)
            x, p = f.positions, f.solver_pressures
            top = x[:, 1].max()
            wall_dist = 0.5 - np.linalg.norm(x, axis=1)
            bulk = (wall_dist > 4 * rr) & (x[:, 1] < top - 4 * rr)
            ys = float(np.mean(x[bulk, 1] + p[bulk] / (RHO0 * G)))
            near = (wall_dist < 3.5 * rr) & (x[:, 1] < top - 4 * rr)
            ph = RHO0 * G * (ys - x[near, 1])
            k = float(np.dot(p[near], ph) / np.dot(ph, ph))
            bias.append(k - 1)
            noise.append(float(np.sqrt(np.mean((p[near] - k * ph) ** 2)) / np.mean(ph)))
        wall = time.perf_counter() - t0
        out["spheredrop_noise"] = 100 * float(np.mean(noise))
        out["spheredrop_bias"] = 100 * abs(float(np.mean(bias)))
    s = sim.summary()
    out.update({"wall": wall, "steps": s["steps"], "pressure_iterations": s["averagePressureIterations"],
                "cap_hits": s["iterationCapHits"], "treatment_resolved": s["boundaryPressure"]})
    return out


def sweep(quick, have_float):
    """(case, cfg, r) for every point."""
    points = []
    for case in CASES:
        radii = RADII[case][:2] if quick else RADII[case]
        base = {"tolerance": DEFAULT_TOLERANCE, "precision": "double"}
        for r in radii:
            for solver in ["DFSPH", "IISPH"]:
                models = ["Akinci2012"] if quick else ["Akinci2012", "VolumeMap"]
                treatments = ["consistent", "extrapolation"] if quick else ["consistent", "mirroring", "extrapolation"]
                for model in models:
                    for treatment in treatments:
                        points.append((case, dict(base, solver=solver, model=model, treatment=treatment), r))
                if not quick:
                    for tol in [0.1, 0.05]:
                        points.append((case, dict(base, solver=solver, model="Akinci2012", treatment="auto", tolerance=tol), r))
            for model in (["Akinci2012"] if quick else ["Akinci2012", "VolumeMap"]):
                points.append((case, dict(base, solver="WCSPH", model=model, treatment="auto"), r))
            if have_float and not quick:
                points.append((case, dict(base, solver="DFSPH", model="Akinci2012", treatment="auto", precision="float"), r))
    if not quick:
        for treatment in ["consistent", "mirroring", "extrapolation"]:
            points.append(("spheredrop", {"solver": "DFSPH", "model": "Akinci2012", "treatment": treatment,
                                          "tolerance": DEFAULT_TOLERANCE, "precision": "double"}, 0.01))
    return points


def label(cfg, r):
    tol = "" if cfg["solver"] == "WCSPH" else f" {cfg['tolerance']}%"
    return f"{cfg['solver']} {cfg['model']} {cfg['treatment']}{tol} r={r:.4g} {cfg['precision']}"


def front(points, metric):
    """The Pareto front: points no cheaper point beats in error, by increasing wall time."""
    best, out = math.inf, []
    for p in sorted((p for p in points if metric in p), key=lambda p: p["wall"]):
        if p[metric] < best:
            best = p[metric]
            out.append(p)
    return out


def plot(points, case, metric, stem):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    colours = {"DFSPH": "tab:blue", "IISPH": "tab:orange", "WCSPH": "tab:green"}
    markers = {"Akinci2012": "o", "VolumeMap": "s"}
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for p in points:
        if metric not in p:
            continue
        c = p["cfg"]
        ax.scatter(p["wall"], max(p[metric], 1e-3), c=colours[c["solver"]], marker=markers[c["model"]], s=22,
                   facecolors="none" if c["precision"] == "float" else colours[c["solver"]], edgecolors=colours[c["solver"]])
    fr = front(points, metric)
    ax.plot([p["wall"] for p in fr], [max(p[metric], 1e-3) for p in fr], "k-", lw=1, label="Pareto front")
    # The treatment (and radius) beside each front point, beside every point where there are few:
    # where consistent, mirroring and extrapolation sit is what the plot is read for.
    for p in (points if len(points) <= 6 else fr):
        if metric in p:
            c = p["cfg"]
            ax.annotate(f"{c['treatment']} r={p['r']:.3g}" + (" f" if c["precision"] == "float" else ""),
                        (p["wall"], max(p[metric], 1e-3)), textcoords="offset points", xytext=(4, 3), fontsize=6)

    for s, col in colours.items():
        ax.scatter([], [], c=col, marker="o", label=s)
    for m, mk in markers.items():
        ax.scatter([], [], c="gray", marker=mk, label=m)
    ax.set_xscale("log")
    ax.set_yscale("log")
    from matplotlib.ticker import ScalarFormatter
    for axis, values in ((ax.xaxis, [p["wall"] for p in points if metric in p]),
                         (ax.yaxis, [max(p[metric], 1e-3) for p in points if metric in p])):
        if values and max(values) < 10 * min(values):  # within a decade: plain tick labels
            axis.set_major_formatter(ScalarFormatter())
            axis.set_minor_formatter(ScalarFormatter())
    ax.set_xlabel("wall time of the run, s")
    ax.set_ylabel(f"{metric} error, %")
    ax.set_title(f"{case}: error against run time", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "results", f"{stem}_{metric}.png"), dpi=110)
    plt.close(fig)


def feature_costs(build, threads, reps=3):
    """ms per step (and steps) of the n = 12 tank with and without features that do nothing."""
    cfg = {"solver": "DFSPH", "model": "Akinci2012", "treatment": "auto", "tolerance": DEFAULT_TOLERANCE, "precision": "double"}
    base, _ = tank_scene(cfg, RADII["tank"][1])
    base["simulation"]["stopAt"] = 1.0
    # The same steps in every variant: without a given maxTimeStep the step follows the scene's
    # speed scale, which an emitter's speed or a body's height raise (a first sweep measured the
    # emitter and the animated body 23-30 % cheaper per step: smaller steps, fewer iterations).
    base["simulation"]["maxTimeStep"] = 0.003
    base.pop("probes")
    variants = {"none": base}
    v = json.loads(json.dumps(base))
    v["fluids"][0]["emitters"] = [{"shape": "circle", "position": [0.18, 1.5, 0.18], "direction": [0, -1, 0], "speed": 1.0,
                                   "radius": 0.03, "start": 100.0}]
    variants["emitter, never starts"] = v
    v = json.loads(json.dumps(base))
    v["boundaries"].append({"name": "idle", "box": {"min": [2, 2, 2], "max": [2.1, 2.1, 2.1]}, "animated": {"velocity": [0, 0, 0]}})
    v["simulation"]["domain"] = {"min": [-1, -1, -1], "max": [3, 3, 3]}
    variants["animated body out of reach"] = v
    v = json.loads(json.dumps(base))
    v["fluids"][0]["forces"].append({"type": "Macklin2014", "drag": 0.0})
    variants["drag force, coefficient 0"] = v
    v = json.loads(json.dumps(base))
    v["probes"] = [{"name": "level", "kind": "level", "position": [0.18, 0, 0.18]}]
    variants["one level probe"] = v
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, build, "python"), OMP_NUM_THREADS=str(threads))
    code = ("import sys, json, consph; consph.set_num_threads(%d); s = consph.Simulation.from_dict(json.loads(sys.stdin.read())); "
            "s.run(until=0.2); import time; t = time.perf_counter(); n0 = s.step_count; s.run(until=1.0); "
            "print((time.perf_counter() - t) * 1000 / (s.step_count - n0), s.step_count - n0)") % threads
    times, steps = {k: [] for k in variants}, {}
    for _ in range(reps):
        for name, scene in variants.items():
            res = subprocess.run([sys.executable, "-c", code], input=json.dumps(scene), capture_output=True, text=True, env=env)
            if res.returncode != 0:
                times[name].append(float("nan"))
                print(f"feature cost {name}: {res.stderr.strip().splitlines()[-1:]}", flush=True)
                continue
            ms, count = res.stdout.strip().splitlines()[-1].split()
            times[name].append(float(ms))
            steps[name] = int(count)
    return times, steps


CSV_HEADER = ["case", "solver", "model", "treatment", "tolerance_percent", "precision", "r", "metric", "error_percent",
              "wall_s", "steps", "pressure_iterations_per_step", "cap_hits", "load", "failure"]


def read_points(path):
    """The points of an earlier pareto.csv (one row per metric), as main() builds them."""
    points = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            cfg = {"solver": row["solver"], "model": row["model"], "treatment": row["treatment"],
                   "tolerance": float(row["tolerance_percent"]), "precision": row["precision"]}
            key = (row["case"], json.dumps(cfg, sort_keys=True), row["r"])
            p = points.setdefault(key, {"case": row["case"], "cfg": cfg, "r": float(row["r"]), "load": float(row["load"])})
            if row["error_percent"] != "nan":
                p.update({row["metric"]: float(row["error_percent"]), "wall": float(row["wall_s"]), "steps": int(row["steps"]),
                          "pressure_iterations": float(row["pressure_iterations_per_step"]), "cap_hits": int(row["cap_hits"])})
            elif row.get("failure"):
                p["error"] = row["failure"]
    for p in points.values():
        if "wall" not in p and "error" not in p:
            p["error"] = "failed (the earlier csv has no reason)"
    return list(points.values())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--build", default="build")
    ap.add_argument("--float-build", default="", help="a build folder configured with -DCONSPH_DOUBLE=OFF")
    ap.add_argument("--cases", default="", help="comma-separated cases to re-measure; the rest is kept from pareto.csv")
    ap.add_argument("--replot", action="store_true", help="measure nothing: the plots and tables again from pareto.csv")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    # The quick sweep writes files of its own: it does not overwrite the full sweep's.
    stem = "pareto_quick" if args.quick else "pareto"
    only = ["nothing"] if args.replot else [c for c in args.cases.split(",") if c]
    for c in only:
        if c not in METRICS and c not in ("features", "nothing"):
            ap.error(f"--cases: unknown case '{c}' (cases: {', '.join(METRICS)}, features)")
    kept, old_md = [], ""
    if only:
        old_csv, md_path = (os.path.join(HERE, "results", stem + ext) for ext in (".csv", ".md"))
        flag = "--replot" if args.replot else "--cases"
        for path in (old_csv, md_path):
            if not os.path.exists(path):
                ap.error(f"{flag} keeps the earlier points from {path}, which does not exist: run the sweep first")
        kept = [p for p in read_points(old_csv) if p["case"] not in only]
        with open(md_path) as f:
            old_md = f.read()  # its header and feature-cost section are carried over
    if args.child:
        spec = json.loads(args.child)
        print(json.dumps(measure(spec["case"], spec["cfg"], spec["r"], args.threads)))
        return
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    points = []
    started = time.time()
    header = (f"Machine: {machine_line()}; {args.threads} threads per run, one run at a time; load average at start "
              f"{os.getloadavg()[0]:.2f}")
    print(header, flush=True)
    for case, cfg, r in sweep(args.quick, bool(args.float_build)):
        if only and case not in only:
            continue
        build = args.float_build if cfg["precision"] == "float" else args.build
        env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, build, "python"), OMP_NUM_THREADS=str(args.threads))
        spec = json.dumps({"case": case, "cfg": cfg, "r": r})
        res = subprocess.run([sys.executable, __file__, "--child", spec, "--threads", str(args.threads)], capture_output=True,
                             text=True, env=env)
        point = {"case": case, "cfg": cfg, "r": r, "load": os.getloadavg()[0]}
        if res.returncode != 0:
            point["error"] = (res.stderr.strip().splitlines() or ["?"])[-1]
            print(f"{label(cfg, r)} {case}: FAILED {point['error']}", flush=True)
        else:
            point.update(json.loads(res.stdout.strip().splitlines()[-1]))
            errs = ", ".join(f"{m} {point[m]:.3g} %" for m in METRICS[case] if m in point)
            print(f"{case:11s} {label(cfg, r):60s} {errs}, {point['wall']:.1f} s, {point['steps']} steps", flush=True)
        points.append(point)
    minutes = (time.time() - started) / 60
    measured = len(points)
    points = kept + points
    with open(os.path.join(HERE, "results", stem + ".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(CSV_HEADER)
        for p in points:
            c = p["cfg"]
            for m in METRICS[p["case"]]:
                w.writerow([p["case"], c["solver"], c["model"], c["treatment"], c["tolerance"], c["precision"], p["r"], m,
                            p.get(m, "nan"), p.get("wall", "nan"), p.get("steps", ""), p.get("pressure_iterations", ""),
                            p.get("cap_hits", ""), f"{p['load']:.2f}", p.get("error", "")])
    sweep_line = f"; sweep {'quick' if args.quick else 'full'}, {measured} runs, {minutes:.1f} min."
    earlier = ""
    if only:
        sweep_line = (f"; re-measured now: {', '.join(only)} ({measured} runs, {minutes:.1f} min); the other "
                      f"{len(kept)} points kept from the earlier pareto.csv.")
        # The header of the sweep that measured the kept points (carried over re-measurements).
        md = old_md.splitlines()
        kept_from = [l for l in md if l.startswith("Points kept from: ")]
        earlier = kept_from[0] if kept_from else "Points kept from: " + (md[0] if md else "?")
    lines = [header + sweep_line, ""]
    if earlier:
        lines += [earlier, ""]
    if args.replot:  # the earlier header stands: nothing was measured
        lines = []
        for l in md:
            if l.startswith("Runs that failed") or l.startswith("### "):
                break
            lines.append(l)
    failed = [p for p in points if "error" in p]
    if failed:
        lines += ["Runs that failed (no point on the plot):", ""]
        lines += [f"- {p['case']} {label(p['cfg'], p['r'])}: {p['error']}" for p in failed]
        lines.append("")
    for case in CASES + ["spheredrop"]:
        for metric in METRICS[case]:
            pts = [p for p in points if p["case"] == case and metric in p]
            if not pts:
                continue
            plot(pts, case, metric, stem)
            lines += [f"### {metric}", "", "Pareto front (each point cheaper than every more accurate one):", "",
                      "| wall s | error % | configuration | steps | iterations / step |", "|---|---|---|---|---|"]
            for p in front(pts, metric):
                lines.append(f"| {p['wall']:.1f} | {p[metric]:.3g} | {label(p['cfg'], p['r'])} | {p['steps']} | "
                             f"{p['pressure_iterations']:.1f} |")
            lines += ["", "Cheapest configuration per error level:", "", "| error at most | configuration | wall s |", "|---|---|---|"]
            for level in [0.5, 1, 2, 5, 10, 20]:
                ok = [p for p in pts if p[metric] <= level]
                if ok:
                    p = min(ok, key=lambda p: p["wall"])
                    lines.append(f"| {level} % | {label(p['cfg'], p['r'])} ({p[metric]:.3g} %) | {p['wall']:.1f} |")
                else:
                    lines.append(f"| {level} % | none of the sweep | |")
            lines.append("")
    mark = "### What an unused feature costs"
    if only and "features" not in only:
        if mark in old_md:
            section = old_md[old_md.index(mark):].rstrip("\n")
            note = "(measured by an earlier run of this script)"
            if note not in section and not args.replot:
                section = section.replace(mark, mark + "\n\n" + note, 1)
            lines += [section, ""]
    elif not args.quick:
        costs, steps = feature_costs(args.build, args.threads)
        base = [t for t in costs["none"] if t == t]
        lines += [mark, "",
                  f"The n = 12 tank, DFSPH defaults with maxTimeStep 0.003 s (the same steps in every variant), ms per "
                  f"step over 0.2-1 s, {len(base)} interleaved repetitions:", "",
                  "| scene | steps | ms per step (each repetition) | mean / without |", "|---|---|---|---|"]
        mean0 = sum(base) / max(1, len(base))
        for name, ts in costs.items():
            good = [t for t in ts if t == t]
            mean = sum(good) / max(1, len(good))
            lines.append(f"| {name} | {steps.get(name, '')} | {', '.join(f'{t:.2f}' for t in ts)} | {mean / mean0:.3f} |")
        lines.append("")
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(HERE, "results", stem + ".md"), "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
