#!/usr/bin/python3
"""Dynamic wall pressure: does a dam break's impact pressure converge? (the wall-pressure issue, item 3)

A water column 0.2 m long, 0.4 m high and 0.1 m deep (z) at one end of a 0.8 m tank collapses and
hits the far wall x = 0.8 m. Two pressure probes on that wall, at y = 0.03 m and y = 0.10 m (mid
depth in z), with a fixed radius of 0.025 m at every resolution (so each resolution measures the
same wall patch; the default 2h would shrink with r). Each run records the probes every step.

Per run (solver DFSPH, Akinci walls, one treatment, one particle radius, one maxTimeStep):
  arrival    first time the low probe reads more than 0.1 rho0 g H (H = 0.4 m);
  peak       the low probe's maximum, raw (every step) and after a centred moving average over 1 ms
             (or 3 steps where the step is longer than 1/3 ms), / rho0 g H;
  impulse    the integral of the low probe's pressure over [arrival, arrival + 50 ms], / (rho0 g H s);
  noise      RMS of (raw - that moving average) over the same window, / rho0 g H;
  late       the mean of the high probe over 0.55-0.6 s, / rho0 g H (after the first run-up);
  time       wall seconds, steps.
Convergence is read from the differences between successive resolutions (r halved): they must
shrink. The time-step sensitivity reruns the middle resolution with maxTimeStep halved.

Prints a markdown table (machine, threads, precision named), writes it to
bench/results/impact_pressure.md, the time series to bench/results/impact_pressure.csv and a PNG
of p(t) per treatment to bench/results/impact_pressure_<treatment>.png.
Usage: /usr/bin/python3 bench/impact_pressure.py [--quick] [--threads 2] [--build build]
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402

RHO0, G, H, L, W, DEPTH = 1000.0, 9.81, 0.4, 0.8, 0.2, 0.1
PROBE_RADIUS, END = 0.025, 0.6
TREATMENTS = ["consistent", "mirroring", "extrapolation"]


def scene(treatment, r, max_dt):
    sim = {"particleRadius": r, "stopAt": END, "boundaryPressure": treatment}
    if max_dt:
        sim["maxTimeStep"] = max_dt
    return {
        "name": "ImpactPressure",
        "simulation": sim,
        "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.001}],
                    "blocks": [{"min": [0, 0, 0], "max": [W, H, DEPTH]}]}],
        "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [L, 0.8, DEPTH]}, "inverted": True}],
        "probes": [{"name": "low", "kind": "pressure", "position": [L, 0.03, DEPTH / 2], "radius": PROBE_RADIUS},
                   {"name": "high", "kind": "pressure", "position": [L, 0.10, DEPTH / 2], "radius": PROBE_RADIUS}],
        "output": {"enabled": False},
    }


def moving_average(t, p, width):
    """Centred moving average over `width` seconds of a series with uneven steps."""
    import numpy as np
    out = np.empty_like(p)
    lo = hi = 0
    csum = np.concatenate([[0.0], np.cumsum(p)])
    for i, ti in enumerate(t):
        while t[lo] < ti - width / 2:
            lo += 1
        while hi < len(t) and t[hi] <= ti + width / 2:
            hi += 1
        out[i] = (csum[hi] - csum[lo]) / (hi - lo)
    return out


def measure(treatment, r, max_dt, threads):
    import numpy as np
    import consph
    consph.set_num_threads(threads)
    sim = consph.Simulation.from_dict(scene(treatment, r, max_dt))
    t0 = time.time()
    ts, low, high = [], [], []
    while sim.time < END - 1e-9:
        sim.step(1)
        ts.append(sim.time)
        low.append(sim.probes["low"])
        high.append(sim.probes["high"])
    wall = time.time() - t0
    t, p, q = np.array(ts), np.array(low), np.array(high)
    ref = RHO0 * G * H
    hit = np.nonzero(p > 0.1 * ref)[0]
    out = {"treatment": sim.summary()["boundaryPressure"], "r": r, "max_dt": max_dt, "wall": wall,
           "steps": sim.step_count, "precision": consph.precision, "t": ts, "low": low}
    if len(hit) == 0:
        out["error"] = "the front never reached the low probe"
        return out
    ta = t[hit[0]]
    window = (t >= ta) & (t <= ta + 0.05)
    dt = np.diff(np.concatenate([[0.0], t]))
    # 1 ms, or three steps where the step is longer (a 1 ms average of one sample is no average).
    width = max(0.001, 3 * float((t[-1] - t[0]) / (len(t) - 1)))
    smooth = moving_average(t, p, width)
    out.update({
        "arrival": float(ta),
        "peak": float(p[window].max() / ref),
        "peak_smooth": float(smooth[window].max() / ref),
        "impulse": float(np.sum(p[window] * dt[window]) / ref),
        "noise": float(np.sqrt(np.mean((p[window] - smooth[window]) ** 2)) / ref),
        "late": float(np.mean(q[(t >= 0.55)]) / ref),
        "mean_dt": float((t[-1] - t[0]) / (len(t) - 1)),
        "width": width,
    })
    return out


def plot(results, treatments):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    for treatment in treatments:
        fig, ax = plt.subplots(figsize=(6, 3.5))
        for res in results:
            if res["key"][0] != treatment or "t" not in res:
                continue
            label = f"r = {res['r']}" + (f", dt <= {res['max_dt']}" if res["max_dt"] else "")
            ax.plot(res["t"], [p / (RHO0 * G * H) for p in res["low"]], lw=0.8, label=label)
        ax.set_xlim(0.15, END)
        ax.set_xlabel("t, s")
        ax.set_ylabel("low probe p / rho0 g H")
        ax.set_title(f"dam break impact, DFSPH, Akinci walls, {treatment}", fontsize=9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(HERE, "results", f"impact_pressure_{treatment}.png"), dpi=110)
        plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="r = 0.01 and 0.005 only, no time-step rerun")
    ap.add_argument("--treatments", default=",".join(TREATMENTS))
    ap.add_argument("--build", default="build", help="build folder whose python/ module to run")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        treatment, r, max_dt = args.child.split(",")
        print(json.dumps(measure(treatment, float(r), float(max_dt), args.threads)))
        return
    radii = [0.01, 0.005] if args.quick else [0.01, 0.005, 0.0025]
    treatments = args.treatments.split(",")
    runs = [(t, r, 0.0) for t in treatments for r in radii]
    if not args.quick:
        # The middle resolution again with its time step halved (its mean step, measured first).
        runs += [(t, radii[1], "half") for t in treatments]
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, args.build, "python"), OMP_NUM_THREADS=str(args.threads))
    results = []
    for t, r, max_dt in runs:
        if max_dt == "half":
            base = next(x for x in results if x["key"] == (t, r, 0.0))
            max_dt = round(0.5 * base.get("mean_dt", 0.001), 6)
        cmd = [sys.executable, __file__, "--child", f"{t},{r},{max_dt}", "--threads", str(args.threads)]
        res = subprocess.run(cmd, capture_output=True, text=True, env=env)
        out = json.loads(res.stdout.strip().splitlines()[-1]) if res.returncode == 0 else {
            "error": (res.stderr.strip().splitlines() or ["?"])[-1], "r": r, "max_dt": max_dt}
        out["key"] = (t, r, 0.0 if max_dt == 0.0 else max_dt)
        results.append(out)
        print(f"{t} r={r} dt<={max_dt}: " + ", ".join(f"{k} {out[k]:.4g}" for k in
              ("arrival", "peak", "peak_smooth", "impulse", "noise", "late", "wall") if k in out), flush=True)
    precision = next((x["precision"] for x in results if "precision" in x), "?")
    lines = [f"Machine: {machine_line()}; {args.threads} thread(s); {precision}; DFSPH, Akinci walls, probes of radius "
             f"{PROBE_RADIUS} m on the far wall, p / rho0 g H (H = {H} m), impulse / (rho0 g H s).", "",
             "| treatment | r, m | max dt, s | mean dt, s | arrival, s | peak raw | average over, ms | peak averaged | "
             "impulse 50 ms | noise | high probe 0.55-0.6 s | wall s |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for x in results:
        t = x["key"][0]
        if "peak" not in x:
            lines.append(f"| {t} | {x['r']} | {x['max_dt'] or 'default'} | {x.get('error', '?')} | | | | | | | | |")
            continue
        lines.append(f"| {t} | {x['r']} | {x['max_dt'] or 'default'} | {x['mean_dt']:.2e} | {x['arrival']:.4f} | "
                     f"{x['peak']:.2f} | {1000 * x['width']:.1f} | {x['peak_smooth']:.2f} | {x['impulse']:.4f} | {x['noise']:.3f} | {x['late']:.3f} | "
                     f"{x['wall']:.0f} |")
    # Convergence: successive differences as r halves, per treatment and quantity.
    lines += ["", "| treatment | quantity | " + " | ".join(f"r {a} -> {b}" for a, b in zip(radii, radii[1:])) + " |",
              "|---|---|" + "---|" * (len(radii) - 1)]
    for t in treatments:
        series = [next((x for x in results if x["key"] == (t, r, 0.0) and "peak" in x), None) for r in radii]
        if None in series:
            continue
        for q in ("peak_smooth", "impulse", "late"):
            lines.append(f"| {t} | {q} | " + " | ".join(f"{b[q] - a[q]:+.4f}" for a, b in zip(series, series[1:])) + " |")
    table = "\n".join(lines) + "\n"
    print(table)
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "impact_pressure.md"), "w") as out:
        out.write(table)
    with open(os.path.join(HERE, "results", "impact_pressure.csv"), "w") as out:
        out.write("treatment,r,max_dt,t,low\n")
        for x in results:
            for ti, pi in zip(x.get("t", []), x.get("low", [])):
                out.write(f"{x['key'][0]},{x['r']},{x['max_dt']},{ti:.6f},{pi:.3f}\n")
    plot(results, treatments)


if __name__ == "__main__":
    main()
