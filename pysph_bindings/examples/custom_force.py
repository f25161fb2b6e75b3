"""A non-pressure force written in Python: wind blowing over a pool.

SurfaceWind drags the free-surface particles (those with fewer fluid + boundary neighbours than
the bulk, about 33 at rest) towards
the wind velocity, a_i = k (u_wind - v_i). It is registered under a name, so the scene names it
like a built-in plugin ({"type": "SurfaceWind", ...}), and uses the step's neighbour lists.
The wind piles the water up at the downwind wall (wind set-up): the script prints the surface
height at both ends of the pool with and without wind, and the cost of the Python force.

    PYTHONPATH=build/python /usr/bin/python3 pysph_bindings/examples/custom_force.py [--threads 2]
"""
import argparse

import numpy as np

import consph


@consph.register_force("SurfaceWind", parameters=[
    consph.Param("wind", "vector3", [1.0, 0.0, 0.0], "wind velocity u_wind, m/s"),
    consph.Param("drag", float, 5.0, "drag rate k, 1/s", min=0),
    consph.Param("surfaceNeighbors", int, 24, "a particle with fewer neighbours is at the surface", min=1),
])
class SurfaceWind(consph.Force):
    """Wind drag on free-surface particles: a_i = k (u_wind - v_i)."""

    def __init__(self, wind, drag, surfaceNeighbors):
        self.wind = np.asarray(wind)
        self.drag = drag
        self.surface_neighbors = surfaceNeighbors

    def add_acceleration(self, ctx, fluid):
        fluid_offsets, _ = ctx.fluid_neighbors()  # CSR lists of this step (copies)
        boundary_offsets, _ = ctx.boundary_neighbors()
        surface = np.diff(fluid_offsets) + np.diff(boundary_offsets) < self.surface_neighbors
        v = fluid.velocities  # zero-copy views of this step's particles
        fluid.accelerations[surface] += self.drag * (self.wind - v[surface])


def pool(wind):
    forces = [{"type": "StandardViscosity", "viscosity": 0.01}]
    if wind:
        forces.append({"type": "SurfaceWind", "wind": [1.0, 0.0, 0.0], "drag": 5.0})
    return {
        "name": "WindOverPool" if wind else "Pool",
        "simulation": {"particleRadius": 0.02, "maxTimeStep": 0.005, "stopAt": 1.5,
                       "pressureSolver": {"type": "DFSPH", "maxError": 0.05}},
        "fluids": [{"name": "water", "forces": forces,
                    "blocks": [{"min": [0.04, 0.04, 0.04], "max": [1.56, 0.36, 0.36]}]}],
        "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [1.6, 0.8, 0.4]}, "inverted": True}],
        "output": {"enabled": False},
    }


def surface_heights(sim):
    """Highest particle (plus r) in the first and last 0.2 m of the pool (0 where it is dry)."""
    x = sim.fluid().positions
    r = sim.particle_radius
    left, right = x[x[:, 0] < 0.2, 1], x[x[:, 0] > 1.4, 1]
    return (left.max() + r if len(left) else 0.0), (right.max() + r if len(right) else 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()
    if args.threads:
        consph.set_num_threads(args.threads)
    print("SurfaceWind is registered:", [p["name"] for p in consph.plugins()["forces"]])
    for wind in (False, True):
        sim = consph.Simulation.from_dict(pool(wind))
        sim.run(progress=False)
        upwind, downwind = surface_heights(sim)
        s = sim.summary()
        print(f"{s['scene']:13s} t = {sim.time:.2f} s, {s['fluidParticles']} particles: surface {upwind:.3f} m upwind, "
              f"{downwind:.3f} m downwind (set-up {downwind - upwind:+.3f} m), mean u = "
              f"{sim.fluid().velocities[:, 0].mean():+.3f} m/s; forces took {s['phaseSeconds']['nonPressureForces']:.2f} "
              f"of {s['wallSeconds']:.2f} s")


if __name__ == "__main__":
    main()
