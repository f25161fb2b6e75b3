"""Rigid bodies from Python: sim.bodies lists the moving bodies' state (the columns of bodies.csv)."""
import consph
import pytest

from conftest import tank_scene


def test_scene_without_bodies_has_none():
    sim = consph.Simulation.from_dict(tank_scene(), output=False)
    assert sim.bodies == []


def test_falling_body_state_follows_gravity():
    # A box far above the fluid: only gravity acts, and the semi-implicit velocity update adds
    # g dt every step, so v = -g t to round-off whatever the time steps were.
    scene = tank_scene()
    scene["boundaries"].append({"name": "crate", "box": {"min": [0.2, 2.0, 0.1], "max": [0.3, 2.1, 0.2]},
                                "dynamic": True, "density": 500})
    sim = consph.Simulation.from_dict(scene, output=False)
    (body,) = sim.bodies
    assert body["name"] == "crate" and body["motion"] == "dynamic"
    assert body["mass"] == pytest.approx(500 * 0.1 ** 3, rel=1e-9)
    assert body["position"] == pytest.approx((0.25, 2.05, 0.15), abs=1e-9)
    sim.step(20)
    (body,) = sim.bodies
    assert body["velocity"][1] == pytest.approx(-9.81 * sim.time, rel=1e-9)
    assert body["velocity"][0] == pytest.approx(0, abs=1e-12)
    assert body["fluid_force"] == pytest.approx((0, 0, 0), abs=1e-12)
    assert body["orientation"] == pytest.approx((1, 0, 0, 0), abs=1e-12)
