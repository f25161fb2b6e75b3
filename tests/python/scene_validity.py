"""An independent reading of the scene format (docs/scene-format.md, docs/rigid-bodies.md,
docs/probes.md, the parameter declarations in Simulation/Scene.cpp and Probes.cpp, and the
plugins' tables from `consph --list-plugins --json`), used as the oracle of the scene-mutation
test (issue 16): a run that exits 0 must have been given a scene this module finds valid.

`problems(scene, plugins, base_dir)` returns every (path, why, kind) it finds, paths written as
consph writes them (`fluids[0].blocks[1].min`); kind "unknown" is an unknown key, which consph
warns about and ignores (allowed, if it warned), kind "invalid" anything else. Beyond types,
ranges and required keys, a scene must mean one thing:
- null is a value, not an absent key: an object or array key given null is a wrong type;
- names are printable text: a boundary's name is a bodies.csv field and appears in messages (no
  comma, quote or line break, as probe names), and unique among named boundaries (force probes
  and bodies.csv pick objects by name);
- a fluid's sources do not overlap: two blocks whose boxes share volume, or two identical
  emitters, particle files or mesh volumes, would put particles on top of each other;
- a force type appears once per fluid: a second instance shares the first's particle fields
  (ParticleFields::add returns the existing field), so its state would be overwritten;
- two boundaries are not the same object (equal but for the name): coincident walls or bodies;
- `output.directory` names a folder: a non-empty printable path.
What it does not model (exit 2 on a scene it finds valid is not a failure): the particle and
memory estimates, a mesh's contents beyond an OBJ's vertices (closed, loadable), probe placement.
"""
import json
import math
import os

LATTICES = ["cellCentred", "splishsplashRegular", "splishsplashMoreDense", "splishsplashDense"]
INF = math.inf


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def finite(v):
    try:
        return math.isfinite(float(v))
    except OverflowError:  # an int past the range of a double
        return False


def printable(s):
    """Printable text: no control characters (C0, DEL, C1) and no lone surrogates."""
    return all(not (ord(c) < 0x20 or 0x7f <= ord(c) < 0xa0 or 0xd800 <= ord(c) <= 0xdfff) for c in s)


def parse_range(text):
    """A plugin parameter's range as --list-plugins writes it: "[a, b]", "one of x y", ""."""
    if text.startswith("one of"):
        return -INF, INF, text.split()[2:]
    if not text:
        return -INF, INF, None
    lo, hi = text.strip("[]").split(", ")
    return float(lo), float(hi), None


def load_plugins(listing):
    """{category: {lower-case name: (name, {param: (type, default, min, max, choices)})}} from
    `consph --list-plugins --json`."""
    out = {}
    for category, entries in listing.items():
        out[category] = {}
        for e in entries:
            params = {}
            for p in e["parameters"]:
                lo, hi, choices = parse_range(p["range"])
                params[p["name"]] = (p["type"], p["default"], lo, hi, choices)
            out[category][e["name"].lower()] = (e["name"], params)
    return out


def obj_vertices(path):
    with open(path, errors="replace") as f:
        return [tuple(float(x) for x in line.split()[1:4]) for line in f if line.startswith("v ")]


def rotate(axis, angle, p):
    """Rodrigues' rotation of p about the unit vector along axis."""
    if angle == 0:
        return p
    n = math.hypot(*axis)  # without overflow: [1e308, 1e308, 0] is a direction
    k = [a / n for a in axis]
    c, s = math.cos(angle), math.sin(angle)
    kxp = [k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]]
    kp = sum(a * b for a, b in zip(k, p))
    return [p[i] * c + kxp[i] * s + k[i] * kp * (1 - c) for i in range(3)]


class Validator:
    def __init__(self, plugins, base_dir):
        self.plugins = plugins
        self.base_dir = base_dir
        self.found = []

    def bad(self, path, why):
        self.found.append((path, why, "invalid"))

    # --- values ---------------------------------------------------------------------------
    def number(self, v, path, lo=-INF, hi=INF, integer=False):
        if integer and (not isinstance(v, int) or isinstance(v, bool)):
            return self.bad(path, "expected an integer, got %r" % (v,))
        if not is_number(v):
            return self.bad(path, "expected a number, got %r" % (v,))
        if not finite(v) or not lo <= v <= hi:
            return self.bad(path, "%r is out of range [%g, %g]" % (v, lo, hi))
        return v

    def vector3(self, v, path, lo=-INF, hi=INF):
        if not isinstance(v, list) or len(v) != 3 or not all(is_number(c) and finite(c) and lo <= c <= hi for c in v):
            return self.bad(path, "expected [x, y, z] of finite numbers in [%g, %g], got %r" % (lo, hi, v))
        return [float(c) for c in v]

    def boolean(self, v, path):
        if not isinstance(v, bool):
            return self.bad(path, "expected true or false, got %r" % (v,))
        return v

    def string(self, v, path, choices=None):
        if not isinstance(v, str):
            return self.bad(path, "expected a string, got %r" % (v,))
        if choices is not None and v not in choices:
            return self.bad(path, "%r is not one of %s" % (v, ", ".join(choices)))
        return v

    def obj(self, v, path, keys, what="an object"):
        """v as a dict (None when it is not one); keys not in `keys` are unknown."""
        if not isinstance(v, dict):
            self.bad(path, "expected %s, got %r" % (what, v))
            return None
        for k in v:
            if k not in keys:
                self.found.append((path + "." + k if path else k, "unknown key", "unknown"))
        return v

    def array(self, v, path, what):
        if not isinstance(v, list):
            self.bad(path, "expected an array of %s, got %r" % (what, v))
            return []
        return v

    def fields(self, o, path, spec):
        """Checks o's keys against spec {key: (checker(value, path) or None, required)}; returns
        {key: checked value} for the given keys that passed."""
        out = {}
        for key, (check, required) in spec.items():
            if key not in o:
                if required:
                    self.bad(path + "." + key if path else key, "required key is missing")
                continue
            if check is not None:
                value = check(o[key], path + "." + key if path else key)
                if value is not None:
                    out[key] = value
        return out

    def box(self, v, path):
        b = self.obj(v, path, ("min", "max"))
        if b is None:
            return None
        got = self.fields(b, path, {"min": (self.vector3, True), "max": (self.vector3, True)})
        if "min" in got and "max" in got:
            if not all(hi > lo for lo, hi in zip(got["min"], got["max"])):
                return self.bad(path, "max must exceed min on every axis")
            return got["min"], got["max"]
        return None

    def file(self, v, path):
        if self.string(v, path) is None:
            return None
        full = os.path.normpath(os.path.join(self.base_dir, v))
        if not os.path.isfile(full):
            return self.bad(path, "no file %r" % v)
        return full

    # --- plugins --------------------------------------------------------------------------
    def plugin(self, v, path, category, default_type=None):
        if isinstance(v, str) and default_type is not None:
            v = {"type": v}
        o = self.obj(v, path, self._plugin_keys(v, category, default_type), "an object naming a plugin")
        if o is None:
            return None
        name = o.get("type", default_type)
        if name is None:
            return self.bad(path + ".type", "required string is missing")
        if not isinstance(name, str) or name.lower() not in self.plugins[category]:
            return self.bad(path + ".type", "unknown plugin %r" % (name,))
        canonical, params = self.plugins[category][name.lower()]
        values = {}
        for key, (kind, default, lo, hi, choices) in params.items():
            at = path + "." + key
            if key not in o:
                if default is None:
                    self.bad(at, "required %s is missing" % kind)
                values[key] = default
                continue
            value = o[key]
            if kind == "number":
                value = self.number(value, at, lo, hi)
            elif kind == "integer":
                value = self.number(value, at, lo, hi, integer=True)
            elif kind == "boolean":
                value = self.boolean(value, at)
            elif kind == "string":
                value = self.string(value, at, choices)
            else:
                value = self.vector3(value, at, lo, hi)
            values[key] = value
        # Cross-checks the plugins make (Plugins/Pressure/DFSPH.cpp, IISPH.cpp).
        lo_it, hi_it = values.get("minIterations"), values.get("maxIterations")
        if isinstance(lo_it, int) and isinstance(hi_it, int) and lo_it > hi_it:
            self.bad(path + ".minIterations", "must not exceed maxIterations")
        return canonical

    def _plugin_keys(self, v, category, default_type):
        if not isinstance(v, dict):
            return ()
        name = v.get("type", default_type)
        entry = self.plugins[category].get(name.lower()) if isinstance(name, str) else None
        return ("type",) + tuple(entry[1]) if entry else tuple(v)  # unknown plugin: its keys are not judged

    # --- the scene --------------------------------------------------------------------------
    def scene(self, s):
        top = self.obj(s, "", ("name", "description", "simulation", "fluids", "boundaries", "probes", "output"),
                       "a JSON object at the top level")
        if top is None:
            return
        self.fields(top, "", {"name": (self.string, False), "description": (self.string, False)})
        sim = self.simulation(top["simulation"]) if "simulation" in top else {}
        if "fluids" not in top:
            self.bad("fluids", "required array of fluids is missing")
        else:
            fluids = self.array(top["fluids"], "fluids", "fluids")
            if len(fluids) != 1:
                self.bad("fluids", "expected exactly one fluid (this version), got %d" % len(fluids))
            for i, f in enumerate(fluids):
                self.fluid(f, "fluids[%d]" % i, sim)
        names = []
        if "boundaries" in top:
            seen = []
            for i, b in enumerate(self.array(top["boundaries"], "boundaries", "boundary objects")):
                path = "boundaries[%d]" % i
                name = self.boundary(b, path)
                if name:
                    if name in names:
                        self.bad(path + ".name", "another boundary is already named %r" % name)
                    names.append(name)
                if isinstance(b, dict):
                    same = {k: v for k, v in b.items() if k != "name"}
                    if same in seen:
                        self.bad(path, "the same object as boundaries[%d] (equal but for the name)" % seen.index(same))
                    seen.append(same)
        if "probes" in top:
            self.probes(top["probes"], names)
        if "output" in top:
            self.output(top["output"])

    def simulation(self, v):
        o = self.obj(v, "simulation", ("particleRadius", "gravity", "cflFactor", "minTimeStep", "maxTimeStep",
                                       "initialTimeStep", "stopAt", "particleSpacing", "sortInterval", "maxParticles",
                                       "iterationCapSteps", "boundaryPressure", "pressureSolver", "boundaryModel",
                                       "domain"))
        if o is None:
            return {}
        n = self.number
        got = self.fields(o, "simulation", {
            "particleRadius": (lambda v, p: n(v, p, 1e-5, 10), False),
            "gravity": (self.vector3, False),
            "cflFactor": (lambda v, p: n(v, p, 1e-3, 10), False),
            "minTimeStep": (lambda v, p: n(v, p, 1e-8, 1), False),
            "maxTimeStep": (lambda v, p: n(v, p, 1e-8, 1), False),
            "initialTimeStep": (lambda v, p: n(v, p, 1e-8, 1), False),
            "stopAt": (lambda v, p: n(v, p, 0, 1e9), False),
            "particleSpacing": (lambda v, p: n(v, p, 1.2, 3), False),
            "sortInterval": (lambda v, p: n(v, p, 0, 1e9, integer=True), False),
            "maxParticles": (lambda v, p: n(v, p, 0, 1e15), False),
            "iterationCapSteps": (lambda v, p: n(v, p, 1, 1e9, integer=True), False),
            "boundaryPressure": (lambda v, p: self.string(v, p, ["auto", "consistent", "mirroring", "extrapolation"]), False),
            "pressureSolver": (lambda v, p: self.plugin(v, p, "pressureSolvers", "DFSPH"), False),
            "boundaryModel": (lambda v, p: self.plugin(v, p, "boundaryModels", "Akinci2012"), False),
            "domain": (self.box, False)})
        if got.get("minTimeStep", 1e-4) > got.get("maxTimeStep", 0.005):  # the defaults when not given
            self.bad("simulation.minTimeStep", "must not exceed simulation.maxTimeStep")
        return got

    def fluid(self, v, path, sim):
        o = self.obj(v, path, ("name", "density0", "forces", "blocks", "emitters", "removeOutside", "particleFiles",
                               "meshVolumes"))
        if o is None:
            return
        got = self.fields(o, path, {"name": (self.string, False), "density0": (lambda v, p: self.number(v, p, 1e-3, 1e6), False),
                                    "removeOutside": (self.box, False)})
        name = got.get("name", "fluid" if "name" not in o else None)
        if name is not None and (not name or not printable(name) or any(c in name for c in "/\\<>&\"'") or ".." in name
                                 or name.startswith(".")):
            self.bad(path + ".name", "%r cannot name output files" % name)
        types = []
        for i, f in enumerate(self.array(o.get("forces", []), path + ".forces", "force objects")):
            t = self.plugin(f, "%s.forces[%d]" % (path, i), "forces")
            if t in types:
                self.bad("%s.forces[%d]" % (path, i), "a second %s (forces[%d]): it would share the first's fields" % (t, types.index(t)))
            types.append(t)
        sources = 0
        boxes = []
        for i, b in enumerate(self.array(o.get("blocks", []), path + ".blocks", "blocks")):
            bpath = "%s.blocks[%d]" % (path, i)
            block = self.obj(b, bpath, ("min", "max", "velocity", "lattice"))
            if block is None:
                continue
            sources += 1
            got = self.fields(block, bpath, {"min": (self.vector3, True), "max": (self.vector3, True),
                                             "velocity": (self.vector3, False),
                                             "lattice": (lambda v, p: self.string(v, p, LATTICES), False)})
            if "min" in got and "max" in got:
                lo, hi = got["min"], got["max"]
                if not all(h > l for l, h in zip(lo, hi)):
                    self.bad(bpath, "max must exceed min on every axis")
                    continue
                for j, (lo2, hi2) in enumerate(boxes):
                    if all(min(hi[a], hi2[a]) > max(lo[a], lo2[a]) for a in range(3)):
                        self.bad(bpath, "overlaps blocks[%d]: particles would lie on top of each other" % j)
                boxes.append((lo, hi))
        for key, check in (("emitters", self.emitter), ("particleFiles", self.particle_file), ("meshVolumes", self.mesh_volume)):
            items = self.array(o.get(key, []), path + "." + key, key)
            for i, e in enumerate(items):
                ipath = "%s.%s[%d]" % (path, key, i)
                if check(e, ipath):
                    sources += 1
                if e in items[:i]:
                    self.bad(ipath, "the same as %s[%d]: particles would lie on top of each other" % (key, items.index(e)))
        if sources == 0:
            self.bad(path + ".blocks", "a fluid needs blocks, emitters, particleFiles or meshVolumes")

    def placement(self, o, path):
        got = self.fields(o, path, {"translation": (self.vector3, False), "rotationAxis": (self.vector3, False),
                                    "rotationAngle": (self.number, False), "scale": (self.vector3, False)})
        t, axis, angle, scale = (got.get("translation", [0.0] * 3), got.get("rotationAxis", [0.0, 0.0, 1.0]),
                                 got.get("rotationAngle", 0.0), got.get("scale", [1.0] * 3))
        if any(c == 0 for c in scale):
            self.bad(path + ".scale", "must not be 0 on any axis")
            return None
        if angle != 0 and all(c == 0 for c in axis):
            self.bad(path + ".rotationAxis", "must not be the zero vector when rotationAngle is not 0")
            return None
        if len(got) < sum(k in o for k in ("translation", "rotationAxis", "rotationAngle", "scale")):
            return None
        return lambda p: [a + b for a, b in zip(rotate(axis, angle, [p[i] * scale[i] for i in range(3)]), t)]

    def placed_finite(self, points, place, path):
        if place is None or not points:
            return
        moved = [place(p) for p in points]
        ok = all(math.isfinite(c) for p in moved for c in p)
        ok = ok and all(math.isfinite(max(p[a] for p in moved) - min(p[a] for p in moved)) for a in range(3))
        if not ok:
            self.bad(path, "the transformed object has coordinates beyond the range of a number")

    def emitter(self, v, path):
        o = self.obj(v, path, ("shape", "position", "direction", "speed", "width", "height", "radius", "start", "end"))
        if o is None:
            return False
        n = self.number
        got = self.fields(o, path, {
            "shape": (lambda v, p: self.string(v, p, ["rectangle", "circle"]), False),
            "position": (self.vector3, True), "direction": (self.vector3, True),
            "speed": (lambda v, p: n(v, p, 1e-6, 1e4), True),
            "width": (lambda v, p: n(v, p, 0, 1e6), False), "height": (lambda v, p: n(v, p, 0, 1e6), False),
            "radius": (lambda v, p: n(v, p, 0, 1e6), False),
            "start": (lambda v, p: n(v, p, 0, 1e9), False), "end": (lambda v, p: n(v, p, 0, 1e9), False)})
        if "direction" in got and all(c == 0 for c in got["direction"]):
            self.bad(path + ".direction", "must not be the zero vector")
        circle = got.get("shape", "rectangle" if "shape" not in o else None) == "circle"
        if circle and got.get("radius", 0) <= 0:
            self.bad(path + ".radius", "a circular nozzle needs a radius > 0")
        if not circle and (got.get("width", 0) <= 0 or got.get("height", 0) <= 0):
            self.bad(path, "a rectangular nozzle needs width and height > 0")
        if got.get("end", 1e9) <= got.get("start", 0):
            self.bad(path + ".end", "must exceed start")
        return True

    def particle_file(self, v, path):
        o = self.obj(v, path, ("file", "translation", "rotationAxis", "rotationAngle", "scale", "velocity"))
        if o is None:
            return False
        self.fields(o, path, {"file": (self.file, True), "velocity": (self.vector3, False)})
        self.placement(o, path)
        return True

    def mesh_volume(self, v, path):
        o = self.obj(v, path, ("mesh", "lattice", "translation", "rotationAxis", "rotationAngle", "scale", "velocity"))
        if o is None:
            return False
        got = self.fields(o, path, {"mesh": (self.file, True), "velocity": (self.vector3, False),
                                    "lattice": (lambda v, p: self.string(v, p, ["cellCentred", "splishsplashRegular"]), False)})
        place = self.placement(o, path)
        if "mesh" in got and got["mesh"].endswith(".obj"):
            self.placed_finite(obj_vertices(got["mesh"]), place, path)
        return True

    def name(self, v, path):
        if self.string(v, path) is None:
            return None
        if not printable(v) or any(c in v for c in ",\"\n\r"):
            return self.bad(path, "%r: a name is printable text without a comma or quote (a CSV field, a message)" % v)
        return v

    def boundary(self, v, path):
        """Checks one boundary object; returns its name."""
        o = self.obj(v, path, ("name", "box", "mesh", "translation", "rotationAxis", "rotationAngle", "scale", "inverted",
                               "dynamic", "density", "velocity", "angularVelocity", "animated", "hinge", "friction"))
        if o is None:
            return None
        got = self.fields(o, path, {"name": (self.name, False), "box": (self.box, False), "mesh": (self.file, False),
                                    "inverted": (self.boolean, False), "dynamic": (self.boolean, False),
                                    "friction": (lambda v, p: self.number(v, p, 0, 10), False)})
        if ("box" in o) == ("mesh" in o):
            self.bad(path, "give exactly one of box or mesh")
        dynamic, animated, inverted = got.get("dynamic", False), "animated" in o, got.get("inverted", False)
        if dynamic and animated:
            self.bad(path, "either dynamic or animated, not both")
        if (dynamic or animated) and inverted:
            self.bad(path + ".inverted", "a moving object cannot be a container")
        if dynamic:
            self.fields(o, path, {"density": (lambda v, p: self.number(v, p, 1e-6, 1e9), True),
                                  "velocity": (self.vector3, False), "angularVelocity": (self.vector3, False)})
        else:
            for key in ("density", "velocity", "angularVelocity", "hinge"):
                if key in o:
                    self.bad(path + "." + key, "only a dynamic object takes this key")
        if animated:
            a = self.obj(o["animated"], path + ".animated", ("velocity", "angularVelocity"))
            if a is not None:
                self.fields(a, path + ".animated", {"velocity": (self.vector3, False), "angularVelocity": (self.vector3, False)})
        if dynamic and "hinge" in o:
            self.hinge(o["hinge"], path + ".hinge")
        place = self.placement(o, path)
        if "box" in got:
            lo, hi = got["box"]
            self.placed_finite([[(lo, hi)[(k >> a) & 1][a] for a in range(3)] for k in range(8)], place, path)
        elif "mesh" in got and got["mesh"].endswith(".obj"):
            self.placed_finite(obj_vertices(got["mesh"]), place, path)
        return got.get("name", "")

    def hinge(self, v, path):
        h = self.obj(v, path, ("point", "axis", "motor"))
        if h is None:
            return
        got = self.fields(h, path, {"point": (self.vector3, True), "axis": (self.vector3, True)})
        if "axis" in got and all(c == 0 for c in got["axis"]):
            self.bad(path + ".axis", "must not be the zero vector")
        if "motor" in h:
            m = self.obj(h["motor"], path + ".motor", ("targetVelocity", "maxTorque"))
            if m is not None:
                self.fields(m, path + ".motor", {"targetVelocity": (self.number, True),
                                                 "maxTorque": (lambda v, p: self.number(v, p, 0, 1e12), True)})

    def probes(self, v, boundary_names):
        names = []
        for i, p in enumerate(self.array(v, "probes", "probe objects")):
            path = "probes[%d]" % i
            kind = p.get("kind") if isinstance(p, dict) else None
            keys = {"pressure": ("position", "radius"), "level": ("position",), "force": ("boundary", "point", "region")}
            o = self.obj(p, path, ("kind", "name") + keys.get(kind, ()))
            if o is None:
                continue
            if kind not in keys:
                self.bad(path + ".kind", "expected pressure, level or force, got %r" % (kind,))
                continue
            got = self.fields(o, path, {"name": (self.string, True)})
            name = got.get("name")
            if name is not None:
                if not name or not printable(name) or any(c in name for c in ",\"\n\r"):
                    self.bad(path + ".name", "%r cannot be a CSV column" % name)
                elif name in names:
                    self.bad(path + ".name", "another probe is named %r" % name)
                names.append(name)
            if kind == "force":
                got = self.fields(o, path, {"boundary": (self.string, True), "point": (self.vector3, False),
                                            "region": (self.box, False)})
                if "boundary" in got and got["boundary"] not in boundary_names:
                    self.bad(path + ".boundary", "no boundary is named %r" % got["boundary"])
            else:
                self.fields(o, path, {"position": (self.vector3, True),
                                      "radius": (lambda v, p: self.number(v, p, 0, 1e6), False)})

    def output(self, v):
        o = self.obj(v, "output", ("enabled", "directory", "fps", "probeFps", "overwrite", "format", "attributes",
                                   "precision", "bodies", "checkpointInterval"))
        if o is None:
            return
        n = self.number
        got = self.fields(o, "output", {
            "enabled": (self.boolean, False), "directory": (self.string, False),
            "fps": (lambda v, p: n(v, p, 1e-3, 1e6), False), "probeFps": (lambda v, p: n(v, p, 0, 1e9), False),
            "overwrite": (self.boolean, False),
            "format": (lambda v, p: self.string(v, p, ["vtu", "bgeo", "ply"]), False),
            "precision": (lambda v, p: self.string(v, p, ["float", "double"]), False),
            "bodies": (lambda v, p: self.string(v, p, ["auto", "meshes", "transforms"]), False),
            "checkpointInterval": (lambda v, p: n(v, p, 0, 1e9), False),
            "attributes": (lambda v, p: [self.string(a, "%s[%d]" % (p, i)) for i, a in enumerate(self.array(v, p, "field names"))], False)})
        if "directory" in got and (not got["directory"] or not printable(got["directory"])):
            self.bad("output.directory", "%r does not name a folder" % got["directory"])
        if got.get("format") == "bgeo" and got.get("precision") == "double":
            self.bad("output.precision", "double is not available with bgeo")
        if got.get("format") == "bgeo" and got.get("bodies") == "meshes":
            self.bad("output.bodies", "meshes are not available with bgeo")


def problems(scene, plugins, base_dir):
    v = Validator(plugins, base_dir)
    v.scene(scene)
    return v.found


class DuplicateKey(ValueError):
    pass


def _pairs(pairs):
    keys = [k for k, _ in pairs]
    if len(set(keys)) != len(keys):
        raise DuplicateKey("duplicate key %r" % next(k for k in keys if keys.count(k) > 1))
    return dict(pairs)


def _no_constant(name):
    raise ValueError("%s is not JSON" % name)


def parse(text):
    """The scene as strict JSON (RFC 8259): no NaN/Infinity, no duplicate keys, numbers within a
    double. Raises ValueError otherwise."""
    def number(s):
        x = float(s)
        if not math.isfinite(x):
            raise ValueError("number %s is out of the range of a double" % s)
        return x
    return json.loads(text, object_pairs_hook=_pairs, parse_constant=_no_constant, parse_float=number)


def apply_override(scene, dotted, value):
    """consph's --set (Simulation/Scene.cpp applyOverride): a null on the way becomes an object,
    a missing key is added. Returns the scene; raises ValueError where consph refuses."""
    holder = [scene]
    parent, key = holder, 0
    for k in dotted.split("."):
        node = parent[key]
        if isinstance(node, list):
            if not k.isdigit() or int(k) >= len(node):
                raise ValueError("--set %s: no item %s" % (dotted, k))
            parent, key = node, int(k)
            continue
        if node is None:
            node = parent[key] = {}
        if not isinstance(node, dict):
            raise ValueError("--set %s: inside a non-object value" % dotted)
        node.setdefault(k, None)
        parent, key = node, k
    parent[key] = value
    return holder[0]
