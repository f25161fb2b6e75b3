"""Shared helpers: tiny scenes built from dicts (a few hundred particles, fractions of a second)."""
import copy
import os
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "bench"))  # vtu.py

# One OpenMP thread: these scenes have a few hundred particles, and on a shared 2-core machine
# threads only wait for each other (libgomp reads this when consph loads it; threads that Python
# starts get it too). Bitwise comparisons below also rely on a fixed thread count.
os.environ.setdefault("OMP_NUM_THREADS", "1")
import consph  # noqa: E402  (PYTHONPATH=build/python)

consph.set_num_threads(int(os.environ["OMP_NUM_THREADS"]))

# The CLI of the same build (the module lives in BUILD/python/consph): messages and summaries
# are compared with it.
CLI = os.environ.get("CONSPH_BINARY") or os.path.join(
    os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(consph.__file__)))), "consph")

# Round-off of the build's Real (consph.precision): absolute for positions of order 1 m, relative.
ATOL = 1e-12 if consph.precision == "double" else 1e-5
RTOL = 1e-9 if consph.precision == "double" else 1e-5
FLOAT_EPS = 2.0 ** -23  # float's machine epsilon, 1.19e-7


def roundoff(double_tol, float_tol):
    """The tolerance of this build, as test::roundoff in tests/TestUtil.h: double_tol (unchanged)
    in a double build, float_tol (written as a multiple of FLOAT_EPS) in a float build."""
    return double_tol if consph.precision == "double" else float_tol

R = 0.025  # particle radius of the tiny scenes, m


def tank_scene(**simulation):
    """A 0.4 x 0.4 x 0.2 m block of water (8 x 8 x 4 = 256 particles of radius 0.025 m) in a closed tank."""
    sim = {"particleRadius": R, "maxTimeStep": 0.005, "sortInterval": 5,
           "pressureSolver": {"type": "DFSPH", "maxError": 0.01}}
    sim.update(simulation)
    return {
        "name": "TinyTank",
        "simulation": sim,
        "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                    "blocks": [{"min": [0.1, 0.1, 0.1], "max": [0.5, 0.5, 0.3]}]}],
        "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [0.6, 1.0, 0.4]}, "inverted": True}],
        "output": {"enabled": False},
    }


def free_particles_scene(count=4, spacing=10 * R, dt=1e-3):
    """`count`^3 single-particle blocks, `spacing` apart (more than the support 4r): no neighbours,
    no boundary, no gravity, a fixed time step. Such particles move only by the forces given."""
    blocks = []
    for i in range(count):
        for j in range(count):
            for k in range(count):
                lo = [i * spacing, j * spacing, k * spacing]
                blocks.append({"min": lo, "max": [c + 2 * R for c in lo]})
    return {
        "name": "FreeParticles",
        "simulation": {"particleRadius": R, "gravity": [0, 0, 0], "minTimeStep": dt, "maxTimeStep": dt,
                       "initialTimeStep": dt},
        "fluids": [{"name": "water", "blocks": blocks}],
        "output": {"enabled": False},
    }


@pytest.fixture
def tank():
    return consph.Simulation.from_dict(tank_scene())


@pytest.fixture
def free():
    return consph.Simulation.from_dict(free_particles_scene())


@pytest.fixture
def scene_copy():
    return lambda scene: copy.deepcopy(scene)
