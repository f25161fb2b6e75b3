"""consph: SPH fluid simulation with consistent rigid-fluid coupling.

Quick start::

    import consph
    sim = consph.Simulation.from_file("data/scenes/DamBreak.json", output=False,
                                      overrides={"simulation.pressureSolver.maxError": 0.01})
    water = sim.fluid("water")
    x = water.positions          # (N, 3) zero-copy NumPy view of the C++ array
    sim.step(100)                # C++ with the GIL released
    sim.run(until=1.0, progress=True)
    print(sim.summary()["averageDensityErrorPercent"])

See docs/python.md for views, forces written in Python and the plugin registry.
"""
from ._consph import (  # noqa: F401
    __version__,
    precision,
    Simulation,
    Fluid,
    StepContext,
    FieldViewOwner,
    SceneError,
    SimulationError,
    OutputError,
    StaleViewError,
    ConsphWarning,
    StaleViewWarning,
    set_num_threads,
    get_num_threads,
)
from .plugins import Force, Param, PluginRegistry, default_plugins, plugins, register_force  # noqa: F401

# Tracebacks and reprs say consph.SimulationError, not consph._consph.SimulationError.
for _cls in (Simulation, Fluid, StepContext, FieldViewOwner, SceneError, SimulationError, OutputError, StaleViewError,
             ConsphWarning, StaleViewWarning):
    _cls.__module__ = __name__
del _cls


def is_current(array):
    """True if `array` (a particle view or a slice of one) still matches the particle storage and
    count it was made for. Views become stale when the particle count changes (emitters)."""
    base = array
    while base is not None and not isinstance(base, FieldViewOwner):
        base = getattr(base, "base", None)
    if base is None:
        raise TypeError("not a view of consph particle data")
    return base.is_current()
