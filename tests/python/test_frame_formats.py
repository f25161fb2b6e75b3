"""Frames for Houdini (.bgeo) and Blender (.ply), read back with readers written here from the
formats' documentation (not with consph's writer): positions and attributes round-trip, and
output.format / attributes / precision / bodies do what docs/scene-format.md says."""
import gzip
import struct

import numpy as np
import pytest

import consph
from conftest import tank_scene
from vtu import read_vtu

REAL = np.float64 if consph.precision == "double" else np.float32


def read_bgeo(path):
    """Houdini's classic .bgeo (version 5, big-endian; partio's layout): returns
    ({name: array}, trailer) with 'P' (N, 3) and 'Pw' (N,) from the points' x y z w."""
    raw = open(path, "rb").read()
    if raw[:2] == b"\x1f\x8b":  # gzip magic
        raw = gzip.decompress(raw)
    assert raw[:5] == b"BgeoV", raw[:5]
    version, points, prims, point_groups, prim_groups, point_attrs, vertex_attrs, prim_attrs, detail_attrs = \
        struct.unpack(">9i", raw[5:41])
    assert version == 5 and prims == point_groups == prim_groups == vertex_attrs == prim_attrs == detail_attrs == 0
    at = 41
    fields = [("P", ">f4", (3,)), ("Pw", ">f4")]
    for _ in range(point_attrs):
        (length,) = struct.unpack(">H", raw[at:at + 2])
        name = raw[at + 2:at + 2 + length].decode()
        at += 2 + length
        size, kind = struct.unpack(">Hi", raw[at:at + 6])
        at += 6 + 4 * size  # one 4-byte default per component
        assert kind in (0, 1, 5), kind  # float, int, vector
        fields.append((name, ">i4" if kind == 1 else ">f4", (size,) if size > 1 else ()))
    dtype = np.dtype(fields)
    table = np.frombuffer(raw, dtype, count=points, offset=at)
    trailer = raw[at + points * dtype.itemsize:]
    return {name: table[name] for name in dtype.names}, trailer


_PLY_TYPES = {"float": "<f4", "double": "<f8", "uint": "<u4", "int": "<i4", "uchar": "u1"}


def read_ply(path):
    """Binary little-endian PLY: returns ({property: array}, property types, faces (M, 3) or None)."""
    raw = open(path, "rb").read()
    end = raw.index(b"end_header\n") + len(b"end_header\n")
    lines = raw[:end].decode().splitlines()
    assert lines[0] == "ply" and lines[1] == "format binary_little_endian 1.0"
    elements = []
    for line in lines[2:]:
        words = line.split()
        if words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property":
            elements[-1][2].append(words[1:])
    name, count, props = elements[0]
    assert name == "vertex"
    dtype = np.dtype([(p[1], _PLY_TYPES[p[0]]) for p in props])
    vertices = np.frombuffer(raw, dtype, count=count, offset=end)
    faces = None
    if len(elements) > 1:
        fname, fcount, fprops = elements[1]
        assert fname == "face" and fprops == [["list", "uchar", "int", "vertex_indices"]]
        table = np.frombuffer(raw, np.dtype([("n", "u1"), ("v", "<i4", (3,))]), count=fcount, offset=end + count * dtype.itemsize)
        assert (table["n"] == 3).all()
        faces = table["v"]
        assert end + count * dtype.itemsize + fcount * 13 == len(raw)
    else:
        assert end + count * dtype.itemsize == len(raw)
    return {p[1]: vertices[p[1]] for p in props}, {p[1]: p[0] for p in props}, faces


@pytest.fixture
def moving_tank():
    sim = consph.Simulation.from_dict(tank_scene(), output=False)
    sim.step(3)  # moving particles, re-sorted (sortInterval 5: not yet), pressures set
    return sim


@pytest.mark.parametrize("name", ["frame.bgeo.gz", "frame.bgeo"])
def test_bgeo_frame_reads_back(moving_tank, tmp_path, name):
    water = moving_tank.fluid()
    moving_tank.export_frame(tmp_path / name)
    if name.endswith(".gz"):
        assert (tmp_path / name).read_bytes()[:2] == b"\x1f\x8b"
    points, trailer = read_bgeo(str(tmp_path / name))
    assert trailer == b"\x00\xff"  # end of the classic format
    np.testing.assert_array_equal(points["P"], water.positions.astype(np.float32))
    np.testing.assert_array_equal(points["Pw"], 1.0)
    np.testing.assert_array_equal(points["v"], water.velocities.astype(np.float32))  # Houdini's name
    np.testing.assert_array_equal(points["id"], water.ids.astype(np.int32))
    np.testing.assert_array_equal(points["density"], water.field("density").astype(np.float32))
    assert np.abs(points["v"]).max() > 0


def test_ply_frame_reads_back(moving_tank, tmp_path):
    water = moving_tank.fluid()
    moving_tank.export_frame(tmp_path / "frame.ply")
    values, types, faces = read_ply(str(tmp_path / "frame.ply"))
    assert faces is None and types["x"] == consph.precision and types["id"] == "uint"
    np.testing.assert_array_equal(np.stack([values["x"], values["y"], values["z"]], axis=1), water.positions)
    np.testing.assert_array_equal(np.stack([values[f"velocity_{c}"] for c in "xyz"], axis=1), water.velocities)
    np.testing.assert_array_equal(values["id"], water.ids)


def body_tank(tmp_path, **output):
    scene = tank_scene()
    scene["boundaries"].append({"name": "crate", "box": {"min": [0.2, 0.7, 0.1], "max": [0.3, 0.8, 0.2]},
                                "dynamic": True, "density": 500})
    scene["output"] = dict({"directory": str(tmp_path / "out"), "fps": 100}, **output)
    return consph.Simulation.from_dict(scene)


def test_ply_series_with_chosen_attributes_float32_and_body_meshes(tmp_path):
    sim = body_tank(tmp_path, format="ply", attributes=["velocity", "mass", "id"])
    water = sim.fluid()
    mass = water.field("mass").copy()
    sim.step(1)  # frame 0: the initial state, written before the first step
    values, types, _ = read_ply(str(tmp_path / "out" / "water_00000.ply"))
    assert list(types) == ["x", "y", "z", "velocity_x", "velocity_y", "velocity_z", "mass", "id"]
    assert types["x"] == "float" and types["mass"] == "float" and types["id"] == "uint"  # float32 by default
    order = np.argsort(values["id"])
    np.testing.assert_array_equal(values["mass"][order], mass.astype(np.float32))
    np.testing.assert_array_equal(values["velocity_y"], 0.0)
    # The body's surface as a mesh: a box, 8 corners (or more), 12 triangles.
    vertices, _, faces = read_ply(str(tmp_path / "out" / "bodies_00000.ply"))
    assert faces.shape == (12, 3) and faces.max() < len(vertices["x"])
    np.testing.assert_allclose([vertices["x"].min(), vertices["y"].max()], [0.2, 0.8], atol=1e-6)


def test_bgeo_series_has_body_transforms_for_copy_to_points(tmp_path):
    sim = body_tank(tmp_path, format="bgeo")
    sim.run(until=0.05)
    frames = sorted((tmp_path / "out").glob("bodies_*.bgeo.gz"))
    assert len(frames) >= 5 and sorted((tmp_path / "out").glob("water_*.bgeo.gz"))
    first, _ = read_bgeo(str(frames[0]))
    np.testing.assert_allclose(first["P"], [[0.25, 0.75, 0.15]], atol=1e-6)  # centre of mass
    np.testing.assert_allclose(first["pivot"], first["P"])
    np.testing.assert_array_equal(first["orient"], [[0, 0, 0, 1]])  # x y z w: no rotation yet
    last, _ = read_bgeo(str(frames[-1]))
    (body,) = sim.bodies
    if abs(sim.time - 0.01 * (len(frames) - 1)) < sim.dt:  # the last frame is the state now
        np.testing.assert_array_equal(last["P"][0], np.float32(body["position"]))
    assert last["v"][0][1] < 0  # falling


def test_vtu_frames_are_float32_unless_double_is_asked(tmp_path):
    sim = body_tank(tmp_path)
    sim.step(1)
    frame = read_vtu(str(tmp_path / "out" / "water_00000.vtu"))
    assert frame["position"].dtype == np.float32 and frame["velocity"].dtype == np.float32
    assert frame["id"].dtype == np.uint32
    sim = body_tank(tmp_path / "double", precision="double")
    sim.step(1)
    frame = read_vtu(str(tmp_path / "double" / "out" / "water_00000.vtu"))
    assert frame["position"].dtype == REAL and frame["density"].dtype == REAL


@pytest.mark.parametrize("output, message", [
    ({"format": "obj"}, r"output\.format: 'obj' is not one of vtu bgeo ply"),
    ({"attributes": ["velocity", "temperature"]}, r"output\.attributes\[1\]: unknown particle field 'temperature'; valid are: .*density"),
    ({"attributes": "velocity"}, r"output\.attributes: expected an array"),
    ({"attributes": [3]}, r"output\.attributes\[0\]: expected a particle field name"),
    ({"precision": "half"}, r"output\.precision: 'half' is not one of float double"),
    ({"format": "bgeo", "precision": "double"}, r"output\.precision: \"double\" is not available with \"format\": \"bgeo\""),
    ({"format": "bgeo", "bodies": "meshes"}, r"output\.bodies: \"meshes\" is not available"),
])
def test_bad_output_settings_name_their_json_path(output, message):
    scene = tank_scene()
    scene["output"] = dict({"enabled": False}, **output)
    with pytest.raises(consph.SceneError, match=message):
        consph.Simulation.from_dict(scene)


def test_export_frame_writes_vtu_for_other_names(moving_tank, tmp_path):
    moving_tank.export_frame(tmp_path / "frame.data")  # as before BGEO and PLY: any other name is a .vtu
    np.testing.assert_array_equal(read_vtu(str(tmp_path / "frame.data"))["position"], moving_tank.fluid().positions)
