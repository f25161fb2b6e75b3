#!/usr/bin/python3
"""Writes WaterWheel.obj: an octagonal hub with eight radial paddles, one closed box per paddle
sitting on a hub face (no overlaps, so the divergence theorem gives the right mass properties).
Centred at the origin, axle along z. Usage: make_water_wheel.py [OUT.obj]"""
import math
import sys

HUB_APOTHEM = 0.08   # m, distance from the axle to a hub face
RADIUS = 0.30        # m, outer edge of the paddles
PADDLE = 0.03        # m, paddle thickness
DEPTH = 0.20         # m, extent along the axle (z from -DEPTH/2 to DEPTH/2)
N = 8

vertices, faces = [], []


def box(corners):
    """corners: the 8 vertices of a hexahedron, ordered like makeBoxMesh (bit 0 = +u, bit 1 = +v,
    bit 2 = +z); adds its 12 outward triangles."""
    base = len(vertices)
    vertices.extend(corners)
    quads = [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]
    for q in quads:
        faces.append((base + q[0], base + q[1], base + q[2]))
        faces.append((base + q[0], base + q[2], base + q[3]))


def prism(polygon, z0, z1):
    """A closed prism over a counter-clockwise polygon."""
    n = len(polygon)
    base = len(vertices)
    vertices.extend((x, y, z0) for x, y in polygon)
    vertices.extend((x, y, z1) for x, y in polygon)
    for i in range(1, n - 1):
        faces.append((base, base + i + 1, base + i))              # bottom, facing -z
        faces.append((base + n, base + n + i, base + n + i + 1))  # top, facing +z
    for i in range(n):
        j = (i + 1) % n
        faces.append((base + i, base + j, base + n + j))
        faces.append((base + i, base + n + j, base + n + i))


corner = HUB_APOTHEM / math.cos(math.pi / N)
prism([(corner * math.cos(2 * math.pi * (k + 0.5) / N), corner * math.sin(2 * math.pi * (k + 0.5) / N)) for k in range(N)],
      -DEPTH / 2, DEPTH / 2)
for k in range(N):
    a = 2 * math.pi * k / N
    radial, tangent = (math.cos(a), math.sin(a)), (-math.sin(a), math.cos(a))
    corners = []
    for i in range(8):
        r = RADIUS if i & 1 else HUB_APOTHEM
        t = PADDLE / 2 if i & 2 else -PADDLE / 2
        z = DEPTH / 2 if i & 4 else -DEPTH / 2
        corners.append((r * radial[0] + t * tangent[0], r * radial[1] + t * tangent[1], z))
    box(corners)

out = sys.argv[1] if len(sys.argv) > 1 else "WaterWheel.obj"
with open(out, "w") as f:
    f.write("# water wheel: octagonal hub (apothem %g m) with %d paddles to radius %g m, depth %g m\n"
            % (HUB_APOTHEM, N, RADIUS, DEPTH))
    for v in vertices:
        f.write("v %.6f %.6f %.6f\n" % v)
    for t in faces:
        f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
