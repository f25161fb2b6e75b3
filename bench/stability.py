#!/usr/bin/python3
"""Stress test: where the default time stepping stops being stable.

Runs small scenes at fine resolution with a fixed maximum time step set in each scene (5 ms,
SPlisHSPlasH's for r = 0.025, or 2 ms; the default cap follows the resolution since issue 15,
bench/RESULTS.md), large compared with the particle size, and reports for each variant whether it
ran to the end or stopped with a blow-up (the simulation's own error: step, time, cause).

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

Usage: bench/stability.py [--threads N] [--stop-at T] [--binary build/consph]"""
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


def run(binary, scene, threads, stop_at, tmp, tag):
    path = os.path.join(tmp, tag + ".json")
    json.dump(scene, open(path, "w"))
    summary = os.path.join(tmp, tag + ".summary.json")
    cmd = [binary, path, "--threads", str(threads), "--quiet", "--no-output", "--summary-json", summary,
           "--stop-at", str(stop_at)]
    start = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - start
    error = next((line for line in p.stderr.splitlines() if "error:" in line), "")
    m = re.search(r"step (\d+), t = ([0-9.e-]+) s: (.*)", error)
    # The cause without the particle's coordinates: "particle 20 (id 1808) left the domain".
    cause = m.group(3).split(" at (")[0] if m else error[:80]
    s = json.load(open(summary)) if os.path.exists(summary) else None
    return {"ok": p.returncode == 0, "wall": wall, "caps": s["iterationCapHits"] if s else 0,
            "failure": ("step %s, t = %.3f s: %s" % (m.group(1), float(m.group(2)), cause)) if m else cause,
            "summary": s}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--stop-at", type=float, default=0.4)
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "consph"))
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n, (scene_label, label, scene) in enumerate(variants()):
            rows.append((scene_label, label, run(args.binary, scene, args.threads, args.stop_at, tmp, "run%d" % n)))
    precision = next((r["summary"]["precision"] for _, _, r in rows if r["summary"]), "see the build")
    print("machine: %s, threads: %d, precision: %s, simulated to %.2f s" % (cpu_model(), args.threads, precision, args.stop_at))
    print("| scene | variant | result | steps | steps at the iteration cap | wall s |")
    print("|---|---|---|---|---|---|")
    for scene_label, label, r in rows:
        s = r["summary"]
        print("| %s | %s | %s | %s | %d | %.1f |" % (
            scene_label, label, "ran to the end" if r["ok"] else "stopped: " + r["failure"],
            s["steps"] if s else "-", r["caps"], r["wall"]))


if __name__ == "__main__":
    main()
