"""Forces written in Python: attached per fluid or registered under a name for scene files."""
import numpy as np
import pytest

import consph
from conftest import ATOL, RTOL, free_particles_scene


class ConstantAcceleration(consph.Force):
    """Adds a constant acceleration to every particle."""

    def __init__(self, a=(0.0, 0.0, 0.0)):
        self.a = np.asarray(a, dtype=float)
        self.calls = 0

    def add_acceleration(self, ctx, fluid):
        self.calls += 1
        fluid.accelerations[:] += self.a


def displacement_by_id(sim, x0_by_id):
    water = sim.fluid()
    return water.positions[np.argsort(water.ids)] - x0_by_id


def expected_displacement(a, n, dt):
    """Constant a from rest for n steps of the semi-implicit Euler step (v += dt a; x += dt v):
    x = a dt^2 n (n + 1) / 2 = a t^2 / 2 + a t dt / 2, the analytic a t^2 / 2 plus the scheme's
    first-order term."""
    return np.asarray(a) * dt * dt * n * (n + 1) / 2


def test_python_force_moves_free_particles_by_a_t2_over_2(free):
    water = free.fluid("water")
    x0 = water.positions[np.argsort(water.ids)]
    a = (2.0, -1.0, 0.5)
    force = water.add_force(ConstantAcceleration(a))
    n, dt = 200, 1e-3
    free.step(n)
    t = free.time
    assert force.calls == n and t == pytest.approx(n * dt, rel=RTOL)
    d = displacement_by_id(free, x0)
    np.testing.assert_allclose(d, np.tile(expected_displacement(a, n, dt), (len(water), 1)), rtol=RTOL, atol=ATOL)
    # ... which is a t^2 / 2 up to the scheme's a t dt / 2.
    np.testing.assert_allclose(d[0], np.multiply(a, t * t / 2), atol=np.abs(a).max() * t * dt / 2 * 1.0001)


def test_a_callable_is_a_force_and_sees_the_step(free):
    seen = {}

    def probe(ctx, fluid):
        seen.update(dt=ctx.dt, step=ctx.step, n=len(fluid), radius=ctx.particle_radius, ctx=ctx)
        seen["offsets"], seen["indices"] = ctx.fluid_neighbors()
        seen["w0"] = ctx.kernel_w(np.zeros(2))
        assert np.all(fluid.accelerations == 0)  # gravity 0, no scene forces before it

    free.fluid().add_force(probe)
    free.step(3)
    assert seen["step"] == 2 and seen["dt"] == pytest.approx(1e-3) and seen["n"] == 64
    assert len(seen["offsets"]) == 65 and len(seen["indices"]) == 0  # free particles: no neighbours
    h = 4 * seen["radius"]
    np.testing.assert_allclose(seen["w0"], 8 / (np.pi * h ** 3), rtol=RTOL)  # cubic spline W(0) = 8 / (pi h^3)
    with pytest.raises(RuntimeError, match="finished step"):
        seen["ctx"].dt  # the context expired with its step


def test_an_exception_in_a_force_reaches_the_caller(free):
    def broken(ctx, fluid):
        raise ValueError("wind sensor missing")

    free.fluid().add_force(broken)
    with pytest.raises(ValueError, match="wind sensor missing"):
        free.step()
    assert free.time == 0  # the aborted step did not count; the simulation is usable
    with pytest.raises(TypeError, match="consph.Force"):
        free.fluid().add_force(42)


def test_registered_force_usable_from_a_scene():
    registry = consph.PluginRegistry()
    registry.register_force("Push", ConstantAcceleration,
                            parameters=[consph.Param("a", "vector3", [0.0, 0.0, 0.0], "acceleration, m/s^2")])
    names = [f["name"] for f in consph.plugins(registry)["forces"]]
    assert "Push" in names and "StandardViscosity" in names
    push = next(f for f in consph.plugins(registry)["forces"] if f["name"] == "Push")
    assert push["parameters"][0]["name"] == "a" and push["doc"] == "Adds a constant acceleration to every particle."
    assert "Push" not in [f["name"] for f in consph.plugins()["forces"]]  # other registries unaffected

    scene = free_particles_scene()
    scene["fluids"][0]["forces"] = [{"type": "Push", "a": [0.0, 3.0, 0.0]}]
    sim = consph.Simulation.from_dict(scene, plugins=registry)
    x0 = sim.fluid().positions[np.argsort(sim.fluid().ids)]
    sim.step(50)
    np.testing.assert_allclose(displacement_by_id(sim, x0)[5], expected_displacement((0, 3, 0), 50, 1e-3), atol=ATOL)

    scene["fluids"][0]["forces"] = [{"type": "Push", "a": 3}]
    with pytest.raises(consph.SceneError, match=r"fluids\[0\]\.forces\[0\]\.a"):
        consph.Simulation.from_dict(scene, plugins=registry)
    with pytest.raises(ValueError, match="already registered"):
        registry.register_force("StandardViscosity", ConstantAcceleration)
