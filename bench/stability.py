#!/usr/bin/python3
"""Stress tests: where the time stepping and the boundaries stop being stable.

Two suites (--suite):

stress (the default; issue 15 item 5): every case at the scene defaults (no maxTimeStep, no
cflFactor unless the case names one), once with particle walls ("Akinci2012") and once with volume
maps ("VolumeMap"), each run in a child process through the Python module so that every step is
observed. For each: whether it ran to the end (or the run's own stop message: step, time, cause),
steps, steps at the pressure solver's iteration cap, peak fluid and body speeds over every step,
particles lost (fluid particles ever more than 2 r beyond their container's walls, or, for the
jet, through its plate; bodies whose centre left the container) and wall time (scene set-up
included). Cases (STRESS_CASES below has the scenes):
  fine columns   0.1 m wide, 1 m deep, 1 cm from the walls, r = 0.01, 0.006, 0.004, 0.5 s;
  full tank      a 0.2 m cube of fluid drawn up to its tank's walls, r = 0.005, 0.4 s;
  DamBreak       data/scenes/DamBreak.json as it is (its own maxTimeStep 5 ms and cflFactor 1
                 stand: a user who changes only the radius) at r = 0.025 (the file's), 0.0125 and
                 0.01, 0.5 s; r = 0.006 (704 969 particles, ~1 min per step on 2 cores) is not run;
  closing gap    tests/physics RigidBodies.DISABLED_AnOffCentreSinkingBoxRestsOnTheFloor's scene
                 (a 2 rho0 box 3 mm off-centre sinking onto the floor) without its maxTimeStep, 2 s;
  overlap        two boxes 5 cm into each other and one 5 cm into the floor at t = 0, in water, 1 s;
  light, heavy   a 0.01 rho0 box released under 0.25 m of water; a 100 rho0 box dropped into it, 1 s;
  jet            a 20 m/s round jet onto a plate one sample layer thick (particle walls: a square
                 sampled once; volume maps, which refuse open meshes: a box r thick), r = 0.01,
                 0.25 s: nothing may pass through the plate;
  rest           a 0.4 x 0.8 x 0.4 m column drawn up to its walls, r = 0.025, cflFactor 1, 20 s:
                 the mean speed at the end must stay below 1 cm/s;
  50 bodies      50 boxes of 400-2500 kg/m^3 dropped into a tank of water, r = 0.015, 1 s.
--quick drops the r = 0.004 column and the two finer dam breaks (about 3 of the 17 minutes on one
core). --json FILE keeps every figure (where the fastest and the first lost particle were, ...);
--table FILE prints such a file's table again.
--write-scenes DIR writes each case's scene file, so that a row runs again with the CLI:
  consph DIR/ID_MODEL.json --threads 1 --no-output --stop-at T.

caps: the scenes of issue 15 with a fixed maximum time step in each scene (5 ms, SPlisHSPlasH's
for r = 0.025, or 2 ms), large compared with the particle size, through the CLI:
  A  a 1 m deep, 0.2 m wide column dropped from rest, r = 0.006 (22 528 particles, 88 layers):
     the start-up of a deep column;
  B  a 0.4 x 0.2 x 0.4 m block filling its tank to the walls, every sample layer offset
     ("offsetObjects": "all"), r = 0.005 (38 829 particles), maximum step 2 ms;
  C  the same block with the scene defaults (5 ms, CFL 1, "offsetObjects": "auto") at
     r = 0.025 and 0.0075, against the tank's samples kept on the mesh ("moving", the default
     before "auto"): how a fluid drawn up to its container's walls starts;
  A, B and C again with volume-map walls ("boundaryModel": "VolumeMap", Bender et al. 2019).

Prints a table with the machine, thread count and precision. Nothing here is asserted: it maps
the stable region so that the limits in docs/scene-format.md are measured, not guessed.

Usage: bench/stability.py [--suite stress|caps] [--quick] [--threads N] [--build build]
                          [--models Akinci2012,VolumeMap] [--only ID,...] [--write-scenes DIR] [--json FILE]
       bench/stability.py --table FILE
       bench/stability.py --suite caps [--threads N] [--stop-at T]
(--build: a folder holding consph and python/consph, as build/ does; Python: /usr/bin/python3.)"""
import argparse
import json
import os
import re
import subprocess
import tempfile
import time

import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import cpu_model  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = ["Akinci2012", "VolumeMap"]
VISCOSITY = [{"type": "StandardViscosity", "viscosity": 0.01}]


def column_scene():
    return {
        "simulation": {"particleRadius": 0.006, "maxTimeStep": 0.005, "cflFactor": 1,
                       "pressureSolver": {"type": "DFSPH", "maxError": 0.05, "maxErrorDivergence": 0.1}},
        "fluids": [{"forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                    "blocks": [{"min": [0.012, 0.012, 0.012], "max": [0.2, 1.0, 0.2]}]}],
        "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [0.212, 1.5, 0.212]}, "inverted": True}],
        "output": {"enabled": False}}


def block_scene():
    return {
        "simulation": {"particleRadius": 0.005, "maxTimeStep": 0.002, "cflFactor": 1,
                       "boundaryModel": {"type": "Akinci2012", "offsetObjects": "all"}},
        "fluids": [{"forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                    "blocks": [{"min": [0, 0, 0], "max": [0.4, 0.2, 0.4]}]}],
        "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [0.4, 0.5, 0.4]}, "inverted": True}],
        "output": {"enabled": False}}


def variants():
    """(scene label, variant label, scene) for every run."""
    out = []
    for label, change in (("consistent, CFL 1, dt <= 5 ms", {}),
                          ("mirroring, CFL 1, dt <= 5 ms", {"boundaryPressure": "mirroring"}),
                          ("consistent, CFL 0.5, dt <= 5 ms", {"cflFactor": 0.5}),
                          ("consistent, CFL 1, dt <= 2.5 ms", {"maxTimeStep": 0.0025})):
        s = column_scene()
        s["simulation"].update(change)
        out.append(("A deep column, r = 0.006", label, s))
    for label, change in (("consistent, CFL 1, dt <= 2 ms", {}),
                          ("consistent, CFL 0.5, dt <= 2 ms", {"cflFactor": 0.5}),
                          ("consistent, CFL 1, dt <= 1 ms", {"maxTimeStep": 0.001})):
        s = block_scene()
        s["simulation"].update(change)
        out.append(("B block to the walls, r = 0.005", label, s))
    for r in (0.025, 0.0075):
        for label, offset in (('defaults ("auto")', None), ('samples on the mesh ("moving")', "moving")):
            s = block_scene()
            s["simulation"].update({"particleRadius": r, "maxTimeStep": 0.005})
            del s["simulation"]["boundaryModel"]
            if offset:
                s["simulation"]["boundaryModel"] = {"type": "Akinci2012", "offsetObjects": offset}
            out.append(("C block to the walls, r = %g" % r, label, s))
    for scene_label, s in (("A deep column, r = 0.006", column_scene()), ("B block to the walls, r = 0.005", block_scene()),
                           ("C block to the walls, r = 0.0075", block_scene())):
        if scene_label.startswith("C"):
            s["simulation"].update({"particleRadius": 0.0075, "maxTimeStep": 0.005})
        s["simulation"]["boundaryModel"] = {"type": "VolumeMap"}
        out.append((scene_label, "volume maps, consistent, CFL 1, dt <= %g ms" % (1000 * s["simulation"]["maxTimeStep"]), s))
    return out


def run_cli(binary, scene, threads, stop_at, tmp, tag):
    path = os.path.join(tmp, tag + ".json")
    json.dump(scene, open(path, "w"))
    summary = os.path.join(tmp, tag + ".summary.json")
    cmd = [binary, path, "--threads", str(threads), "--quiet", "--no-output", "--summary-json", summary,
           "--stop-at", str(stop_at)]
    start = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - start
    error = next((line for line in p.stderr.splitlines() if "error:" in line), "")
    s = json.load(open(summary)) if os.path.exists(summary) else None
    return {"ok": p.returncode == 0, "wall": wall, "caps": s["iterationCapHits"] if s else 0,
            "failure": failure_text(error), "summary": s}


def failure_text(message):
    """The run's own stop message shortened to step, time and cause (without coordinates and advice):
    "step 20, t = 0.021 s: particle 20 (id 1808) left the domain"."""
    m = re.search(r"step (\d+), t = ([0-9.e+-]+) s: (.*)", message)
    if not m:
        return message[:100]
    cause = m.group(3).split(" at (")[0].split(": ")[0].split(" (|v|")[0]
    return "step %s, t = %.3f s: %s" % (m.group(1), float(m.group(2)), cause)


# The stress suite's scenes: what a user writes, at the defaults (no time-step settings).

def tank(hi, lo=(0, 0, 0)):
    return {"name": "tank", "box": {"min": list(lo), "max": list(hi)}, "inverted": True}


def fluid(lo, hi):
    return {"forces": VISCOSITY, "blocks": [{"min": list(lo), "max": list(hi)}]}


def box_body(name, lo, hi, density):
    return {"name": name, "box": {"min": list(lo), "max": list(hi)}, "dynamic": True, "density": density}


def fine_column(r):
    # tests/physics/test_time_step.cpp's column: 0.1 m wide, 1 cm from the walls, here 1 m deep.
    return {"simulation": {"particleRadius": r}, "fluids": [fluid((0.01, 0.01, 0.01), (0.11, 1.01, 0.11))],
            "boundaries": [tank((0.12, 1.5, 0.12))]}


def full_tank(r):
    return {"simulation": {"particleRadius": r}, "fluids": [fluid((0, 0, 0), (0.2, 0.2, 0.2))],
            "boundaries": [tank((0.2, 0.3, 0.2))]}


def dam_break(r):
    scene = json.load(open(os.path.join(ROOT, "data", "scenes", "DamBreak.json")))
    scene["simulation"]["particleRadius"] = r
    return scene


def closing_gap():
    # expectSinkingBoxRests(0.003, 0.001) in tests/physics/test_rigid_bodies.cpp, without its 4 ms cap.
    return {"simulation": {"particleRadius": 0.025}, "fluids": [{"blocks": [{"min": [0.05, 0.05, 0.05], "max": [0.55, 0.25, 0.55]}]}],
            "boundaries": [tank((0.6, 1.0, 0.6)), box_body("box", (0.203, 0.351, 0.2), (0.403, 0.451, 0.4), 2000)]}


def overlapping_bodies():
    # RigidBodyGuards.OverlappingBodiesAtTheStartWarnAndSeparateGently's overlaps, in water with gravity.
    return {"simulation": {"particleRadius": 0.025}, "fluids": [fluid((0, 0, 0), (1.0, 0.3, 0.6))],
            "boundaries": [tank((1.0, 0.8, 0.6)), box_body("a", (0.1, 0.2, 0.2), (0.3, 0.4, 0.4), 1000),
                           box_body("b", (0.25, 0.23, 0.22), (0.45, 0.43, 0.42), 500),
                           box_body("c", (0.7, -0.05, 0.2), (0.9, 0.15, 0.4), 800)]}


def loose_body(density, lo, hi):
    # RigidBodyGuards' submerged box: a 0.1 m box and 0.25 m of water in a 0.4 m tank.
    return {"simulation": {"particleRadius": 0.025}, "fluids": [fluid((0, 0, 0), (0.4, 0.25, 0.4))],
            "boundaries": [tank((0.4, 0.8, 0.4)), box_body("body", lo, hi, density)]}


JET_R = 0.01
PLATE_MESH = "plate.obj"  # a unit square in the x-z plane, written beside the scene


def jet_onto_plate(model):
    # A 20 m/s round jet (radius 4 r) 0.15 m above a 0.6 m plate one sample layer thick: with
    # particle walls a square of two triangles (an open mesh, sampled once); volume maps refuse
    # open meshes, so there it is a box r thick, one sample spacing. Fluid is removed 0.1 m short
    # of the plate's edges and 0.2 m under it, so what is under it came through it.
    r = JET_R
    if model == "Akinci2012":
        plate = {"name": "plate", "mesh": PLATE_MESH, "scale": [0.6, 1, 0.6]}
    else:
        plate = {"name": "plate", "box": {"min": [-0.3, -r, -0.3], "max": [0.3, 0, 0.3]}}
    return {"simulation": {"particleRadius": r, "domain": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}},
            "fluids": [{"forces": VISCOSITY,
                        "emitters": [{"shape": "circle", "position": [0, 0.15, 0], "direction": [0, -1, 0], "speed": 20.0,
                                      "radius": 4 * r}],
                        "removeOutside": {"min": [-0.2, -0.2, -0.2], "max": [0.2, 0.4, 0.2]}}],
            "boundaries": [plate]}


def write_plate_mesh(folder):
    with open(os.path.join(folder, PLATE_MESH), "w") as f:
        f.write("v -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0.5 0 0.5\nv -0.5 0 0.5\nf 1 3 2\nf 1 4 3\n")


def resting_column():
    return {"simulation": {"particleRadius": 0.025, "cflFactor": 1}, "fluids": [fluid((0, 0, 0), (0.4, 0.8, 0.4))],
            "boundaries": [tank((0.4, 1.2, 0.4))]}


def fifty_bodies():
    # 0.08 m boxes (5.3 r) in two layers of 5 x 5 above 0.3 m of water, densities 400-2500 in turn.
    densities = [400, 700, 1000, 1500, 2500]
    bodies = []
    for n in range(50):
        layer, i, k = n // 25, n % 5, (n // 5) % 5
        lo = (0.08 + 0.14 * i, 0.45 + 0.15 * layer, 0.08 + 0.14 * k)
        bodies.append(box_body("b%02d" % n, lo, (lo[0] + 0.08, lo[1] + 0.08, lo[2] + 0.08), densities[n % 5]))
    return {"simulation": {"particleRadius": 0.015}, "fluids": [fluid((0, 0, 0), (0.8, 0.3, 0.8))],
            "boundaries": [tank((0.8, 1.0, 0.8))] + bodies}


# (id, row label, scene, simulated seconds, in --quick, the row's own check)
STRESS_CASES = [
    ("column-0.01", "fine column 0.1 x 1 m, r = 0.01", lambda m: fine_column(0.01), 0.5, True, None),
    ("column-0.006", "fine column 0.1 x 1 m, r = 0.006", lambda m: fine_column(0.006), 0.5, True, None),
    ("column-0.004", "fine column 0.1 x 1 m, r = 0.004", lambda m: fine_column(0.004), 0.5, False, None),
    ("full-tank", "0.2 m cube filling its tank, r = 0.005", lambda m: full_tank(0.005), 0.4, True, None),
    ("dambreak-0.025", "DamBreak.json, r = 0.025 (the file's)", lambda m: dam_break(0.025), 0.5, True, None),
    ("dambreak-0.0125", "DamBreak.json, r = 0.0125", lambda m: dam_break(0.0125), 0.5, False, None),
    ("dambreak-0.01", "DamBreak.json, r = 0.01", lambda m: dam_break(0.01), 0.5, False, None),
    ("closing-gap", "closing gap: 2 rho0 box 3 mm off-centre onto the floor", lambda m: closing_gap(), 2.0, True, "rests"),
    ("overlap", "bodies overlapping at t = 0 (two boxes, one in the floor)", lambda m: overlapping_bodies(), 1.0, True, "warned"),
    ("light-body", "0.01 rho0 box released under water", lambda m: loose_body(10, (0.15, 0.08, 0.15), (0.25, 0.18, 0.25)), 1.0,
     True, None),
    ("heavy-body", "100 rho0 box dropped into water", lambda m: loose_body(1e5, (0.15, 0.4, 0.15), (0.25, 0.5, 0.25)), 1.0, True,
     None),
    ("jet", "20 m/s jet onto a plate one sample layer thick, r = 0.01", jet_onto_plate, 0.25, True, "through"),
    ("rest", "column resting 20 s, r = 0.025, cflFactor 1", lambda m: resting_column(), 20.0, True, "mean speed"),
    ("50-bodies", "50 boxes dropped into a tank, r = 0.015", lambda m: fifty_bodies(), 1.0, True, None),
]


def with_model(scene, model):
    scene = json.loads(json.dumps(scene))
    scene["simulation"]["boundaryModel"] = {"type": model}
    scene["output"] = {"enabled": False}
    return scene


def observe(job):
    """Runs one case in this process (the child of main), watching every step; returns its figures."""
    import numpy as np
    import consph
    consph.set_num_threads(job["threads"])
    scene, stop_at = job["scene"], job["stopAt"]
    container = next((b["box"] for b in scene["boundaries"] if b.get("inverted")), None)
    # The jet's plate: under it is below its lower face and within its 0.6 m square.
    plate = next((b for b in scene["boundaries"] if b.get("name") == "plate"), None)
    plate_bottom = (plate["box"]["min"][1] if "box" in plate else 0.0) if plate else None
    r = scene["simulation"]["particleRadius"]
    warnings = []
    out = {"status": 0, "error": "", "peakSpeed": 0.0, "peakSpeedTime": 0.0, "peakBodySpeed": 0.0, "peakBodySpin": 0.0}
    lost, through, bodies_out = set(), set(), set()

    def watch(sim):
        f = sim.fluid()
        v, x, ids = f.velocities, f.positions, f.ids
        if len(v):
            speed2 = np.einsum("ij,ij->i", v, v)
            i = int(np.argmax(speed2))
            if speed2[i] > out["peakSpeed"] ** 2:
                out.update(peakSpeed=float(np.sqrt(speed2[i])), peakSpeedTime=sim.time, peakSpeedAt=x[i].tolist())
        if container and len(x):
            outside = np.any((x < np.array(container["min"]) - 2 * r) | (x > np.array(container["max"]) + 2 * r), axis=1)
            if np.any(outside) and not lost:
                out["firstLost"] = {"t": sim.time, "id": int(ids[outside][0]), "at": x[outside][0].tolist()}
            lost.update(ids[outside].tolist())
        if plate is not None and len(x):
            under = (x[:, 1] < plate_bottom) & (np.abs(x[:, 0]) < 0.3) & (np.abs(x[:, 2]) < 0.3)
            through.update(ids[under].tolist())
        for b in sim.bodies:
            out["peakBodySpeed"] = max(out["peakBodySpeed"], float(np.linalg.norm(b["velocity"])))
            out["peakBodySpin"] = max(out["peakBodySpin"], float(np.linalg.norm(b["angular_velocity"])))
            p = np.array(b["position"])
            if container and (np.any(p < container["min"]) or np.any(p > container["max"])):
                bodies_out.add(b["name"])

    start = time.time()
    try:
        sim = consph.Simulation.from_dict(scene, base_dir=job["dir"], output=False,
                                          log=lambda level, message: warnings.append(message) if level == "warning" else None)
    except consph.SceneError as e:
        out.update(status=2, error=str(e), wall=time.time() - start)
        return out
    try:
        sim.run(until=stop_at, progress=watch)
    except consph.SimulationError as e:
        out.update(status=3, error=str(e))
        watch(sim)  # the state of the failed step
    out["wall"] = time.time() - start
    v = sim.fluid().velocities
    out["meanSpeed"] = float(np.mean(np.linalg.norm(v, axis=1))) if len(v) else 0.0
    out["bodiesEnd"] = [{"name": b["name"], "speed": float(np.linalg.norm(b["velocity"])), "y": float(b["position"][1])}
                        for b in sim.bodies]
    out["overlapWarnings"] = sum("overlap" in w for w in warnings)
    out.update(lost=len(lost), through=len(through), bodiesLost=sorted(bodies_out), summary=sim.summary(),
               precision=consph.precision)
    return out


def check_text(kind, res):
    """The row's own criterion, where the issue states one."""
    if kind == "rests":
        b = res["bodiesEnd"][0]
        return "box at rest at the end: |v| = %.3g m/s (test: < 0.02), centre %.3f m up" % (b["speed"], b["y"])
    if kind == "warned":
        return "%d overlap warnings" % res["overlapWarnings"]
    if kind == "through":
        return "%d particles through the plate (must be 0)" % res["through"]
    if kind == "mean speed":
        return "mean speed at the end %.2g m/s (must be < 0.01)" % res["meanSpeed"]
    return ""


def run_stress(args):
    cases = [c for c in STRESS_CASES if (c[4] or not args.quick) and (not args.only or c[0] in args.only.split(","))]
    env = dict(os.environ, PYTHONPATH=os.path.join(os.path.abspath(args.build), "python"),
               OMP_NUM_THREADS=str(args.threads))
    rows, total = [], time.time()
    with tempfile.TemporaryDirectory() as tmp:
        if args.write_scenes:
            os.makedirs(args.write_scenes, exist_ok=True)
            write_plate_mesh(args.write_scenes)
        for name, label, build, stop_at, _, kind in cases:
            for model in args.models.split(","):
                scene = with_model(build(model), model)
                tag = "%s_%s" % (name, model)
                if args.write_scenes:
                    json.dump(scene, open(os.path.join(args.write_scenes, tag + ".json"), "w"), indent=1)
                # A folder of its own: the scene's meshes and its volume-map cache (none reused).
                folder = os.path.join(tmp, tag)
                os.makedirs(folder)
                write_plate_mesh(folder)
                job = os.path.join(folder, "job.json")
                json.dump({"scene": scene, "stopAt": stop_at, "threads": args.threads, "dir": folder,
                           "result": os.path.join(folder, "result.json")}, open(job, "w"))
                start = time.time()
                try:
                    p = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", job], env=env,
                                       capture_output=True, text=True, timeout=args.timeout)
                    why = (p.stderr.strip().splitlines() or ["exit code %d, no result" % p.returncode])[-1]
                except subprocess.TimeoutExpired:
                    why = "not finished after %g s (--timeout)" % args.timeout
                wall = time.time() - start
                try:
                    res = json.load(open(os.path.join(folder, "result.json")))
                except OSError:
                    res = {"status": -1, "error": why}
                res["wall"] = wall
                print("%s %s: %s (%.1f s)" % (name, model, "ok" if res["status"] == 0 else failure_text(res["error"]), wall),
                      file=sys.stderr, flush=True)
                rows.append((name, label, model, stop_at, kind, res))
    record = {"machine": cpu_model(), "threads": args.threads, "models": args.models.split(","),
              "precision": next((r["precision"] for *_, r in rows if "precision" in r), "see the build"),
              "totalWall": time.time() - total,
              "rows": [{"case": name, "label": label, "model": model, "stopAt": stop_at, "check": kind, **res}
                       for name, label, model, stop_at, kind, res in rows]}
    if args.json:
        json.dump(record, open(args.json, "w"), indent=1)
    print_stress_table(record)


def print_stress_table(record):
    print("machine: %s, threads: %d, precision: %s; scene defaults (no maxTimeStep, no cflFactor unless the row "
          "names one), walls: %s; total wall %.0f s" % (record["machine"], record["threads"], record["precision"],
                                                        ", ".join(record["models"]), record["totalWall"]))
    print()
    print("| case | walls | simulated s | result | steps | steps at the iteration cap | peak fluid speed m/s (at t s) | "
          "peak body speed m/s, spin rad/s | mean fluid speed at the end m/s | particles lost | check | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for res in record["rows"]:
        s = res.get("summary")
        out = res.get("bodiesLost", [])
        lost = "-" if s is None else "%d%s" % (res["lost"] + res["through"], "" if not out else
                                                "; body '%s' out of the tank" % out[0] if len(out) == 1 else
                                                "; %d bodies out of the tank" % len(out))
        body = "%.3g, %.3g" % (res["peakBodySpeed"], res["peakBodySpin"]) if s and s["movingBodies"] else "-"
        print("| %s | %s | %g | %s | %s | %s | %s | %s | %s | %s | %s | %.1f |" % (
            res["label"], res["model"], res["stopAt"],
            "ran to the end" if res["status"] == 0 else "stopped: " + failure_text(res["error"]),
            s["steps"] if s else "-", s["iterationCapHits"] if s else "-",
            "%.3g (%.3f)" % (res["peakSpeed"], res["peakSpeedTime"]) if s else "-", body,
            "%.2g" % res["meanSpeed"] if s else "-", lost, check_text(res["check"], res) if s else "", res["wall"]))


def run_caps(args):
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n, (scene_label, label, scene) in enumerate(variants()):
            rows.append((scene_label, label, run_cli(os.path.join(args.build, "consph"), scene, args.threads, args.stop_at, tmp,
                                                     "run%d" % n)))
    precision = next((r["summary"]["precision"] for _, _, r in rows if r["summary"]), "see the build")
    print("machine: %s, threads: %d, precision: %s, simulated to %.2f s" % (cpu_model(), args.threads, precision, args.stop_at))
    print("| scene | variant | result | steps | steps at the iteration cap | wall s |")
    print("|---|---|---|---|---|---|")
    for scene_label, label, r in rows:
        s = r["summary"]
        print("| %s | %s | %s | %s | %d | %.1f |" % (
            scene_label, label, "ran to the end" if r["ok"] else "stopped: " + r["failure"],
            s["steps"] if s else "-", r["caps"], r["wall"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", choices=["stress", "caps"], default="stress")
    ap.add_argument("--quick", action="store_true", help="stress: without the most expensive cases")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder: its consph and python/ module")
    ap.add_argument("--models", default=",".join(MODELS), help="stress: comma-separated boundary models")
    ap.add_argument("--only", help="stress: comma-separated case ids (%s)" % ", ".join(c[0] for c in STRESS_CASES))
    ap.add_argument("--write-scenes", help="stress: write each case's scene file into this folder")
    ap.add_argument("--timeout", type=float, default=900, help="stress: seconds one run may take")
    ap.add_argument("--json", help="stress: write every row's figures to this file")
    ap.add_argument("--table", help="stress: print the table of a --json file again, without running")
    ap.add_argument("--stop-at", type=float, default=0.4, help="caps: simulated seconds")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        job = json.load(open(args.child))
        json.dump(observe(job), open(job["result"], "w"))
    elif args.table:
        print_stress_table(json.load(open(args.table)))
    elif args.suite == "stress":
        run_stress(args)
    else:
        run_caps(args)


if __name__ == "__main__":
    main()
