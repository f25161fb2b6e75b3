#!/usr/bin/env python3
"""Dam-break benchmark (issue 2): runs data/scenes/DamBreak.json to 2 s (and at r = 0.0125) with
the given thread count in the float and double builds, and prints one table row per run.

    /usr/bin/python3 bench/dambreak.py [--threads 2] [--stop-at 2] [--radii 0.025 0.0125] [--builds float double]

The float build is made in build-bench-float/ (Release, -DCONSPH_DOUBLE=OFF); the double build is
build/. Not a test: figures vary with the machine's load.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import cpu_model  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def ensure_build(precision):
    build = os.path.join(ROOT, "build" if precision == "double" else "build-bench-float")
    if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
        subprocess.check_call(["cmake", "-S", ROOT, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                               "-DCONSPH_DOUBLE=" + ("ON" if precision == "double" else "OFF"),
                               "-DCONSPH_BUILD_TESTS=OFF", "-DCONSPH_BUILD_PYTHON=OFF"], stdout=subprocess.DEVNULL)
    subprocess.check_call(["cmake", "--build", build, "--target", "consph"], stdout=subprocess.DEVNULL)
    return os.path.join(build, "consph")


def run(binary, radius, threads, stop_at, extra):
    with tempfile.TemporaryDirectory() as tmp:
        summary = os.path.join(tmp, "summary.json")
        cmd = ["/usr/bin/time", "-v", binary, os.path.join(ROOT, "data/scenes/DamBreak.json"), "--quiet", "--no-output",
               "--threads", str(threads), "--stop-at", str(stop_at), "--set", "simulation.particleRadius=%g" % radius,
               "--summary-json", summary] + extra
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit("benchmark run failed:\n" + p.stderr)
        rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1)) / 1024
        s = json.load(open(summary))
        s["peakRssMB"] = rss
        return s


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--stop-at", type=float, default=2.0)
    ap.add_argument("--radii", type=float, nargs="+", default=[0.025, 0.0125])
    ap.add_argument("--builds", nargs="+", default=["float", "double"], choices=["float", "double"])
    ap.add_argument("--set", action="append", default=[], help="extra --set overrides for every run")
    args = ap.parse_args()
    extra = sum((["--set", s] for s in args.set), [])
    print("machine: %s, %d cores; threads: %d; scene: data/scenes/DamBreak.json to %g s" %
          (cpu_model(), os.cpu_count(), args.threads, args.stop_at))
    header = ("| precision | r | fluid | boundary | steps | p iters | div iters | density err avg % | ms/step | "
              "us/particle-step | peak RSS MB | neighbours s | pressure s | divergence s | forces s | densities s |")
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    for precision in args.builds:
        binary = ensure_build(precision)
        for r in args.radii:
            s = run(binary, r, args.threads, args.stop_at, extra)
            ph = s["phaseSeconds"]
            print("| %s | %g | %d | %d | %d | %.2f | %.2f | %.4f | %.2f | %.3f | %.0f | %.2f | %.2f | %.2f | %.2f | %.2f |" % (
                s["precision"], r, s["fluidParticles"], s["boundaryParticles"], s["steps"],
                s["averagePressureIterations"], s["averageDivergenceIterations"], s["averageDensityErrorPercent"],
                s["msPerStep"], s["usPerParticleStep"], s["peakRssMB"], ph["neighbourSearch"], ph["pressureSolve"],
                ph["divergenceSolve"], ph["nonPressureForces"], ph["densities"]), flush=True)


if __name__ == "__main__":
    main()
