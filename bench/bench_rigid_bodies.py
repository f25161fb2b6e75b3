#!/usr/bin/python3
"""Cost of the rigid-body coupling (issue 4) and the water-wheel scene.

Runs data/scenes/Buoyancy.json three ways on the same fluid: the three boxes static, animated
with zero velocity (the coupling's whole machinery - solver impulses per pair, per-thread
gathering, sample update, boundary grid rebuild - on an identical fluid) and dynamic (the real
scene, whose fluid then differs). Then data/scenes/WaterWheel.json. Prints a table with the
machine, thread count and precision.

Usage: bench/bench_rigid_bodies.py [--threads N] [--stop-at T] [--binary build/consph]
                                   [--boundary-model Akinci2012|VolumeMap]"""
import argparse
import json
import os
import subprocess
import tempfile

import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import cpu_model  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(binary, scene, threads, stop_at, tmp, tag):
    path = os.path.join(tmp, tag + ".json")
    json.dump(scene, open(path, "w"))
    summary = os.path.join(tmp, tag + ".summary.json")
    cmd = [binary, path, "--threads", str(threads), "--quiet", "--no-output", "--summary-json", summary]
    if stop_at:
        cmd += ["--stop-at", str(stop_at)]
    subprocess.run(cmd, check=True)
    return json.load(open(summary))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--stop-at", type=float, default=1.0, help="simulated seconds of the buoyancy runs")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "consph"))
    ap.add_argument("--boundary-model", default="Akinci2012", choices=["Akinci2012", "VolumeMap"],
                    help="boundary model of every run (the scenes' own: Akinci2012)")
    args = ap.parse_args()

    def with_model(scene):
        model = scene["simulation"].get("boundaryModel", {"type": "Akinci2012"})
        model = {"type": model} if isinstance(model, str) else dict(model)
        if model["type"] != args.boundary_model:
            model = {"type": args.boundary_model, **({"offsetObjects": model["offsetObjects"]}
                                                    if model.get("offsetObjects") in ("auto", "all", "none") else {})}
        scene["simulation"]["boundaryModel"] = model
        return scene
    base = json.load(open(os.path.join(ROOT, "data", "scenes", "Buoyancy.json")))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for tag in ("static", "animated", "dynamic"):
            scene = json.loads(json.dumps(base))
            for b in scene["boundaries"][1:]:
                if tag != "dynamic":
                    b.pop("dynamic"), b.pop("density")
                if tag == "animated":
                    b["animated"] = {"velocity": [0, 0, 0]}
            rows.append(("Buoyancy, boxes " + tag, run(args.binary, with_model(scene), args.threads, args.stop_at, tmp, tag)))
        wheel = json.load(open(os.path.join(ROOT, "data", "scenes", "WaterWheel.json")))
        wheel["boundaries"][0]["mesh"] = os.path.join(ROOT, "data", "meshes", "WaterWheel.obj")
        rows.append(("WaterWheel (to stopAt)", run(args.binary, with_model(wheel), args.threads, None, tmp, "wheel")))
    s0 = rows[0][1]
    print("machine: %s, threads: %d, precision: %s, boundary model: %s" % (cpu_model(), s0["threads"], s0["precision"],
                                                                          args.boundary_model))
    print("| run | fluid particles (end) | boundary samples | steps | simulated s | wall s | ms / step | "
          "rigid-body phase s | neighbour search s | pressure iters | emitted | removed |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, s in rows:
        ph = s["phaseSeconds"]
        print("| %s | %d | %d | %d | %.2f | %.2f | %.3f | %.3f | %.2f | %.2f | %d | %d |" % (
            name, s["fluidParticles"], s["boundaryParticles"], s["steps"], s["simulatedTime"], s["wallSeconds"],
            s["msPerStep"], ph.get("rigidBodies", 0), ph["neighbourSearch"], s["averagePressureIterations"],
            s.get("particlesEmitted", 0), s.get("particlesRemoved", 0)))


if __name__ == "__main__":
    main()
