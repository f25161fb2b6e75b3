"""Rigid bodies from Python: sim.bodies lists the moving bodies' state (the columns of bodies.csv)."""
import consph
import pytest

from conftest import FLOAT_EPS, roundoff, tank_scene


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
    # Float: the vertices at y = 2.0-2.1 are rounded by eps |y|, 21 eps of the 0.1 m sides, so the
    # volume is off by up to 3 x 21 eps (measured 7.5 eps), the centre by eps |y| per vertex and
    # once more when stored (measured 0.2 eps |y|).
    assert body["mass"] == pytest.approx(500 * 0.1 ** 3, rel=roundoff(1e-9, 64 * FLOAT_EPS))
    assert body["position"] == pytest.approx((0.25, 2.05, 0.15), abs=roundoff(1e-9, 2 * FLOAT_EPS * 2.1))
    sim.step(20)
    (body,) = sim.bodies
    # Float: v and t are each a sum of 20 increments rounded to eps of the running sum: up to 2 x 20
    # eps apart (measured 2.7 eps).
    assert body["velocity"][1] == pytest.approx(-9.81 * sim.time, rel=roundoff(1e-9, 2 * 20 * FLOAT_EPS))
    assert body["velocity"][0] == pytest.approx(0, abs=1e-12)
    assert body["fluid_force"] == pytest.approx((0, 0, 0), abs=1e-12)
    assert body["orientation"] == pytest.approx((1, 0, 0, 0), abs=1e-12)
