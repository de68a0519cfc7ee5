#!/usr/bin/python3
"""Generate the bundled test objects for HFTS fingertip grasp planning.

Builds eight closed triangle meshes procedurally (a mug with a handle, a
bowl, a bottle, a torus, an L bracket, a box, a cylinder and a smooth
irregular blob), checks each one, then writes them into ``objects/meshes/``
in the formats the assimp based loader must handle: binary STL, ASCII STL,
binary little-endian PLY and Wavefront OBJ.

Conventions: metres; z up; every object stands on the z = 0 plane and is
roughly centred on the z axis. Every mesh component is closed, edge-manifold
and wound so that right-hand-rule normals point out of the solid. The mug is
deliberately two components (body and handle) whose volumes overlap where
the handle ends are sunk into the wall.

Before anything is written each mesh must pass: finite coordinates, no
degenerate triangles, no unreferenced or duplicated vertices, every directed
edge used once and its reverse once, and a positive signed volume per
component. A failure prints the reason and exits with status 1, leaving the
existing files untouched. Output is byte-deterministic and each file is
replaced atomically, so rerunning is always safe:

    /usr/bin/python3 objects/generate_objects.py [--out DIR]

Needs only the standard library and numpy.
"""

import argparse
import math
import os
import struct
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

MIN_TRIANGLE_AREA = 1e-10  # m^2 (0.1 mm x 2 um); far below any real facet
DUPLICATE_GRID = 1e-8  # m; vertices closer than this count as duplicates


class MeshError(ValueError):
    """A generated mesh is not a valid closed, outward-wound surface."""


@dataclass
class Mesh:
    """Indexed triangle mesh: vertices (n, 3) float, faces (m, 3) int."""

    vertices: np.ndarray
    faces: np.ndarray

    def __add__(self, other):
        faces = np.vstack([self.faces, other.faces + len(self.vertices)])
        return Mesh(np.vstack([self.vertices, other.vertices]), faces)

    def transformed(self, rotation=None, offset=(0.0, 0.0, 0.0)):
        """Rigid transform; a reflection would turn the winding inside out."""
        rotation = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
        assert np.isclose(np.linalg.det(rotation), 1.0), "rotation must be proper"
        return Mesh(self.vertices @ rotation.T + offset, self.faces)

    def standing_on_floor(self):
        """Shift so the bottom is at z = 0 and the bounding box is centred on z."""
        lo, hi = self.vertices.min(axis=0), self.vertices.max(axis=0)
        return self.transformed(offset=(-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]))


# --------------------------------------------------------------------------
# 2-D profiles


def arc(center, radius, start_deg, end_deg, count):
    """Points on a circular arc, both ends included, as (count + 1, 2)."""
    angles = np.radians(np.linspace(start_deg, end_deg, count + 1))
    return np.column_stack([center[0] + radius * np.cos(angles), center[1] + radius * np.sin(angles)])


def polyline(*pieces):
    """Concatenate point lists, dropping a point that repeats its predecessor."""
    points = np.vstack([np.atleast_2d(np.asarray(p, dtype=float)) for p in pieces])
    keep = np.ones(len(points), dtype=bool)
    keep[1:] = np.linalg.norm(np.diff(points, axis=0), axis=1) > 1e-12
    return points[keep]


def refine(points, max_length):
    """Split every segment of an open polyline longer than max_length.

    Keeps the original points, so corners stay sharp.
    """
    out = []
    for a, b in zip(points[:-1], points[1:]):
        pieces = max(1, math.ceil(np.linalg.norm(b - a) / max_length))
        out.extend(a + (b - a) * t for t in np.arange(pieces) / pieces)
    out.append(points[-1])
    return np.array(out)


def _segments_cross(p, q, r, s):
    """True when closed segments pq and rs share a point (non-collinear case)."""

    def side(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    return side(p, q, r) != side(p, q, s) and side(r, s, p) != side(r, s, q)


def check_simple(points, closed):
    """Raise if a 2-D polyline crosses itself (the revolved solid would too)."""
    n = len(points)
    count = n if closed else n - 1
    for i in range(count):
        for j in range(i + 2, count):
            if closed and i == 0 and j == count - 1:
                continue  # first and last segment share the closing vertex
            p, q = points[i], points[(i + 1) % n]
            r, s = points[j], points[(j + 1) % n]
            if _segments_cross(p, q, r, s):
                raise MeshError(f"profile segments {i} and {j} cross")


def polygon_area(points):
    """Signed area of a 2-D polygon; positive when counter-clockwise."""
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


# --------------------------------------------------------------------------
# 3-D primitives


def grid_faces(rings):
    """Quads between consecutive closed index rings, two triangles each.

    rings is (k, n); column j of ring i joins column j of ring i + 1. With
    ring points running counter-clockwise about the direction from ring i to
    ring i + 1, the triangles face outward. A ring collapsed to one repeated
    index (a pole) gives a fan: triangles with a repeated index are dropped.
    """
    next_column = np.roll(rings, -1, axis=1)
    a, b, c, d = rings[:-1], next_column[:-1], next_column[1:], rings[1:]
    faces = np.vstack([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    distinct = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])
    return faces[distinct]


def revolve(profile, segments, closed=False):
    """Surface of revolution about z of an (r, z) profile.

    The solid must lie to the left of the profile direction (counter-clockwise
    in the r-z plane). An open profile must start and end on the axis (r = 0);
    a closed profile (e.g. a torus section) must stay off the axis.
    """
    profile = np.asarray(profile, dtype=float)
    on_axis = profile[:, 0] <= 1e-12
    if closed and on_axis.any():
        raise MeshError("closed profile touches the axis")
    if not closed and not (on_axis[0] and on_axis[-1] and not on_axis[1:-1].any()):
        raise MeshError("open profile must start and end on the axis, and only there")
    if (profile[:, 0] < 0).any():
        raise MeshError("profile has negative radius")
    check_simple(profile, closed)
    theta = 2 * np.pi * np.arange(segments) / segments
    vertices, rings = [], []
    for r, z in profile:
        first = len(vertices)
        if r <= 1e-12:
            vertices.append((0.0, 0.0, z))
            rings.append(np.full(segments, first))
        else:
            vertices.extend(zip(r * np.cos(theta), r * np.sin(theta), np.full(segments, z)))
            rings.append(first + np.arange(segments))
    if closed:
        rings.append(rings[0])
    return Mesh(np.array(vertices), grid_faces(np.array(rings)))


def sweep_tube(centerline, tangents, radius, sides):
    """Closed tube of circular section along a planar curve in the x-z plane.

    Both ends are closed by flat fans around the end points, perpendicular to
    the end tangents. The section frame is (N, B, T) with B = +y, N = B x T,
    which keeps it right-handed so the winding comes out outward.
    """
    centerline = np.asarray(centerline, dtype=float)
    tangents = np.asarray(tangents, dtype=float)
    tangents = tangents / np.linalg.norm(tangents, axis=1, keepdims=True)
    binormal = np.array([0.0, 1.0, 0.0])
    normals = np.cross(binormal, tangents)
    psi = 2 * np.pi * np.arange(sides) / sides
    offsets = np.cos(psi)[None, :, None] * normals[:, None, :] + np.sin(psi)[None, :, None] * binormal
    ring_points = centerline[:, None, :] + radius * offsets
    count = len(centerline)
    vertices = np.vstack([ring_points.reshape(-1, 3), centerline[[0, -1]]])
    start_cap, end_cap = np.full((1, sides), count * sides), np.full((1, sides), count * sides + 1)
    rings = np.vstack([start_cap, np.arange(count * sides).reshape(count, sides), end_cap])
    return Mesh(vertices, grid_faces(rings))


def triangulate_polygon(points):
    """Ear clipping for a simple counter-clockwise polygon; returns index triples."""
    remaining = list(range(len(points)))
    triangles = []
    while len(remaining) > 3:
        for k in range(len(remaining)):
            ear = (remaining[k - 1], remaining[k], remaining[(k + 1) % len(remaining)])
            corner = points[list(ear)]
            if polygon_area(corner) <= 0:
                continue  # reflex corner
            others = [m for m in remaining if m not in ear]
            if _contains_any(corner, points[others]):
                continue  # another vertex would be cut off
            triangles.append(ear)
            remaining.pop(k)
            break
        else:
            raise MeshError("polygon is not simple and counter-clockwise")
    triangles.append(tuple(remaining))
    return np.array(triangles)


def _contains_any(triangle, points):
    """True if any point lies inside or on the counter-clockwise triangle."""
    for p in points:
        if all(polygon_area(np.array([triangle[e], triangle[(e + 1) % 3], p])) >= 0 for e in range(3)):
            return True
    return False


def extrude(polygon, depth):
    """Prism from a simple counter-clockwise (u, v) polygon, w in [0, depth]."""
    polygon = np.asarray(polygon, dtype=float)
    if polygon_area(polygon) <= 0:
        raise MeshError("extrude needs a counter-clockwise polygon")
    n = len(polygon)
    bottom = np.column_stack([polygon, np.zeros(n)])
    top = np.column_stack([polygon, np.full(n, depth)])
    caps = triangulate_polygon(polygon)
    walls = grid_faces(np.vstack([np.arange(n), n + np.arange(n)]))
    faces = np.vstack([caps[:, ::-1], caps + n, walls])
    return Mesh(np.vstack([bottom, top]), faces)


def icosphere(subdivisions):
    """Unit sphere from a subdivided icosahedron, outward wound."""
    t = (1 + 5**0.5) / 2
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    vertices = [np.array(v, dtype=float) / np.linalg.norm(v) for v in vertices]
    for _ in range(subdivisions):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                m = vertices[a] + vertices[b]
                vertices.append(m / np.linalg.norm(m))
                midpoints[key] = len(vertices) - 1
            return midpoints[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return Mesh(np.array(vertices), np.array(faces))


def loft(rings, closed=False):
    """Surface through closed point loops of equal length (a general revolve).

    rings is a sequence of (n, 3) loops; point j of one loop joins point j
    of the next. As with revolve, every loop runs counter-clockwise about
    +z and the sequence goes round the solid's cross-section with the
    solid on its left (outward along the bottom, up the outside, inward
    along the top). An open sequence is closed by two flat caps, so its
    first and last loop must each be a simple horizontal polygon; a closed
    one (e.g. a nut's section, hole included) joins the last loop to the
    first.
    """
    rings = [np.asarray(r, dtype=float) for r in rings]
    n = len(rings[0])
    if any(r.shape != (n, 3) for r in rings):
        raise MeshError("loft loops differ in length")
    index = np.arange(len(rings) * n).reshape(len(rings), n)
    if closed:
        index = np.vstack([index, index[:1]])
    faces = [grid_faces(index)]
    if not closed:
        for ring, loop, upward in ((rings[0], index[0], False), (rings[-1], index[-1], True)):
            if np.ptp(ring[:, 2]) > 1e-12:
                raise MeshError("loft cap is not horizontal")
            cap = loop[triangulate_polygon(ring[:, :2])]
            faces.append(cap if upward else cap[:, ::-1])
    return Mesh(np.vstack(rings), np.vstack(faces))


def rectangle(width, depth):
    """Counter-clockwise (u, v) rectangle centred on the origin."""
    u, v = width / 2, depth / 2
    return np.array([(-u, -v), (u, -v), (u, v), (-u, v)])


def rounded_rectangle(width, depth, radius, per_corner):
    """Counter-clockwise (u, v) rectangle centred on the origin, corners rounded."""
    u, v = width / 2 - radius, depth / 2 - radius
    corners = [((u, -v), -90), ((u, v), 0), ((-u, v), 90), ((-u, -v), 180)]
    return np.vstack([arc(c, radius, start, start + 90, per_corner) for c, start in corners])


def at_height(polygon, z):
    """(n, 3) loop of a 2-D polygon at height z."""
    polygon = np.asarray(polygon, dtype=float)
    return np.column_stack([polygon, np.full(len(polygon), z)])


def catmull_rom(points, per_segment):
    """Smooth open curve through every control point (uniform Catmull-Rom)."""
    p = np.asarray(points, dtype=float)
    p = np.vstack([2 * p[0] - p[1], p, 2 * p[-1] - p[-2]])  # mirrored end tangents
    t = np.arange(per_segment)[:, None] / per_segment
    out = []
    for i in range(1, len(p) - 2):
        p0, p1, p2, p3 = p[i - 1], p[i], p[i + 1], p[i + 2]
        out.append(0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t**2
                          + (3 * p1 - p0 - 3 * p2 + p3) * t**3))
    out.append(p[-2][None])
    return np.vstack(out)


def vessel_profile(outer, wall, floor, rim_segments=12):
    """(r, z) profile of an open-topped vessel for revolve.

    outer runs up the outside from the bottom edge (r > 0, z = 0) to the
    rim. The inside is outer shifted inward by wall along its normals and
    cut off at the floor height; a semicircular rim joins the two. The
    result starts and ends on the axis.
    """
    outer = np.asarray(outer, dtype=float)
    segment = np.diff(outer, axis=0)
    segment /= np.linalg.norm(segment, axis=1, keepdims=True)
    left = np.column_stack([-segment[:, 1], segment[:, 0]])  # towards the solid
    normal = np.vstack([left[:1], left[:-1] + left[1:], left[-1:]])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    inner = outer + wall * normal
    if inner[-1, 1] <= floor:
        raise MeshError("vessel floor above its rim")
    first = np.nonzero(inner[:, 1] < floor)[0].max() + 1  # inside wall above the floor
    a, b = inner[first - 1], inner[first]
    floor_point = a + (b - a) * (floor - a[1]) / (b[1] - a[1])
    inner = np.vstack([floor_point, inner[first:]])
    centre = (outer[-1] + inner[-1]) / 2
    start = math.degrees(math.atan2(*(outer[-1] - centre)[::-1]))
    rim = arc(centre, wall / 2, start, start + 180, rim_segments)
    return polyline((0.0, 0.0), outer, rim[1:-1], inner[::-1], (0.0, floor))


def check_inside(points, inside, what):
    """Raise MeshError unless inside(points) holds for every point."""
    if not inside(np.asarray(points)).all():
        raise MeshError(what)


# Proper rotations that lay objects down (columns: where the old x, y, z axes go).
X_QUARTER_TURN = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], dtype=float)  # y -> z, z -> -y
Y_QUARTER_TURN = np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]], dtype=float)  # z -> x, x -> -z
PRISM_ALONG_X = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0]], dtype=float)  # extrude's (u, v, w) -> (y, z, x)


# --------------------------------------------------------------------------
# The objects (all sizes in metres)


def c_handle(outer_r, sunk, reach, half_height, z_mid, tube_r):
    """A C handle on a vessel of outer radius outer_r: a tube of radius tube_r
    along a half ellipse in the x-z plane centred at height z_mid, reaching
    `reach` out of the wall; its ends are horizontal and stop `sunk` inside
    the outer wall."""
    phi = np.linspace(-np.pi / 2, np.pi / 2, 65)
    a, b = sunk + reach, half_height
    centerline = np.column_stack([outer_r - sunk + a * np.cos(phi), 0 * phi, z_mid + b * np.sin(phi)])
    tangents = np.column_stack([-a * np.sin(phi), 0 * phi, b * np.cos(phi)])
    return sweep_tube(centerline, tangents, tube_r, 32)


def mug():
    """Cup with a real cavity and a C-shaped handle sunk into the wall."""
    outer_r, height, wall, floor = 0.040, 0.100, 0.005, 0.006
    inner_r, foot_fillet, inner_fillet = outer_r - wall, 0.004, 0.005
    profile = polyline(
        (0.0, 0.0),
        arc((outer_r - foot_fillet, foot_fillet), foot_fillet, -90, 0, 6),
        arc((outer_r - wall / 2, height - wall / 2), wall / 2, 0, 180, 12),  # rounded rim
        arc((inner_r - inner_fillet, floor + inner_fillet), inner_fillet, 0, -90, 6),
        (0.0, floor),
    )
    body = revolve(refine(profile, 0.004), 64)

    handle = c_handle(outer_r, sunk=0.0045, reach=0.030, half_height=0.030, z_mid=0.055,
                      tube_r=0.006)
    if np.hypot(handle.vertices[:, 0], handle.vertices[:, 1]).min() < inner_r + 0.0002:
        raise MeshError("mug handle pokes into the cavity")
    return body + handle


def bowl():
    """Thick-walled elliptical bowl on a short solid foot, open at the top."""
    outer_r, rim_z, wall, foot_r = 0.070, 0.0575, 0.005, 0.028
    outer_depth, inner_depth = 0.056, 0.051
    t = np.linspace(0, np.pi / 2, 41)
    outer = np.column_stack([outer_r * np.sin(t), rim_z - outer_depth * np.cos(t)])
    inner_r = outer_r - wall
    inner = np.column_stack([inner_r * np.sin(t), rim_z - inner_depth * np.cos(t)])[::-1]
    foot_top = rim_z - outer_depth * math.sqrt(1 - (foot_r / outer_r) ** 2)
    profile = polyline(
        (0.0, 0.0),
        [(foot_r, 0.0), (foot_r, foot_top)],
        outer[outer[:, 0] > foot_r],
        arc((outer_r - wall / 2, rim_z), wall / 2, 0, 180, 12),  # rounded rim
        inner,
    )
    return revolve(refine(profile, 0.005), 96)


def bottle():
    """Solid bottle: cylindrical body, smooth shoulder, narrow neck."""
    body_r, neck_r, height = 0.033, 0.013, 0.200
    shoulder_bottom, shoulder_top, base_fillet, lip_fillet = 0.125, 0.165, 0.004, 0.002
    s = np.linspace(0, 1, 25)
    # Cosine blend: vertical tangent where it meets both the body and the neck.
    shoulder = np.column_stack([neck_r + (body_r - neck_r) * (1 + np.cos(np.pi * s)) / 2,
                                shoulder_bottom + (shoulder_top - shoulder_bottom) * s])
    profile = polyline(
        (0.0, 0.0),
        arc((body_r - base_fillet, base_fillet), base_fillet, -90, 0, 6),
        shoulder,
        arc((neck_r - lip_fillet, height - lip_fillet), lip_fillet, 0, 90, 4),
        (0.0, height),
    )
    return revolve(refine(profile, 0.004), 64)


def torus():
    """Ring lying flat on the floor (axis = z)."""
    major, minor = 0.050, 0.015
    section = arc((major, minor), minor, -90, 270, 48)[:-1]  # starts at z = 0
    return revolve(section, 96, closed=True)


def l_bracket():
    """L-shaped prism: the long leg lies on the floor, the short leg stands up."""
    long_leg, short_leg, thickness, width = 0.100, 0.060, 0.020, 0.040
    outline = [(0, 0), (long_leg, 0), (long_leg, thickness), (thickness, thickness),
               (thickness, short_leg), (0, short_leg)]
    x_axis_quarter_turn = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]  # (u, v, w) -> (u, -w, v)
    return extrude(outline, width).transformed(x_axis_quarter_turn).standing_on_floor()


def box():
    """8 x 6 x 12 cm box; only flat faces and sharp edges."""
    return extrude([(0, 0), (0.08, 0), (0.08, 0.06), (0, 0.06)], 0.12).standing_on_floor()


def cylinder():
    """Upright cylinder with flat caps."""
    radius, height = 0.035, 0.120
    profile = [(0.0, 0.0), (radius, 0.0), (radius, height), (0.0, height)]
    return revolve(refine(np.array(profile), 0.005), 64)


def blob():
    """Smooth star-shaped blob: an icosphere with a low-frequency radial bump."""
    sphere = icosphere(4)
    x, y, z = sphere.vertices.T
    bumps = (0.40 * np.sin(3.0 * x + 1.0) * np.cos(2.5 * y)
             + 0.35 * np.sin(3.5 * z + 2.0 * x)
             + 0.25 * np.cos(3.0 * y - 2.0 * z + 0.5))
    # Largest deviation exactly 20 %: dents deep enough to make it non-convex
    # (about a tenth of the edges are concave), yet every facet still faces
    # away from the centre, so it stays star-shaped.
    radius = 0.045 * (1 + 0.2 * bumps / np.abs(bumps).max())
    return Mesh(sphere.vertices * radius[:, None], sphere.faces).standing_on_floor()


# -- thin plates (at most 2 cm thick) --------------------------------------


def plate():
    """15 x 10 x 1.2 cm flat plate with 2 cm corner radii, lying on its face."""
    return extrude(rounded_rectangle(0.150, 0.100, 0.020, 8), 0.012).standing_on_floor()


def coaster():
    """Round coaster, 9 cm across and 1 cm thick, both rims rounded (1 mm)."""
    radius, height, fillet = 0.045, 0.010, 0.001
    profile = polyline(
        (0.0, 0.0),
        arc((radius - fillet, fillet), fillet, -90, 0, 4),
        arc((radius - fillet, height - fillet), fillet, 0, 90, 4),
        (0.0, height),
    )
    return revolve(refine(profile, 0.005), 96)


def tile():
    """12 x 6 x 2 cm tile; its four top edges are chamfered 3 mm x 3 mm."""
    width, depth, height, chamfer = 0.120, 0.060, 0.020, 0.003
    loops = [at_height(rectangle(width, depth), 0.0),
             at_height(rectangle(width, depth), height - chamfer),
             at_height(rectangle(width - 2 * chamfer, depth - 2 * chamfer), height)]
    return loft(loops)


# -- flat boxes and rings (at most 4 cm tall) ------------------------------


def crayon_box():
    """14 x 9 x 3.6 cm flat box; grasped across its 3.6 cm height or its sides."""
    return extrude(rectangle(0.140, 0.090), 0.036)


def washer():
    """Flat ring (fender washer): 10 cm across, 3.6 cm hole, 1.2 cm thick, 2 mm fillets."""
    inner, outer, height, fillet = 0.018, 0.050, 0.012, 0.002
    section = polyline(
        arc((outer - fillet, fillet), fillet, -90, 0, 4),
        arc((outer - fillet, height - fillet), fillet, 0, 90, 4),
        arc((inner + fillet, height - fillet), fillet, 90, 180, 4),
        arc((inner + fillet, fillet), fillet, 180, 270, 4),
    )
    return revolve(section, 96, closed=True)


def tin_can():
    """Flat tin, 10 cm across and 3 cm tall; the lid overhangs the base by 1 mm."""
    base_r, lid_r, lid_z, height, fillet = 0.049, 0.050, 0.022, 0.030, 0.002
    profile = polyline(
        (0.0, 0.0),
        arc((base_r - fillet, fillet), fillet, -90, 0, 4),
        (base_r, lid_z),
        (lid_r, lid_z),  # the step under the lid's rim
        arc((lid_r - fillet, height - fillet), fillet, 0, 90, 4),
        (0.0, height),
    )
    return revolve(refine(profile, 0.005), 96)


# -- small parts (at most 5 cm) ---------------------------------------------


def small_cube():
    """4.6 cm cube (a toy block); the smallest box the hand must pinch."""
    return extrude(rectangle(0.046, 0.046), 0.046)


def egg():
    """Egg, 5 cm long and 4.2 cm across, lying on its side; blunt end and pointed end."""
    length, radius = 0.050, 0.021
    t = np.linspace(0, np.pi, 49)
    profile = np.column_stack([radius * np.sin(t) * (1 + 0.12 * np.cos(t)), length / 2 * (1 - np.cos(t))])
    profile[[0, -1], 0] = 0.0  # the tips exactly on the axis
    return revolve(profile, 64).transformed(Y_QUARTER_TURN).standing_on_floor()


def small_ball():
    """5 cm ball (icosphere, 1280 triangles) resting on one facet."""
    sphere = icosphere(3)
    return Mesh(sphere.vertices * 0.025, sphere.faces).standing_on_floor()


def peg():
    """Wooden peg, 4 cm across and 5 cm tall, 3 mm chamfer on top."""
    radius, height, chamfer, fillet = 0.020, 0.050, 0.003, 0.001
    profile = polyline(
        (0.0, 0.0),
        arc((radius - fillet, fillet), fillet, -90, 0, 4),
        (radius, height - chamfer),
        (radius - chamfer, height),
        (0.0, height),
    )
    return revolve(refine(profile, 0.004), 64)


# -- large objects (15 cm or more) ------------------------------------------


def carton():
    """15 x 9.5 x 19.5 cm carton standing upright; only its 9.5 cm side fits the hand."""
    return extrude(rectangle(0.150, 0.095), 0.195)


def vase():
    """Tall open vase, 19.6 cm: foot, belly 12 cm across, neck, flared lip; 4 mm wall."""
    outer = catmull_rom([(0.036, 0.0), (0.052, 0.030), (0.060, 0.070), (0.052, 0.115),
                         (0.036, 0.150), (0.036, 0.175), (0.044, 0.196)], 8)
    return revolve(refine(vessel_profile(outer, 0.004, 0.008), 0.008), 64)


def basin():
    """Wash basin 19.6 cm across and 8 cm tall: flat bottom, sloped 5 mm wall."""
    bottom_r, top_r, height, fillet = 0.068, 0.0975, 0.0775, 0.006
    slope = math.degrees(math.atan2(height, top_r - bottom_r))  # wall angle from horizontal
    corner = arc((bottom_r - fillet * math.tan(math.radians(slope / 2)), fillet), fillet, -90, slope - 90, 6)
    outer = polyline(corner, (top_r, height))
    return revolve(refine(vessel_profile(outer, 0.005, 0.006), 0.006), 96)


# -- non-convex prisms ------------------------------------------------------


def u_channel():
    """U channel, 14 cm long, 6 x 4.5 cm section, 8 mm walls, open side up."""
    width, height, wall, length = 0.060, 0.045, 0.008, 0.140
    outline = [(0, 0), (width, 0), (width, height), (width - wall, height), (width - wall, wall),
               (wall, wall), (wall, height), (0, height)]
    return extrude(outline, length).transformed(PRISM_ALONG_X).standing_on_floor()


def t_profile():
    """Inverted T profile, 12 cm long: 7 x 1.2 cm flange on the floor, 1.2 cm web 6 cm tall."""
    flange, web, thickness, height, length = 0.070, 0.012, 0.012, 0.060, 0.120
    left, right = (flange - web) / 2, (flange + web) / 2
    outline = [(0, 0), (flange, 0), (flange, thickness), (right, thickness), (right, height),
               (left, height), (left, thickness), (0, thickness)]
    return extrude(outline, length).transformed(PRISM_ALONG_X).standing_on_floor()


def star_prism():
    """Five-pointed star lying flat: tips 6.5 cm, notches 2.8 cm from the centre, 3 cm thick."""
    angle = np.radians(90 + 36 * np.arange(10))
    radius = np.where(np.arange(10) % 2 == 0, 0.065, 0.028)
    outline = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    return extrude(outline, 0.030).standing_on_floor()


def cross():
    """Plus-shaped block lying flat: 12 x 12 cm, 4 cm wide arms, 3.5 cm thick."""
    a, b = 0.060, 0.020
    outline = [(b, -a), (b, -b), (a, -b), (a, b), (b, b), (b, a), (-b, a), (-b, b), (-a, b), (-a, -b),
               (-b, -b), (-b, -a)]
    return extrude(outline, 0.035)


# -- handles ----------------------------------------------------------------


def saucepan():
    """Open pot 10 cm across and 5.5 cm tall with a straight handle lying flat.

    The handle is a round tube whose flat inner end is sunk 3 mm into the
    5 mm wall, as the mug's handle is: two overlapping components.
    """
    outer_r, height, wall, floor, fillet = 0.050, 0.055, 0.005, 0.006, 0.004
    outer = polyline(arc((outer_r - fillet, fillet), fillet, -90, 0, 6), (outer_r, height))
    body = revolve(refine(vessel_profile(outer, wall, floor), 0.004), 64)
    sunk, length, z, tube_r = 0.003, 0.093, 0.036, 0.0075
    x = np.linspace(outer_r - sunk, outer_r - sunk + length, 24)
    handle = sweep_tube(np.column_stack([x, 0 * x, np.full_like(x, z)]), np.tile([1.0, 0, 0], (len(x), 1)),
                        tube_r, 24)
    radial = np.hypot(handle.vertices[:, 0], handle.vertices[:, 1])
    check_inside(radial, lambda r: r > outer_r - wall + 0.0002, "saucepan handle pokes into the pot")
    cap = handle.vertices[(handle.vertices[:, 0] < outer_r - sunk + 1e-9)]
    check_inside(np.hypot(cap[:, 0], cap[:, 1]), lambda r: r < outer_r - 0.0002, "handle end sticks out")
    return (body + handle).standing_on_floor()


def jug():
    """Jug 18.5 cm tall and 11 cm across, 4 mm wall, with a C handle like the mug's."""
    outer_r, wall, floor, fillet = 0.055, 0.004, 0.008, 0.005
    outer = polyline(arc((outer_r - fillet, fillet), fillet, -90, 0, 6), (outer_r, 0.160),
                     catmull_rom([(outer_r, 0.160), (0.053, 0.175), (0.054, 0.185)], 4)[1:])
    body = revolve(refine(vessel_profile(outer, wall, floor), 0.008), 64)
    handle = c_handle(outer_r, sunk=0.0035, reach=0.040, half_height=0.050, z_mid=0.100,
                      tube_r=0.007)
    radial = np.hypot(handle.vertices[:, 0], handle.vertices[:, 1])
    check_inside(radial, lambda r: r > outer_r - wall + 0.0002, "jug handle pokes into the cavity")
    if handle.vertices[:, 2].max() > 0.160:
        raise MeshError("jug handle leaves the straight part of the wall")
    return (body + handle).standing_on_floor()


def kettlebell():
    """Kettlebell 10 cm across and 15.4 cm tall: a flat-based ball and an arched handle.

    The handle is a tube along a half ellipse over the ball; both ends run
    straight down into the solid ball (two overlapping components).
    """
    radius, centre_z = 0.050, 0.045
    start = -math.degrees(math.asin(centre_z / radius))
    profile = polyline((0.0, 0.0), arc((0.0, centre_z), radius, start, 90, 40))
    profile[-1, 0] = 0.0  # the pole exactly on the axis
    ball = revolve(profile, 64)
    half_width, rise, end_z, tube_r = 0.036, 0.085, 0.060, 0.009
    phi = np.linspace(np.pi, 0.0, 65)
    centerline = np.column_stack([half_width * np.cos(phi), 0 * phi, end_z + rise * np.sin(phi)])
    tangents = np.column_stack([half_width * np.sin(phi), 0 * phi, -rise * np.cos(phi)])  # phi falls
    tangents[[0, -1]] = [(0, 0, 1), (0, 0, -1)]  # exactly vertical ends
    handle = sweep_tube(centerline, tangents, tube_r, 32)
    ends = handle.vertices[np.abs(handle.vertices[:, 2] - end_z) < 1e-9]
    check_inside(np.linalg.norm(ends - (0, 0, centre_z), axis=1), lambda d: d < radius - 0.001,
                 "kettlebell handle ends stick out of the ball")
    return ball + handle


# -- cylinders lying down ---------------------------------------------------


def can_lying():
    """Food can, 7 cm across and 12 cm long, lying on its side on its rims.

    The rolled rims (3.5 cm radius) stand 1 mm proud of the 3.4 cm body
    and the ends are recessed 3 mm.
    """
    profile = polyline(
        (0.0, 0.003), (0.030, 0.003),
        arc((0.0325, 0.0025), 0.0025, -90, 90, 6),  # bottom rim
        (0.034, 0.007), (0.034, 0.113),
        arc((0.0325, 0.1175), 0.0025, -90, 90, 6),  # top rim
        (0.030, 0.117), (0.0, 0.117),
    )
    return revolve(refine(profile, 0.005), 64).transformed(Y_QUARTER_TURN).standing_on_floor()


def pipe():
    """Pipe lying down: 4 cm outside, 3.2 cm inside, 18 cm long (genus 1)."""
    inner, outer, length = 0.016, 0.020, 0.180
    side = np.linspace(0.0, length, 19)
    section = np.vstack([np.column_stack([np.full_like(side, outer), side]),
                         np.column_stack([np.full_like(side, inner), side[::-1]])])
    return revolve(section, 48, closed=True).transformed(Y_QUARTER_TURN).standing_on_floor()


def dowel():
    """Dowel lying down: 2.5 cm across, 18 cm long, 1.5 mm chamfers at the ends."""
    radius, length, chamfer = 0.0125, 0.180, 0.0015
    profile = [(0.0, 0.0), (radius - chamfer, 0.0), (radius, chamfer), (radius, length - chamfer),
               (radius - chamfer, length), (0.0, length)]
    return revolve(refine(np.array(profile), 0.01), 48).transformed(Y_QUARTER_TURN).standing_on_floor()


# --------------------------------------------------------------------------
# Checks


@dataclass
class MeshReport:
    """What check_mesh measured: one entry per connected component."""

    volumes: np.ndarray
    genera: np.ndarray


def triangle_normals(mesh):
    """Unnormalised normals; their length is twice the triangle area."""
    a, b, c = (mesh.vertices[mesh.faces[:, k]] for k in range(3))
    return np.cross(b - a, c - a)


def component_labels(vertex_count, faces):
    """Connected-component id (0, 1, ...) of every vertex."""
    labels = np.arange(vertex_count)
    while True:
        spread = labels.copy()
        face_min = labels[faces].min(axis=1)
        for k in range(3):
            np.minimum.at(spread, faces[:, k], face_min)
        spread = spread[spread]  # pointer jumping: follow the chain to its root
        if np.array_equal(spread, labels):
            return np.unique(labels, return_inverse=True)[1]
        labels = spread


def check_mesh(mesh):
    """Raise MeshError unless each component is closed, manifold and outward."""
    vertices, faces = mesh.vertices, mesh.faces
    n = len(vertices)
    if not np.isfinite(vertices).all():
        raise MeshError("non-finite vertex coordinates")
    if faces.min() < 0 or faces.max() >= n:
        raise MeshError("face index out of range")
    if len(np.unique(faces)) != n:
        raise MeshError(f"{n - len(np.unique(faces))} unreferenced vertices")
    areas = np.linalg.norm(triangle_normals(mesh), axis=1) / 2
    if areas.min() < MIN_TRIANGLE_AREA:
        count = (areas < MIN_TRIANGLE_AREA).sum()
        raise MeshError(f"{count} degenerate triangles (smallest area {areas.min():.3g} m^2)")

    edges = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2).astype(np.int64)
    codes = edges[:, 0] * n + edges[:, 1]
    if len(np.unique(codes)) != len(codes):
        raise MeshError("a directed edge occurs twice (non-manifold edge or inconsistent winding)")
    if not np.isin(edges[:, 1] * n + edges[:, 0], codes).all():
        raise MeshError("an edge has no opposite twin (open boundary or inconsistent winding)")

    labels = component_labels(n, faces)
    parts = labels.max() + 1
    for part in range(parts):
        grid = np.round(vertices[labels == part] / DUPLICATE_GRID).astype(np.int64)
        if len(np.unique(grid, axis=0)) != len(grid):
            raise MeshError(f"component {part} has duplicated vertices")
    face_part = labels[faces[:, 0]]
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    signed = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6  # divergence theorem
    volumes = np.bincount(face_part, weights=signed, minlength=parts)
    if (volumes <= 0).any():
        raise MeshError(f"component volumes {volumes} not all positive (inward winding)")
    face_count = np.bincount(face_part, minlength=parts)
    euler = np.bincount(labels, minlength=parts) - face_count * 3 // 2 + face_count
    return MeshReport(volumes, (2 - euler) // 2)


# --------------------------------------------------------------------------
# Writers: each returns the file's bytes for one mesh


def unit_normals(mesh):
    normals = triangle_normals(mesh)
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def decimal(values):
    """Shortest text that reads back to the same float32 values."""
    return " ".join(np.format_float_positional(np.float32(v) + np.float32(0), unique=True, trim="0")
                    for v in values)


def stl_binary(mesh, name):
    record = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    facets = np.zeros(len(mesh.faces), dtype=record)
    facets["normal"] = unit_normals(mesh)
    facets["corners"] = mesh.vertices[mesh.faces]
    # A binary STL header must not start with "solid" or readers take it for ASCII.
    header = f"HFTS test object '{name}', metres, z up".encode("ascii").ljust(80, b" ")
    return header + struct.pack("<I", len(facets)) + facets.tobytes()


def stl_ascii(mesh, name):
    points = [decimal(p) for p in mesh.vertices]
    lines = [f"solid {name}"]
    for normal, corners in zip(unit_normals(mesh), mesh.faces):
        lines += [f"  facet normal {decimal(normal)}", "    outer loop"]
        lines += [f"      vertex {points[k]}" for k in corners]
        lines += ["    endloop", "  endfacet"]
    lines.append(f"endsolid {name}")
    return ("\n".join(lines) + "\n").encode("ascii")


def ply_binary(mesh, name):
    header = "\n".join([
        "ply", "format binary_little_endian 1.0", f"comment HFTS test object '{name}', metres, z up",
        f"element vertex {len(mesh.vertices)}", "property float x", "property float y", "property float z",
        f"element face {len(mesh.faces)}", "property list uchar int vertex_indices", "end_header",
    ]) + "\n"
    faces = np.zeros(len(mesh.faces), dtype=[("count", "u1"), ("indices", "<i4", (3,))])
    faces["count"] = 3
    faces["indices"] = mesh.faces
    return header.encode("ascii") + mesh.vertices.astype("<f4").tobytes() + faces.tobytes()


def obj_text(mesh, name):
    lines = [f"# HFTS test object '{name}', metres, z up", f"o {name}"]
    lines += [f"v {decimal(p)}" for p in mesh.vertices]
    lines += [f"f {a} {b} {c}" for a, b, c in mesh.faces + 1]
    return ("\n".join(lines) + "\n").encode("ascii")


def write_atomically(path, data):
    """Replace path with data so readers never see a half-written file."""
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


# --------------------------------------------------------------------------


OBJECTS = [  # name, builder, file name, writer
    ("mug", mug, "mug.ply", ply_binary),
    ("bowl", bowl, "bowl.obj", obj_text),
    ("bottle", bottle, "bottle.stl", stl_binary),
    ("torus", torus, "torus.stl", stl_binary),
    ("l_bracket", l_bracket, "l_bracket.ply", ply_binary),
    ("box", box, "box.stl", stl_binary),
    ("cylinder", cylinder, "cylinder.stl", stl_binary),
    ("blob", blob, "blob.stl", stl_ascii),
    # thin plates
    ("plate", plate, "plate.ply", ply_binary),
    ("coaster", coaster, "coaster.stl", stl_binary),
    ("tile", tile, "tile.obj", obj_text),
    # flat boxes and rings
    ("crayon_box", crayon_box, "crayon_box.stl", stl_ascii),
    ("washer", washer, "washer.obj", obj_text),
    ("tin_can", tin_can, "tin_can.ply", ply_binary),
    # small parts
    ("small_cube", small_cube, "small_cube.stl", stl_ascii),
    ("egg", egg, "egg.ply", ply_binary),
    ("small_ball", small_ball, "small_ball.stl", stl_binary),
    ("peg", peg, "peg.obj", obj_text),
    # large objects
    ("carton", carton, "carton.stl", stl_binary),
    ("vase", vase, "vase.ply", ply_binary),
    ("basin", basin, "basin.obj", obj_text),
    # non-convex prisms
    ("u_channel", u_channel, "u_channel.stl", stl_binary),
    ("t_profile", t_profile, "t_profile.ply", ply_binary),
    ("star_prism", star_prism, "star_prism.stl", stl_ascii),
    ("cross", cross, "cross.obj", obj_text),
    # handles
    ("saucepan", saucepan, "saucepan.ply", ply_binary),
    ("jug", jug, "jug.obj", obj_text),
    ("kettlebell", kettlebell, "kettlebell.ply", ply_binary),
    # cylinders lying down
    ("can_lying", can_lying, "can_lying.stl", stl_binary),
    ("pipe", pipe, "pipe.stl", stl_binary),
    ("dowel", dowel, "dowel.stl", stl_ascii),
]


def summary(name, file_name, mesh, report):
    lo, hi = mesh.vertices.min(axis=0) * 100, mesh.vertices.max(axis=0) * 100
    bbox = " x ".join(f"[{a:6.2f},{b:6.2f}]" for a, b in zip(lo, hi))
    return (f"{name:<10} {file_name:<14} vertices {len(mesh.vertices):6d}  triangles {len(mesh.faces):6d}  "
            f"volume {report.volumes.sum() * 1e6:7.1f} cm^3  parts {len(report.volumes)}  "
            f"genus {','.join(map(str, report.genera))}  bbox {bbox} cm")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, metavar="DIR", default=Path(__file__).resolve().parent / "meshes",
                        help="output folder (default: meshes/ next to this script)")
    args = parser.parse_args(argv)

    checked = []
    for name, build, file_name, writer in OBJECTS:
        try:
            built = build()
            # Check exactly what the files will hold: float32 coordinates.
            mesh = Mesh(built.vertices.astype(np.float32).astype(np.float64), built.faces)
            checked.append((name, file_name, writer, mesh, check_mesh(mesh)))
        except MeshError as error:
            print(f"generate_objects: '{name}' failed its check: {error}; nothing written", file=sys.stderr)
            return 1

    args.out.mkdir(parents=True, exist_ok=True)
    for name, file_name, writer, mesh, report in checked:
        write_atomically(args.out / file_name, writer(mesh, name))
        print(summary(name, file_name, mesh, report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
