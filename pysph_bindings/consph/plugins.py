"""Forces written in Python and the plugin registry."""
from dataclasses import asdict, dataclass, field
from typing import Any, List, Optional

from ._consph import _PluginRegistry


class Force:
    """Base class of non-pressure forces written in Python.

    Override ``add_acceleration(self, ctx, fluid)``: add this force's acceleration (m/s^2) to
    ``fluid.accelerations`` (an (N, 3) zero-copy view that already holds gravity and the forces
    before this one). It runs inside every step where non-pressure forces run, before the pressure
    solve, with this step's neighbours and densities. ``ctx`` is a consph.StepContext (dt, time,
    neighbour lists, kernel), valid during the call only. Rows are in memory order; the Z-order
    sort permutes them between calls, so do not cache per-row data across steps (use fluid.ids).

    Attach an instance with ``sim.fluid().add_force(obj)``, or register the class under a name
    (``consph.register_force``) and name it in a scene's "forces" list.
    """

    def add_acceleration(self, ctx, fluid):
        raise NotImplementedError(f"{type(self).__name__} must implement add_acceleration(ctx, fluid)")


@dataclass
class Param:
    """A declared plugin parameter, validated like those of built-in plugins (type, range,
    choices; unknown keys in the scene are warned about). default=None makes it required."""

    name: str
    type: Any = "real"  # "real"|"int"|"bool"|"string"|"vector3", or float, int, bool, str
    default: Any = None
    doc: str = ""
    min: Optional[float] = None
    max: Optional[float] = None
    choices: Optional[List[str]] = field(default=None)

    def as_dict(self):
        d = asdict(self)
        d["type"] = {float: "real", int: "int", bool: "bool", str: "string"}.get(self.type, self.type)
        return d


class PluginRegistry(_PluginRegistry):
    """The built-in plugins plus forces registered from Python. A Simulation copies the registry
    it is built with (plugins=...; default: consph.default_plugins), so registering later never
    affects existing simulations and two simulations never share plugin state."""

    def register_force(self, name, factory=None, *, parameters=(), doc=""):
        """Registers `factory` (usually a Force subclass; called as factory(**parameters)) as the
        non-pressure force `name`, usable in a scene as {"type": name, ...}. `parameters`: Param
        objects, or a dict {name: default} whose types follow the defaults. Usable as a decorator:
        @registry.register_force("Wind", parameters=[Param("strength", float, 1.0)])."""
        if factory is None:
            return lambda f: self.register_force(name, f, parameters=parameters, doc=doc) or f
        if isinstance(parameters, dict):
            parameters = [Param(k, _infer_type(v), v) for k, v in parameters.items()]
        specs = [p.as_dict() if isinstance(p, Param) else dict(p) for p in parameters]
        self._add_force(name, doc or (factory.__doc__ or "").strip().split("\n")[0], specs, factory)
        return factory


def _infer_type(value):
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int"
    if isinstance(value, float):
        return "real"
    if isinstance(value, str):
        return "string"
    if isinstance(value, (list, tuple)) and len(value) == 3:
        return "vector3"
    raise TypeError(f"cannot infer a parameter type from {value!r}: use consph.Param")


# The process-wide registry Simulation.from_file/from_dict use when given no plugins=.
default_plugins = PluginRegistry()


def register_force(name, factory=None, *, parameters=(), doc=""):
    """default_plugins.register_force: see PluginRegistry.register_force."""
    return default_plugins.register_force(name, factory, parameters=parameters, doc=doc)


def plugins(registry=None):
    """Every plugin and its parameters: {"pressureSolvers": [...], "boundaryModels": [...],
    "forces": [...]} with {name, doc, parameters: [{name, type, default, range, doc}]}."""
    return (registry or default_plugins).to_dict()
