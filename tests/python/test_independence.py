"""Two simulations in one process are independent: no global state, in one thread or two."""
import threading

import numpy as np

import consph
from conftest import tank_scene


def state(sim):
    water = sim.fluid()
    order = np.argsort(water.ids)
    return water.positions[order].copy(), water.velocities[order].copy()


def test_two_simulations_do_not_interfere():
    reference = consph.Simulation.from_dict(tank_scene())
    reference.step(8)
    a = consph.Simulation.from_dict(tank_scene())
    b = consph.Simulation.from_dict(tank_scene(gravity=[0, 0, 0]))
    b.fluid().add_force(lambda ctx, fluid: fluid.accelerations.__iadd__([5.0, 0, 0]))
    for _ in range(8):  # interleaved
        a.step()
        b.step()
    for x, y in zip(state(a), state(reference)):
        assert np.array_equal(x, y)
    assert a.summary()["steps"] == 8 and b.summary()["steps"] == 8
    assert not np.array_equal(state(b)[0], state(a)[0])


def test_two_simulations_in_two_threads():
    reference = consph.Simulation.from_dict(tank_scene())
    reference.step(8)
    sims = [consph.Simulation.from_dict(tank_scene()) for _ in range(2)]
    threads = [threading.Thread(target=lambda s=s: (consph.set_num_threads(1), s.step(8))) for s in sims]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for s in sims:
        for x, y in zip(state(s), state(reference)):
            assert np.array_equal(x, y)
