#!/usr/bin/python3
"""Wall pressure and wall loads per solver x boundary model x treatment (the wall-pressure issue).

Two cases, each run through the consph Python module (PYTHONPATH=build/python), one process per
combination:
  tank     an N x N x 2N block of water drawn up to the walls of its tank (r = 0.025 m; N = 10 by
           default), rests for 3 s; every figure is a mean over the frames of the last 0.5 s:
             particle RMS  of p - rho0 g d over every particle deeper than 3r (wall layers
                           included), d below the level gauge's surface, in % of rho0 g H; "raw" is
                           the solver's pressure (fluid.solver_pressures), "field" the exported
                           pressure field (fluid.pressures), its kernel average over each
                           particle's neighbourhood (sum_j V_j p_j W_ij / sum_j V_j W_ij);
             slope         of p against d over the same particles, in rho0 g (raw, and of the
                           field; in brackets the field's slope's spread from frame to frame, its
                           standard deviation);
             time-averaged the same RMS and slope of the field averaged over those frames (each
                           particle's mean pressure at its mean height);
             wall layers   mean p / rho0 g d of the particles within one spacing of the floor and of
                           a side wall (raw, and of the exported field);
             floor probe   pressure probe at the floor's centre / (weight / area);
             side probe    pressure probe on a side wall at mid-depth / rho0 g (H - y);
             floor force   force probe on the tank (vertical) / weight;
             side force    force probe on one wall / (g w sum_j m_j y_j / A), the hydrostatic force
                           of the fluid as it lies (= rho0 g H^2 w / 2 at density rho0); the wall's
                           samples above the floor's edge row (particle walls), the whole wall
                           (volume maps, whose wall faces reach down to the floor's);
             M / (A H)     the fluid's mass per volume as it lies, / rho0: a fluid at rest has
                           dp/dd = g M / (A H) (H moves by a percent or two as the packing settles);
  held box a static 0.2 m cube held at the centre of a 0.36 m tank filled to 0.36 m (r = 0.01 m):
             fluid force on it / rho0 V g, means over 1.0-1.5 s;
  jet      a 2 m/s round jet (radius 0.04 m, r = 0.005 m, nu = 1e-3 m^2/s) without gravity onto a
           plate: plate force / (mdot U), means over 0.3-0.6 s.
Prints a markdown table (machine, threads, precision in its header), writes it to
bench/results/wall_pressure.md and p(depth) PNGs (raw and Shepard) to
bench/results/wall_pressure_<solver>_<model>_<treatment>.png.
Usage: /usr/bin/python3 bench/wall_pressure.py [--threads 1] [--jobs 2] [--quick]
"""
import argparse
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402

SOLVERS = ["DFSPH", "IISPH", "WCSPH"]
MODELS = ["Akinci2012", "VolumeMap"]
TREATMENTS = ["consistent", "mirroring", "extrapolation"]
R, RHO0, G = 0.025, 1000.0, 9.81
SPACING = 1.8566 * R


def tank_scene(solver, model, treatment, n):
    w, hb = n * SPACING, 2 * n * SPACING
    ps = {"type": solver}
    if solver == "IISPH":
        ps["maxIterations"] = 300  # 0.01 % under 1 m of water needs more than the default 100
    return {
        "name": "RestingTank",
        "simulation": {"particleRadius": R, "stopAt": 3.0, "boundaryPressure": treatment, "boundaryModel": {"type": model},
                       "pressureSolver": ps},
        "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                    "blocks": [{"min": [0, 0, 0], "max": [w + 1e-9, hb + 1e-9, w + 1e-9]}]}],
        "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [w, 3 * hb, w]}, "inverted": True}],
        "probes": [{"name": "floor", "kind": "pressure", "position": [w / 2, 0, w / 2]},
                   {"name": "side", "kind": "pressure", "position": [0, hb / 2, w / 2]},
                   {"name": "level", "kind": "level", "position": [w / 2, 0, w / 2]},
                   {"name": "tank", "kind": "force", "boundary": "tank"},
                   # The wall x = 0. Particle walls: its samples above the floor's edge row; volume maps:
                   # from the bottom, since the tank's walls are slabs whose inner faces the surface
                   # offset moves 1.36 r into the solid, down to the floor's face at y = -1.36 r, where
                   # the lowest layers' push lands (docs/boundary-models.md, "Corners").
                   {"name": "wall", "kind": "force", "boundary": "tank",
                    "region": {"min": [-1, 0.3 * R if model == "Akinci2012" else -1, -1], "max": [0.3 * R, 10, 10]}}],
        "output": {"enabled": False},
    }


def box_scene(solver, model, treatment):
    # The test HeldBox.FeelsTheWeightOfItsVolumeOfWater: a 0.2 m cube at the centre of a 0.36 m
    # tank filled to 0.36 m, r = 0.01 (10.8 spacings across). (Before 2026-12-01: r = 0.02 in a
    # 0.6 m tank, 5.4 spacings across: Akinci walls 0.870 consistent / 0.967 extrapolation.)
    w, lo = 0.36, 0.08
    ps = {"type": solver}
    if solver == "IISPH":
        ps["maxIterations"] = 300
    return {
        "name": "HeldBox",
        "simulation": {"particleRadius": 0.01, "stopAt": 1.5, "boundaryPressure": treatment,
                       "boundaryModel": {"type": model}, "pressureSolver": ps},
        "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                    "blocks": [{"min": [0, 0, 0], "max": [w, w, w]}]}],
        "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [w, w + 0.2, w]}, "inverted": True},
                       {"name": "box", "box": {"min": [lo, lo, lo], "max": [lo + 0.2, lo + 0.2, lo + 0.2]}}],
        "probes": [{"name": "box", "kind": "force", "boundary": "box"}],
        "output": {"enabled": False},
    }


def jet_scene(solver, model, treatment):
    # A 2 m/s round jet (radius a = 0.04 m, 8 particles across: r = a / 8) without gravity onto a
    # plate 5a away, nu = 1e-3 m^2/s (Re = U a / nu = 80); particles 6a off the axis are removed.
    # The same jet as the test Jet.PlateForceIsTheMomentumFlux. (Before 2026-12-01 this case ran
    # r = a / 4 and nu = 0.01, Re = 8: the fluid piled up on the plate and splashed back, 1.14-1.30.)
    a = 0.04
    rm = 6 * a
    return {
        "name": "Jet",
        "simulation": {"particleRadius": a / 8, "gravity": [0, 0, 0], "stopAt": 0.6, "boundaryPressure": treatment,
                       "boundaryModel": {"type": model}, "pressureSolver": {"type": solver},
                       "domain": {"min": [-1, -1, -1], "max": [1, 1, 1]}},
        "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.001}],
                    "emitters": [{"shape": "circle", "position": [0, 5 * a, 0], "direction": [0, -1, 0], "speed": 2.0,
                                  "radius": a}],
                    "removeOutside": {"min": [-rm, -0.1, -rm], "max": [rm, 5 * a + 0.3, rm]}}],
        "boundaries": [{"name": "plate", "box": {"min": [-rm - 0.1, -0.05, -rm - 0.1], "max": [rm + 0.1, 0, rm + 0.1]}}],
        "probes": [{"name": "plate", "kind": "force", "boundary": "plate"}],
        "output": {"enabled": False},
    }


def time_mean(values, dts):
    """The time average of per-step values (each weighted by its step): a mean over steps would
    weight a short step as much as a long one, and the adaptive step shortens where loads peak
    (volume maps' approach limit: the jet's plate force read 30 % high at r = 0.01 as a step mean)."""
    return float(sum(v * dt for v, dt in zip(values, dts)) / sum(dts))


def measure(case, solver, model, treatment, n, threads):
    """Runs one combination in this process (the child of main) and returns its figures."""
    import numpy as np
    import consph
    consph.set_num_threads(threads)
    out = {}
    if case == "tank":
        sim = consph.Simulation.from_dict(tank_scene(solver, model, treatment, n))
        f = sim.fluid("water")
        w = n * SPACING
        weight = len(f.positions) * f.masses[0] * G
        t0 = time.time()
        sim.run(until=2.5)
        rows, moment, frames, dts = [], [], [], []
        while sim.time < 3.0 - 1e-9:
            sim.step(1)
            rows.append(sim.probes)
            dts.append(sim.dt)
            moment.append(float(np.sum(f.masses * f.positions[:, 1])))
            frames.append((f.positions[:, 1].copy(), f.solver_pressures.copy(), f.pressures.copy()))
        wall = time.time() - t0
        avg = {k: time_mean([r[k] for r in rows], dts) for k in rows[0]}
        H = avg["level"]
        x = f.positions.copy()

        def figures(y, p, shepard):
            # One frame's figures; raw: the solver's per-particle pressure; field: the exported
            # pressure field (its kernel average, Simulation::updatePressureField), what a frame
            # and fluid.pressures hold.
            depth = H - y
            deep = depth > 3 * R
            ref = RHO0 * G * depth[deep]
            norm = RHO0 * G * H
            floor = deep & (y < SPACING)
            side = deep & (y > SPACING) & (np.minimum(np.minimum(x[:, 0], w - x[:, 0]), np.minimum(x[:, 2], w - x[:, 2])) < SPACING)
            fig = {}
            for tag, q in (("raw", p), ("field", shepard)):
                fig["rms_" + tag] = 100 * float(np.sqrt(np.mean((q[deep] - ref) ** 2)) / norm)
                fig["slope_" + tag] = float(np.polyfit(depth[deep], q[deep], 1)[0] / (RHO0 * G))
                fig["floor_layer_" + tag] = float(np.mean(q[floor]) / np.mean(RHO0 * G * depth[floor]))
                fig["side_layer_" + tag] = float(np.mean(q[side]) / np.mean(RHO0 * G * depth[side]))
            return fig

        # Every figure of the field is the mean over the last 0.5 s of one frame's figure (a single
        # frame's slope scatters by ~1 % from step to step as the packing breathes: the spread is
        # reported), and the same of the time-averaged field (each particle's mean pressure at its
        # mean height; the particles move by a fraction of r over 0.5 s at rest).
        per = [figures(*fr) for fr in frames]
        for k in per[0]:
            out[k] = float(np.mean([q[k] for q in per]))
        out["slope_field_spread"] = float(np.std([q["slope_field"] for q in per]))
        out["snapshot_slope_field"] = per[-1]["slope_field"]
        mean_y = np.mean([fr[0] for fr in frames], axis=0)
        tavg = figures(mean_y, np.mean([fr[1] for fr in frames], axis=0), np.mean([fr[2] for fr in frames], axis=0))
        out["tavg_rms_field"], out["tavg_slope_field"] = tavg["rms_field"], tavg["slope_field"]
        p, shepard = f.solver_pressures.copy(), f.pressures.copy()
        depth = H - x[:, 1]
        deep = depth > 3 * R
        out["floor_probe"] = avg["floor"] / (weight / (w * w))
        out["side_probe"] = avg["side"] / (RHO0 * G * (H - n * SPACING))
        out["floor_force"] = -avg["tank.fy"] / weight
        out["side_force"] = -avg["wall.fx"] / (G * w * time_mean(moment, dts) / (w * w))
        out["level"] = H
        # The fluid's mass per volume as it lies, M / (A H), against rho0: p(d) of a fluid at rest
        # rises at g times this (a disordered packing at SPH density rho0 fills a little more or
        # less volume than the start lattice's d^3 per particle).
        out["fill"] = weight / G / (w * w * H) / RHO0
        out["ms_per_step"] = sim.summary()["msPerStep"]
        out["steps"] = sim.step_count
        out["profile"] = {"depth": depth[deep].tolist(), "raw": p[deep].tolist(), "shepard": shepard[deep].tolist(),
                          "H": H}
        out["wall_seconds_last_half"] = wall
    elif case == "jet":
        # Plate force against the momentum flux mdot U, mdot counted from the emitted particles,
        # means over 0.3-0.6 s (the jet reaches the plate at 0.1 s).
        sim = consph.Simulation.from_dict(jet_scene(solver, model, treatment))
        f = sim.fluid("water")
        sim.run(until=0.3)
        emitted0, t0, fy, dts = sim.summary()["particlesEmitted"], sim.time, [], []
        while sim.time < 0.6 - 1e-9:
            sim.step(1)
            fy.append(sim.probes["plate.fy"])
            dts.append(sim.dt)
        mdot = (sim.summary()["particlesEmitted"] - emitted0) * float(f.masses[0]) / (sim.time - t0)
        out["jet"] = -time_mean(fy, dts) / (mdot * 2.0)
    else:
        sim = consph.Simulation.from_dict(box_scene(solver, model, treatment))
        sim.run(until=1.0)
        fy, dts = [], []
        while sim.time < 1.5 - 1e-9:
            sim.step(1)
            fy.append(sim.probes["box.fy"])
            dts.append(sim.dt)
        out["buoyancy"] = time_mean(fy, dts) / (RHO0 * 0.2 ** 3 * G)
    out["resolved_treatment"] = sim.summary()["boundaryPressure"]
    out["precision"] = consph.precision
    return out


def plot(results, path_prefix):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    for key, res in results.items():
        prof = res.get("profile")
        if not prof:
            continue
        fig, ax = plt.subplots(figsize=(4, 4))
        ax.plot(prof["raw"], prof["depth"], ".", ms=2, label="particle p (raw)")
        ax.plot(prof["shepard"], prof["depth"], ".", ms=2, label="pressure field (kernel average)")
        dmax = max(prof["depth"])
        ax.plot([0, RHO0 * G * dmax], [0, dmax], "k-", lw=1, label="rho0 g d")
        ax.invert_yaxis()
        ax.set_xlabel("pressure, Pa")
        ax.set_ylabel("depth below the level gauge's surface, m")
        ax.set_title(key.replace("_", " "), fontsize=9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(f"{path_prefix}_{key}.png", dpi=110)
        plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--n", type=int, default=10, help="tank columns per side (layers: 2n)")
    ap.add_argument("--quick", action="store_true", help="DFSPH only")
    ap.add_argument("--models", default=",".join(MODELS), help="comma-separated boundary models")
    ap.add_argument("--treatments", default=",".join(TREATMENTS + ["auto"]), help="comma-separated treatments")
    ap.add_argument("--cases", default="tank,box,jet", help="comma-separated cases")
    ap.add_argument("--build", default="build", help="build folder whose python/ module to run")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        case, solver, model, treatment = args.child.split(",")
        print(json.dumps(measure(case, solver, model, treatment, args.n, args.threads)))
        return
    solvers = ["DFSPH"] if args.quick else SOLVERS
    combos = [(c, s, m, t) for s in solvers for m in args.models.split(",") for t in args.treatments.split(",")
              for c in args.cases.split(",")]
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, args.build, "python"), OMP_NUM_THREADS=str(args.threads))

    def run(combo):
        cmd = [sys.executable, __file__, "--child", ",".join(combo), "--n", str(args.n), "--threads", str(args.threads)]
        res = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if res.returncode != 0:
            return combo, {"error": (res.stderr.strip().splitlines() or ["?"])[-1]}
        return combo, json.loads(res.stdout.strip().splitlines()[-1])

    with ThreadPoolExecutor(args.jobs) as pool:
        done = list(pool.map(run, combos))
    results = {}
    for (case, s, m, t), res in done:
        results.setdefault(f"{s}_{m}_{t}", {}).update(res)
    precision = next((r["precision"] for r in results.values() if "precision" in r), "?")
    lines = [f"Machine: {machine_line()}; {args.threads} thread(s) per run, {args.jobs} runs at a time; {precision}; "
             f"tank {args.n} x {args.n} x {2 * args.n} at r = {R} m (3 s), held box r = 0.01 m (1.5 s), jet r = 0.005 m (0.6 s).", "",
             "| solver | walls | treatment | particle RMS raw / field, % rho0 g H | slope raw / field (field's spread) | time-averaged field: RMS % / slope | "
             "floor layer raw / field | side layer raw / field | "
             "floor probe | side probe | floor force / weight | side force / hydrostatic | held box / rho0 V g | jet / mdot U | tank ms/step | "
             "M / (A H), rho0 |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key, r in results.items():
        s, m, t = key.split("_")
        if "rms_raw" not in r:
            lines.append(f"| {s} | {m} | {t} | {r.get('error', 'tank not run')} | | | | | | | | | "
                         f"{r.get('buoyancy', float('nan')):.3f} | {r.get('jet', float('nan')):.3f} | | |")
            continue
        name = t if t != "auto" else f"auto ({r['resolved_treatment']})"
        lines.append(f"| {s} | {m} | {name} | {r['rms_raw']:.1f} / {r['rms_field']:.1f} | "
                     f"{r['slope_raw']:.3f} / {r['slope_field']:.3f} (±{r['slope_field_spread']:.3f}) | "
                     f"{r['tavg_rms_field']:.1f} / {r['tavg_slope_field']:.3f} | "
                     f"{r['floor_layer_raw']:.2f} / {r['floor_layer_field']:.2f} | "
                     f"{r['side_layer_raw']:.2f} / {r['side_layer_field']:.2f} | {r['floor_probe']:.3f} | {r['side_probe']:.3f} | "
                     f"{r['floor_force']:.4f} | {r['side_force']:.3f} | {r.get('buoyancy', float('nan')):.3f} | {r.get('jet', float('nan')):.3f} | "
                     f"{r['ms_per_step']:.2f} | {r['fill']:.4f} |")
    table = "\n".join(lines) + "\n"
    print(table)
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "wall_pressure.md"), "w") as out:
        out.write(table)
    plot(results, os.path.join(HERE, "results", "wall_pressure"))


if __name__ == "__main__":
    main()
