"""Particle arrays are zero-copy views whose base keeps the simulation alive."""
import gc

import numpy as np
import pytest

import consph
from conftest import ATOL, tank_scene


def test_arrays_are_views_of_the_cpp_fields(tank):
    water = tank.fluid("water")
    x = water.positions
    assert x.shape == (len(water), 3) and x.dtype == (np.float64 if consph.precision == "double" else np.float32)
    assert isinstance(x.base, consph.FieldViewOwner) and x.base.field == "position"
    # Two accesses see the same memory: no copy.
    assert np.shares_memory(x, water.positions)
    x[0] = (0.3, 0.7, 0.2)
    assert tuple(water.positions[0]) == pytest.approx((0.3, 0.7, 0.2))
    for name in ("velocities", "accelerations", "densities", "pressures", "masses", "ids"):
        a = getattr(water, name)
        assert a.shape[0] == len(water) and a.base.simulation is tank


def test_writing_through_a_view_changes_the_motion(free):
    # Free particles, no forces: x(t) = x0 + v t exactly as set through the view.
    # Rows are re-sorted (Z-order) at the first step: compare particles by id.
    water = free.fluid()
    x0 = water.positions[np.argsort(water.ids)]
    water.velocities[:] = (0.5, 0.0, -0.25)
    free.step(20)
    t = free.time
    assert t == pytest.approx(20 * 1e-3)
    x = water.positions[np.argsort(water.ids)]
    np.testing.assert_allclose(x - x0, np.tile([0.5 * t, 0.0, -0.25 * t], (len(water), 1)), atol=ATOL)


def test_ids_are_read_only_and_follow_resorting():
    sim = consph.Simulation.from_dict(tank_scene(sortInterval=1))
    water = sim.fluid()
    with pytest.raises(ValueError):
        water.ids[0] = 5
    before = {int(i): tuple(x) for i, x in zip(water.ids, water.positions)}
    sim.step(1)  # the sort happens at the start of the step, then the particles move a little
    ids = water.ids.copy()
    assert sorted(ids) == list(range(len(water)))
    moved = [np.linalg.norm(np.subtract(x, before[int(i)])) for i, x in zip(ids, water.positions)]
    assert max(moved) < 0.01  # each id is still its own particle


def test_any_registered_field_by_name(tank):
    water = tank.fluid()
    fields = water.fields()
    assert {"position", "velocity", "acceleration", "density", "pressure", "mass", "id"} <= set(fields)
    assert any(name.startswith("dfsph") for name in fields)  # registered by the DFSPH plugin
    for name, info in fields.items():
        a = water[name]
        assert a.shape == ((len(water), 3) if info["type"] == "vector3" else (len(water),))
        assert a.flags.writeable == info["writable"]
    with pytest.raises(KeyError, match="no particle field 'nope'; fields: position"):
        water.field("nope")


def test_an_array_outlives_its_simulation(tank):
    x = tank.fluid().positions
    expected = x.copy()
    del tank
    gc.collect()
    np.testing.assert_array_equal(x, expected)  # the base still owns the simulation
    sim = x.base.simulation
    sim.step(2)
    assert sim.step_count == 2 and not np.array_equal(x, expected)


def test_views_made_for_another_particle_count_are_reported(tank):
    water = tank.fluid()
    n = len(water)
    x = water.positions
    with pytest.warns(consph.StaleViewWarning):
        water._resize(n - 1)  # the storage stays where it is: old views are only stale
    assert not consph.is_current(x) and not consph.is_current(x[:, 0])
    y = water.velocities
    assert consph.is_current(y) and len(y) == n - 1
    with pytest.raises(consph.StaleViewError, match="reallocated"):
        water._resize(100 * n)  # the storage moves: y would dangle
    assert not consph.is_current(y)
    assert len(water.velocities) == 100 * n and consph.is_current(water.velocities)


def test_pressures_are_the_kernel_average_of_the_solver_pressures_after_every_step():
    # fluid.pressures (the frames' "pressure") is sum_j V_j p_j W_ij / sum_j V_j W_ij of the
    # solver's p_j (fluid.solver_pressures), j = i included, computed after the last step.
    sim = consph.Simulation.from_dict(tank_scene())
    water = sim.fluid()
    h = 4 * 0.025
    for steps in (5, 1):
        sim.step(steps)
        x, p, m, rho = water.positions, water.solver_pressures, water.masses, water.densities
        q = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2) / h
        w = np.where(q <= 0.5, 6 * (q ** 3 - q ** 2) + 1, np.where(q <= 1, 2 * (1 - q) ** 3, 0.0)) * (m / rho)[None, :]
        expected = w @ p / w.sum(1)
        assert np.max(np.abs(p)) > 0  # the block presses on its floor: not a vacuous comparison
        np.testing.assert_allclose(water.pressures, expected, rtol=1e-9 if consph.precision == "double" else 1e-4,
                                   atol=1e-9 * np.max(np.abs(p)))
        assert not np.allclose(water.pressures, p)  # the field is not the per-particle values
        assert "solverPressure" in water.fields() and "pressure" in water.fields()
