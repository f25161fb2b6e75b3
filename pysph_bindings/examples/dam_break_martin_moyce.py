"""Dam break of a water column twice as high as wide (Martin & Moyce 1952, n^2 = 2).

Runs data/scenes/DamBreakMartinMoyce.json (width a, height 2a), records the surge front x(t) after
every step, and plots the dimensionless front Z = x / a against T = t sqrt(2 g / a) together with
Martin & Moyce's measurements; prints the RMS difference of Z at the measured times.

The front is the largest x of any particle plus its radius, measured from the column's initial
back face (the fluid block's min x): the block's lattice (spacing simulation.particleSpacing r, one particle of volume
d^3 per cell) fills [min, max] exactly, so Z = 1 at T = 0.

    PYTHONPATH=build/python /usr/bin/python3 pysph_bindings/examples/dam_break_martin_moyce.py \
        [--scene data/scenes/DamBreakMartinMoyce.json] [--png dam_break_martin_moyce.png] [--threads 2]
"""
import argparse
import json
import os
import time

import numpy as np

import consph

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DEFAULT_DATA = os.path.join(REPO, "data", "validation", "martin_moyce_1952_front_n2.csv")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=os.path.join(REPO, "data", "scenes", "DamBreakMartinMoyce.json"))
    ap.add_argument("--data", default=DEFAULT_DATA, help="Martin & Moyce front data (CSV with T,Z)")
    ap.add_argument("--png", default="dam_break_martin_moyce.png")
    ap.add_argument("--threads", type=int, default=0, help="OpenMP threads (default: all)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="scene override, as the CLI's")
    args = ap.parse_args()
    if args.threads:
        consph.set_num_threads(args.threads)

    measured = np.loadtxt(args.data, delimiter=",", comments="#", skiprows=3)
    overrides = {}
    for kv in args.set:
        key, value = kv.split("=", 1)
        try:
            overrides[key] = json.loads(value)
        except ValueError:
            overrides[key] = value  # a bare word is a string, as with the CLI's --set
    sim = consph.Simulation.from_file(args.scene, overrides=overrides, output=False)
    block = sim.scene["fluids"][0]["blocks"][0]
    a = block["max"][0] - block["min"][0]  # column width
    height = block["max"][1] - block["min"][1]
    x_back = block["min"][0]
    g = -sim.scene["simulation"]["gravity"][1]
    r = sim.particle_radius
    t_scale = np.sqrt(2 * g / a)  # T = t sqrt(2 g / a)
    t_end = (measured[:, 0].max() + 0.1) / t_scale
    water = sim.fluid("water")
    print(f"a = {a:g} m, height = {height:g} m ({height / a:.2f} a), r = {r} m, {len(water)} particles, "
          f"{consph.get_num_threads()} threads, {consph.precision}; simulating {t_end:.3f} s")

    def front():
        return (water.positions[:, 0].max() + r - x_back) / a  # a fresh view every call

    T, Z = [0.0], [front()]
    start = time.perf_counter()
    next_report = 0.5
    while sim.time < t_end:
        sim.step()
        T.append(sim.time * t_scale)
        Z.append(front())
        if T[-1] >= next_report:
            print(f"  T = {T[-1]:.2f}  Z = {Z[-1]:.3f}  ({time.perf_counter() - start:.0f} s)", flush=True)
            next_report += 0.5
    wall = time.perf_counter() - start
    T, Z = np.array(T), np.array(Z)

    Z_at = np.interp(measured[:, 0], T, Z)
    rms = np.sqrt(np.mean((Z_at - measured[:, 1]) ** 2))
    summary = sim.summary()
    print(f"{summary['steps']} steps in {wall:.1f} s ({summary['usPerParticleStep']:.2f} us/particle-step), "
          f"average density error {summary['averageDensityErrorPercent']:.3f} %")
    print(" T_measured  Z_measured  Z_simulated")
    for (tm, zm), zs in zip(measured, Z_at):
        print(f"  {tm:9.2f}  {zm:10.2f}  {zs:11.3f}")
    print(f"RMS difference of Z (front / a) against Martin & Moyce 1952: {rms:.3f} "
          f"(mean {np.mean(Z_at - measured[:, 1]):+.3f})")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(T, Z, "-", label=f"consph DFSPH, r = {r * 1000:g} mm ({len(water)} particles)")
    ax.plot(measured[:, 0], measured[:, 1], "o", mfc="none", label="Martin & Moyce 1952, n$^2$ = 2")
    ax.set_xlabel(r"$T = t\,\sqrt{2g/a}$")
    ax.set_ylabel(r"$Z = x_{front}/a$")
    ax.set_title(f"Dam break, column {height / a:.0f}a high, a = {a:g} m: RMS(Z) = {rms:.3f}", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
