#!/usr/bin/python3
"""Generate the held-out test objects: shapes, sizes and densities the
bundled objects do not have, for evaluating the planner only (nobody tunes
on them; see README.md beside this script).

Twenty closed objects are built procedurally from the primitives of
``objects/generate_objects.py`` (imported, not copied) and checked with its
``check_mesh``: finite, no degenerate or duplicated vertices, every edge
used once each way, every part wound outward. Seven of them also get a
*scan-like* variant (``<name>_scan``): the same solid as a signed distance
function, remeshed by marching tetrahedra to about 16 000 irregular
triangles, with 0.08 mm of surface noise, then damaged the way real scans
are: two small holes (one and three triangles), two T-junctions closed by
zero-area triangles (which the loader drops, leaving cracks) and one flap
of debris on an edge (a non-manifold edge). Each scan is checked before
the damage with ``check_mesh`` and after it for exactly that damage.

Every mesh gets a sidecar ``<stem>.json`` holding ``{"density": kg/m^3}``.
Conventions as for the bundled objects: metres, z up, standing on z = 0,
centred on the z axis. Output is byte-deterministic and written atomically
after all checks passed; a failed check writes nothing and exits 1:

    /usr/bin/python3 objects/heldout/generate_heldout.py [--out DIR]

Needs only the standard library and numpy.
"""

import argparse
import itertools
import json
import math
import sys
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import generate_objects as base  # noqa: E402  (the bundled objects' primitives and checks)

Mesh, MeshError = base.Mesh, base.MeshError

SCAN_TRIANGLES = 16000  # what the tester's scans had
SCAN_NOISE = 0.00008  # m, standard deviation along the vertex normal
SNAP = 2.0**-19  # m; T-junction ends on this grid make the midpoint exact in float32


# --------------------------------------------------------------------------
# Clean meshes (construction frame; `Part.pose` lays them down)


def superellipsoid(half, exponent, subdivisions=4):
    """Superquadric through the icosphere: each coordinate of a unit-sphere
    point raised to `exponent` with its sign kept (< 1: boxier), then scaled
    by the half extents. The map keeps the winding outward."""
    sphere = base.icosphere(subdivisions)
    v = np.sign(sphere.vertices) * np.abs(sphere.vertices) ** exponent
    return Mesh(v * np.asarray(half, dtype=float), sphere.faces)


def regular_polygon(sides, across_flats, phase=0.0):
    """Counter-clockwise (u, v) polygon with a flat at the bottom."""
    circumradius = across_flats / 2 / math.cos(math.pi / sides)
    angles = -math.pi / 2 + math.pi / sides + phase + 2 * math.pi * np.arange(sides) / sides
    return np.column_stack([circumradius * np.cos(angles), circumradius * np.sin(angles)])


def tapered_tube(centerline, radii, sides):
    """Closed tube along a curve in the x-z plane whose radius follows `radii`
    (one per centreline point); the first and last radius must be 0, where
    the tube closes to a point (a banana's ends)."""
    centerline = np.asarray(centerline, dtype=float)
    tangents = np.gradient(centerline, axis=0)
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    binormal = np.array([0.0, 1.0, 0.0])
    normals = np.cross(binormal, tangents)
    psi = 2 * np.pi * np.arange(sides) / sides
    vertices, rings = [], []
    for c, n, r in zip(centerline, normals, radii):
        first = len(vertices)
        if r <= 0:
            vertices.append(c)
            rings.append(np.full(sides, first))
        else:
            vertices.extend(c + r * (np.cos(p) * n + np.sin(p) * binormal) for p in psi)
            rings.append(first + np.arange(sides))
    return Mesh(np.array(vertices), base.grid_faces(np.array(rings)))


def frustum_profile(bottom_r, top_r, height, chamfer):
    return base.polyline((0.0, 0.0), (bottom_r - chamfer, 0.0), (bottom_r, chamfer),
                         (top_r, height - chamfer), (top_r - chamfer, height), (0.0, height))


# --------------------------------------------------------------------------
# Signed distance functions (negative inside) of the scanned objects


def _segment_distance(p, a, b):
    """Distances (n, m) from points p (n, d) to segments a -> b (m, d)."""
    ab = b - a
    t = np.einsum("nmd,md->nm", p[:, None, :] - a[None], ab) / np.maximum(np.einsum("md,md->m", ab, ab), 1e-30)
    t = np.clip(t, 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(p[:, None, :] - closest, axis=2), t


def _inside_polygon(p, polygon):
    """Even-odd test of 2-D points against a closed polygon."""
    inside = np.zeros(len(p), dtype=bool)
    q = np.roll(polygon, -1, axis=0)
    for (ax, ay), (bx, by) in zip(polygon, q):
        straddles = (ay > p[:, 1]) != (by > p[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            x = ax + (p[:, 1] - ay) * (bx - ax) / (by - ay)
        inside ^= straddles & (p[:, 0] < x)
    return inside


def sdf_polygon(p, polygon, open_chain=False):
    """Signed distance to a closed 2-D polygon. With `open_chain` the closing
    segment (last -> first) bounds the inside but is not surface: a revolve
    profile's stretch along the axis."""
    polygon = np.asarray(polygon, dtype=float)
    a = polygon if not open_chain else polygon[:-1]
    b = np.roll(polygon, -1, axis=0) if not open_chain else polygon[1:]
    distance = _segment_distance(p, a, b)[0].min(axis=1)
    return np.where(_inside_polygon(p, polygon), -distance, distance)


def sdf_revolve(points, profile):
    q = np.column_stack([np.hypot(points[:, 0], points[:, 1]), points[:, 2]])
    return sdf_polygon(q, profile, open_chain=True)


def sdf_extrude(points, polygon, depth):
    """The prism of base.extrude: (u, v) polygon, w in [0, depth]."""
    d2 = sdf_polygon(points[:, :2], polygon)
    dw = np.abs(points[:, 2] - depth / 2) - depth / 2
    outside = np.hypot(np.maximum(d2, 0), np.maximum(dw, 0))
    return outside + np.minimum(np.maximum(d2, dw), 0)


def sdf_tube(points, centerline, radii):
    """Round-ended tube along a polyline; `radii` per point, interpolated."""
    centerline = np.asarray(centerline, dtype=float)
    radii = np.broadcast_to(np.asarray(radii, dtype=float), (len(centerline),))
    d, t = _segment_distance(points, centerline[:-1], centerline[1:])
    r = radii[:-1][None] + t * (radii[1:] - radii[:-1])[None]
    return (d - r).min(axis=1)


def transformed_sdf(sdf, rotation=None, offset=(0.0, 0.0, 0.0)):
    """The SDF of a part moved like Mesh.transformed(rotation, offset)."""
    rotation = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    return lambda p: sdf((p - np.asarray(offset)) @ rotation)


def union(*sdfs):
    return lambda p: np.min([f(p) for f in sdfs], axis=0)


# --------------------------------------------------------------------------
# The objects (metres). Each returns (mesh, sdf or None) in its construction
# frame; OBJECTS below says how it is laid on the table.


def soap_bar():
    return superellipsoid((0.045, 0.030, 0.0175), 0.55), None


def dice():
    return superellipsoid((0.01, 0.01, 0.01), 0.25), None


def lemon():
    """Prolate, pointed at both ends: r(z) = R sin(pi t)^0.7 plus two nubs."""
    length, radius = 0.080, 0.028
    t = np.linspace(0, 1, 61)
    r = radius * np.sin(np.pi * t) ** 0.7
    profile = np.column_stack([r, length * t])
    profile[0, 0] = profile[-1, 0] = 0.0
    return base.revolve(profile, 48), lambda p: sdf_revolve(p, profile)


def capsule_torch():
    radius, length = 0.015, 0.130
    bottom = base.arc((0.0, radius), radius, -90, 0, 12)
    top = base.arc((0.0, length - radius), radius, 0, 90, 12)
    return base.revolve(base.refine(base.polyline(bottom, top), 0.005), 48), None


def traffic_cone():
    profile = base.polyline((0.0, 0.0), (0.040, 0.0), (0.040, 0.006), (0.030, 0.006), (0.007, 0.090),
                            (0.0, 0.090))
    return base.revolve(base.refine(profile, 0.005), 64), None


def cork():
    return base.revolve(base.refine(frustum_profile(0.017, 0.014, 0.040, 0.0015), 0.004), 48), None


def hex_bar():
    return base.extrude(regular_polygon(6, 0.022), 0.150), None


def toblerone():
    edge = 0.035
    triangle = np.array([(-edge / 2, 0.0), (edge / 2, 0.0), (0.0, edge * math.sqrt(3) / 2)])
    return base.extrude(triangle, 0.200), None


def marker_profile():
    """Marker along z: conical tip, Ø 17 mm barrel, Ø 19 mm cap with a rounded end."""
    barrel, cap, length = 0.0085, 0.0095, 0.130
    return base.polyline((0.0, 0.0), (0.002, 0.0), (0.004, 0.004), (barrel, 0.016), (barrel, 0.085),
                         (cap, 0.085), (cap, length - cap * 0.5),
                         base.arc((0.0, length - cap * 0.5), cap, 0, 90, 10)[1:])


def marker():
    profile = base.refine(marker_profile(), 0.004)
    body = base.revolve(profile, 48)
    # A pocket clip along the cap, its foot sunk 0.5 mm into the cap.
    clip_outline = np.array([(-0.002, 0.0), (0.002, 0.0), (0.002, 0.0015), (-0.002, 0.0015)])
    clip = base.extrude(clip_outline, 0.038).transformed(offset=(0.0, 0.009, 0.090))
    clip_sdf = transformed_sdf(lambda p: sdf_extrude(p, clip_outline, 0.038), offset=(0.0, 0.009, 0.090))
    return body + clip, union(lambda p: sdf_revolve(p, profile), clip_sdf)


def clamp_outline():
    """C-frame of a small clamp in the (u, v) plane, 12 x 10 mm arms."""
    return np.array([(0.0, 0.0), (0.060, 0.0), (0.060, 0.012), (0.012, 0.012), (0.012, 0.068),
                     (0.075, 0.068), (0.075, 0.080), (0.0, 0.080)])


def clamp():
    outline, depth = clamp_outline(), 0.010
    frame = base.extrude(outline, depth)
    # The screw: a Ø 8 mm rod through the lower arm's end, with a T handle.
    screw_profile = base.refine(np.array([(0.0, -0.030), (0.004, -0.030), (0.004, 0.050), (0.0, 0.050)]), 0.005)
    screw_pose = dict(rotation=base.X_QUARTER_TURN.T, offset=(0.050, 0.0, depth / 2))  # axis along +v
    screw = base.revolve(screw_profile, 24).transformed(**screw_pose)
    handle_profile = base.refine(np.array([(0.0, -0.025), (0.003, -0.025), (0.003, 0.025), (0.0, 0.025)]), 0.005)
    handle_pose = dict(rotation=base.Y_QUARTER_TURN, offset=(0.050, -0.027, depth / 2))  # along u
    handle = base.revolve(handle_profile, 24).transformed(**handle_pose)
    sdf = union(lambda p: sdf_extrude(p, outline, depth),
                transformed_sdf(lambda p: sdf_revolve(p, screw_profile), **screw_pose),
                transformed_sdf(lambda p: sdf_revolve(p, handle_profile), **handle_pose))
    return frame + screw + handle, sdf


def banana():
    """A curved, tapering tube: an arc of radius 14 cm over 90 degrees."""
    bend, sweep, thickest = 0.140, math.radians(90), 0.018
    s = np.linspace(0, 1, 49)
    angles = -sweep / 2 + sweep * s
    centerline = np.column_stack([bend * np.sin(angles), 0 * s, bend * (1 - np.cos(angles))])
    radii = thickest * np.sin(np.pi * s) ** 0.6
    radii[0] = radii[-1] = 0.0
    return tapered_tube(centerline, radii, 32), lambda p: sdf_tube(p, centerline, radii)


def padlock():
    width, thickness, height, corner = 0.040, 0.018, 0.045, 0.005
    body_outline = base.rounded_rectangle(width, thickness, corner, 6)
    body = base.extrude(body_outline, height)
    # The shackle: a U of 3.5 mm wire, legs 26 mm apart, sunk 6 mm into the body.
    legs, wire, top = 0.013, 0.0035, 0.068
    phi = np.linspace(np.pi, 0, 33)
    arc = np.column_stack([legs * np.cos(phi), 0 * phi, top - legs + legs * np.sin(phi)])
    leg_left = np.column_stack([np.full(8, -legs), np.zeros(8), np.linspace(height - 0.006, top - legs, 8)])
    centerline = np.vstack([leg_left[:-1], arc, leg_left[::-1][1:] * [-1, 1, 1]])
    tangents = np.gradient(centerline, axis=0)
    shackle = base.sweep_tube(centerline, tangents, wire, 20)
    return body + shackle, union(lambda p: sdf_extrude(p, body_outline, height),
                                 lambda p: sdf_tube(p, centerline, wire))


def tumbler():
    """Tall thin-walled glass, slightly tapered, no handle."""
    outer = base.polyline(base.arc((0.030 - 0.004, 0.004), 0.004, -90, 0, 6), (0.035, 0.120))
    return base.revolve(base.refine(base.vessel_profile(outer, 0.0025, 0.006), 0.005), 72), None


def espresso_profile():
    """Straight 4 mm wall on a rounded foot, an 8 mm floor."""
    outer = base.polyline(base.arc((0.023, 0.005), 0.005, -90, 0, 6), (0.028, 0.055))
    return base.refine(base.vessel_profile(outer, 0.004, 0.008), 0.003)


def espresso_cup():
    """Small thick cup with a small ring handle, its ends sunk 3.5 mm into
    the 4 mm wall (as the bundled mug's)."""
    profile = espresso_profile()
    outer_r, sunk, reach, half_height, z_mid, wire = 0.028, 0.0035, 0.016, 0.014, 0.031, 0.0035
    phi = np.linspace(-np.pi / 2, np.pi / 2, 65)
    a = sunk + reach
    centerline = np.column_stack([outer_r - sunk + a * np.cos(phi), 0 * phi, z_mid + half_height * np.sin(phi)])
    tangents = np.column_stack([-a * np.sin(phi), 0 * phi, half_height * np.cos(phi)])
    handle = base.sweep_tube(centerline, tangents, wire, 24)
    base.check_inside(np.hypot(handle.vertices[:, 0], handle.vertices[:, 1]),
                      lambda r: r >= outer_r - 0.004 + 0.0002, "espresso cup handle pokes into the cavity")
    return base.revolve(profile, 64) + handle, union(lambda p: sdf_revolve(p, profile),
                                                     lambda p: sdf_tube(p, centerline, wire))


def spray_profile():
    body_r, neck_r = 0.033, 0.013
    s = np.linspace(0, 1, 13)
    shoulder = np.column_stack([neck_r + (body_r - neck_r) * (1 + np.cos(np.pi * s)) / 2, 0.095 + 0.025 * s])
    return base.refine(base.polyline((0.0, 0.0), base.arc((body_r - 0.005, 0.005), 0.005, -90, 0, 6), shoulder,
                                     (neck_r, 0.135), (0.0, 0.135)), 0.005)


def spray_bottle():
    """Bottle, trigger head (a block), nozzle and trigger plate, all overlapping."""
    profile = spray_profile()
    head_outline = base.rounded_rectangle(0.048, 0.028, 0.006, 4)
    head_pose = dict(offset=(0.010, 0.0, 0.130))
    nozzle_profile = base.refine(np.array([(0.0, 0.0), (0.005, 0.0), (0.005, 0.015), (0.0, 0.015)]), 0.005)
    nozzle_pose = dict(rotation=base.Y_QUARTER_TURN, offset=(0.030, 0.0, 0.148))
    trigger_outline = np.array([(-0.003, -0.010), (0.003, -0.010), (0.003, 0.010), (-0.003, 0.010)])
    trigger_pose = dict(offset=(0.026, 0.0, 0.112))  # hangs free in front of the neck
    parts = [base.revolve(profile, 48),
             base.extrude(head_outline, 0.032).transformed(**head_pose),
             base.revolve(nozzle_profile, 16).transformed(**nozzle_pose),
             base.extrude(trigger_outline, 0.024).transformed(**trigger_pose)]
    sdf = union(lambda p: sdf_revolve(p, profile),
                transformed_sdf(lambda p: sdf_extrude(p, head_outline, 0.032), **head_pose),
                transformed_sdf(lambda p: sdf_revolve(p, nozzle_profile), **nozzle_pose),
                transformed_sdf(lambda p: sdf_extrude(p, trigger_outline, 0.024), **trigger_pose))
    mesh = parts[0]
    for part in parts[1:]:
        mesh = mesh + part
    return mesh, sdf


def book():
    return base.extrude(base.rounded_rectangle(0.190, 0.130, 0.002, 3), 0.018), None


def bolt():
    head = base.extrude(regular_polygon(6, 0.019, phase=math.pi / 6), 0.008)  # a flat at +u: lies on it
    shaft_profile = base.polyline((0.0, 0.0), (0.006, 0.0), (0.006, 0.069), (0.0048, 0.070), (0.0, 0.070))
    shaft = base.revolve(base.refine(shaft_profile, 0.005), 32).transformed(offset=(0.0, 0.0, 0.0075))
    return head + shaft, None


def dumbbell():
    end = base.extrude(regular_polygon(6, 0.050, phase=math.pi / 6), 0.032)
    bar_profile = base.refine(np.array([(0.0, 0.0), (0.013, 0.0), (0.013, 0.100), (0.0, 0.100)]), 0.005)
    bar = base.revolve(bar_profile, 32).transformed(offset=(0.0, 0.0, 0.027))
    return end + bar + end.transformed(offset=(0.0, 0.0, 0.122)), None


def wedge():
    return base.extrude(np.array([(0.0, 0.0), (0.120, 0.0), (0.0, 0.030)]), 0.040), None


def light_bulb():
    base_r, bulb_r = 0.0135, 0.030
    profile = base.polyline((0.0, 0.0), (0.008, 0.0), (base_r, 0.004), (base_r, 0.025), (0.016, 0.032),
                            base.arc((0.0, 0.075), bulb_r, -60, 90, 30))
    return base.revolve(base.refine(profile, 0.004), 64), None


# --------------------------------------------------------------------------
# Scans: marching tetrahedra over an SDF, noise, damage


def _kuhn_tetrahedra():
    """The six tetrahedra of a cube around its diagonal 0 -> 7 (corner bits
    x = 1, y = 2, z = 4): the same split in every cube, so the
    tetrahedra of neighbouring cubes share faces."""
    out = []
    for a, b, _ in itertools.permutations((1, 2, 4)):
        out.append((0, a, a + b, 7))
    return np.array(out)


def marching_tetrahedra(values, origin, spacing):
    """Outward-wound surface where the grid's piecewise-linear interpolant
    crosses 0 (negative inside). No value may be 0."""
    nx, ny, nz = values.shape
    node = np.arange(values.size).reshape(values.shape)
    corners = [(dx, dy, dz) for dz in (0, 1) for dy in (0, 1) for dx in (0, 1)]
    cube = np.stack([node[dx:nx - 1 + dx, dy:ny - 1 + dy, dz:nz - 1 + dz].ravel() for dx, dy, dz in corners], 1)
    tets = cube[:, _kuhn_tetrahedra()].reshape(-1, 4)
    f = values.ravel()
    inside = f[tets] < 0
    count = inside.sum(axis=1)
    tets, inside, count = tets[(count > 0) & (count < 4)], inside[(count > 0) & (count < 4)], count[(count > 0) & (count < 4)]
    position = origin + spacing * np.stack(np.unravel_index(np.arange(values.size), values.shape), 1)

    edges, triangles = [], []  # crossing edges as node pairs; triangles as indices into edges
    def add(pairs_per_triangle):
        start = sum(len(e) for e in edges)
        edges.append(pairs_per_triangle.reshape(-1, 2))
        triangles.append(start + np.arange(pairs_per_triangle.shape[0] * 3).reshape(-1, 3))

    order = np.argsort(~inside, axis=1, kind="stable")  # inside vertices first
    t = np.take_along_axis(tets, order, axis=1)
    one, three, two = count == 1, count == 3, count == 2
    lone = np.where(one[:, None], t[:, [0]], t[:, [3]])  # the vertex alone on its side
    rest = np.where(one[:, None], t[:, 1:], t[:, :3])
    single = one | three
    add(np.stack([np.stack([lone[single, 0], rest[single, k]], 1) for k in range(3)], 1))
    a, b, c, d = (t[two, k] for k in range(4))  # a, b inside
    quad = np.stack([np.stack(e, 1) for e in ((a, c), (a, d), (b, d), (b, c))], 1)
    add(quad[:, [0, 1, 2]])
    add(quad[:, [0, 2, 3]])

    pairs = np.sort(np.vstack(edges), axis=1)
    keys, vertex_of = np.unique(pairs[:, 0] * values.size + pairs[:, 1], return_inverse=True)
    u, v = keys // values.size, keys % values.size
    w = f[u] / (f[u] - f[v])
    vertices = position[u] + w[:, None] * (position[v] - position[u])
    faces = vertex_of[np.vstack(triangles)]
    # Outward: along the gradient, from the inside nodes to the outside ones.
    p = vertices[faces]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    tet_of = np.concatenate([np.flatnonzero(single), np.flatnonzero(two), np.flatnonzero(two)])
    tet_nodes, tet_inside = t[tet_of], np.take_along_axis(inside, order, axis=1)[tet_of]
    pos = position[tet_nodes]
    gradient = (np.where(~tet_inside[..., None], pos, 0).sum(1) / (~tet_inside).sum(1, keepdims=True)
                - np.where(tet_inside[..., None], pos, 0).sum(1) / tet_inside.sum(1, keepdims=True))
    flip = np.einsum("ij,ij->i", normal, gradient) < 0
    faces[flip] = faces[flip][:, ::-1]
    return Mesh(vertices, faces)


def remesh(sdf, lo, hi, spacing):
    """Marching tetrahedra of `sdf` on a grid covering lo..hi. Grid values
    are kept at least 5 % of a spacing from 0, which keeps the triangles
    from collapsing where the surface passes near a node."""
    lo, hi = np.asarray(lo) - 2 * spacing, np.asarray(hi) + 2 * spacing
    dims = np.ceil((hi - lo) / spacing).astype(int) + 1
    axes = [lo[k] + spacing * np.arange(dims[k]) for k in range(3)]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    values = np.concatenate([sdf(chunk) for chunk in np.array_split(points, max(1, len(points) // 20000))])
    floor = 0.05 * spacing
    values = np.where(np.abs(values) < floor, np.where(values < 0, -floor, floor), values)
    return marching_tetrahedra(values.reshape(dims), lo, spacing)


def scan_of(sdf, clean, rng):
    """About SCAN_TRIANGLES triangles of the solid, with noise."""
    lo, hi = clean.vertices.min(0), clean.vertices.max(0)
    area = np.linalg.norm(base.triangle_normals(clean), axis=1).sum() / 2
    spacing = math.sqrt(2.2 * area / SCAN_TRIANGLES)
    for _ in range(4):  # triangles go as 1 / spacing^2
        mesh = remesh(sdf, lo, hi, spacing)
        if abs(len(mesh.faces) / SCAN_TRIANGLES - 1) < 0.04:
            break
        spacing *= math.sqrt(len(mesh.faces) / SCAN_TRIANGLES)
    normals = np.zeros_like(mesh.vertices)
    for k in range(3):
        np.add.at(normals, mesh.faces[:, k], base.triangle_normals(mesh))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    noisy = mesh.vertices + rng.normal(0.0, SCAN_NOISE, (len(mesh.vertices), 1)) * normals
    return Mesh(noisy, mesh.faces)


@dataclass
class Damage:
    """What damage() did, to be found again in the written mesh."""

    holes: int = 0  # triangles removed
    slivers: int = 0  # zero-area triangles (each leaves a 3-edge crack once dropped)
    flaps: int = 0  # debris triangles on an edge (one non-manifold edge each)


def _edge_owner(faces):
    owner = {}
    for t, face in enumerate(faces):
        for k in range(3):
            owner[(int(face[k]), int(face[(k + 1) % 3]))] = t
    return owner


def _neighbours(faces, owner, t):
    a, b, c = faces[t]
    return [owner.get((b, a)), owner.get((c, b)), owner.get((a, c))]


def _pick(faces, owner, rng, touched, count):
    """`count` triangles whose vertices, and their neighbours' vertices, no
    earlier damage touched (so each damage stays exactly what it is)."""
    picked = []
    for t in rng.permutation(len(faces)):
        around = [t] + _neighbours(faces, owner, t)
        if None in around:
            continue
        vertices = {v for n in around for v in faces[n]}
        if vertices & touched:
            continue
        touched |= vertices
        picked.append(int(t))
        if len(picked) == count:
            return picked
    raise MeshError("no room left for the scan damage")


def damage(mesh, rng):
    """Holes of one and of three triangles, two T-junctions closed by
    zero-area triangles, and a flap on one edge, apart from each other."""
    vertices, faces = mesh.vertices.copy(), [tuple(int(v) for v in f) for f in mesh.faces]
    owner, touched, done = _edge_owner(faces), set(), Damage()
    slivers, flap, single, patch = (_pick(faces, owner, rng, touched, n) for n in (2, 1, 1, 1))
    removed = set(single) | set(patch) | set(_neighbours(faces, owner, patch[0])[:2])
    done.holes = len(removed)
    kept = [f for i, f in enumerate(faces) if i not in removed]
    # T-junctions: triangle (a, b, c) split at the exact middle m of (a, b);
    # the crack is closed by (a, b, m), of zero area in float32.
    for t in slivers:
        a, b, c = faces[t]
        vertices[[a, b]] = np.round(vertices[[a, b]] / SNAP) * SNAP
        m = len(vertices)
        vertices = np.vstack([vertices, (vertices[a] + vertices[b]) / 2])
        kept[kept.index(faces[t])] = (a, m, c)
        kept += [(m, b, c), (a, b, m)]
        done.slivers += 1
    # A flap: a triangle on an edge, its tip 0.3 mm out of the surface.
    a, b, c = faces[flap[0]]
    normal = np.cross(vertices[b] - vertices[a], vertices[c] - vertices[a])
    vertices = np.vstack([vertices, (vertices[a] + vertices[b]) / 2 + 0.0003 * normal / np.linalg.norm(normal)])
    kept.append((a, b, len(vertices) - 1))
    done.flaps += 1
    return Mesh(vertices, np.array(kept)), done


def check_damage(mesh, expected):
    """Raise MeshError unless the float32 mesh has exactly the damage done:
    the zero-area triangles, and as edge uses: one boundary crack of three
    edges per sliver once dropped, the holes' rims, one non-manifold edge
    per flap."""
    p = mesh.vertices[mesh.faces]
    zero = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1) == 0
    if zero.sum() != expected.slivers:
        raise MeshError(f"{zero.sum()} zero-area triangles, expected {expected.slivers}")
    faces = mesh.faces[~zero]  # what the loader keeps
    uses = {}
    for f in faces:
        for k in range(3):
            key = tuple(sorted((int(f[k]), int(f[(k + 1) % 3]))))
            uses[key] = uses.get(key, 0) + 1
    counts = np.array(list(uses.values()))
    if (counts > 2).sum() != expected.flaps:
        raise MeshError(f"{(counts > 2).sum()} non-manifold edges, expected {expected.flaps}")
    # A hole of one triangle has a rim of 3 edges, of three adjacent ones 5;
    # a flap adds 2 boundary edges, a dropped sliver 3.
    boundary = 3 + 5 + 2 * expected.flaps + 3 * expected.slivers
    if (counts == 1).sum() != boundary:
        raise MeshError(f"{(counts == 1).sum()} boundary edges, expected {boundary}")


# --------------------------------------------------------------------------


LIE_ALONG_X = base.Y_QUARTER_TURN  # z -> x: a revolved or extruded part lies down
PRISM_ON_FACE = base.PRISM_ALONG_X  # extrude's (u, v, w) -> (y, z, x)
FLAT = base.X_QUARTER_TURN  # y -> z, z -> -y


@dataclass
class HeldOut:
    name: str
    build: object
    file_name: str
    writer: object
    density: float  # kg/m^3
    pose: object = None  # rotation laying the construction frame on the table
    scan: bool = False  # also write <name>_scan.ply


OBJECTS = [
    HeldOut("soap_bar", soap_bar, "soap_bar.ply", base.ply_binary, 1100.0),
    HeldOut("dice", dice, "dice.obj", base.obj_text, 1200.0),
    HeldOut("lemon", lemon, "lemon.stl", base.stl_binary, 950.0, LIE_ALONG_X, scan=True),
    HeldOut("capsule_torch", capsule_torch, "capsule_torch.stl", base.stl_binary, 1500.0, LIE_ALONG_X),
    HeldOut("traffic_cone", traffic_cone, "traffic_cone.ply", base.ply_binary, 300.0),
    HeldOut("cork", cork, "cork.stl", base.stl_ascii, 240.0),
    HeldOut("hex_bar", hex_bar, "hex_bar.obj", base.obj_text, 700.0, PRISM_ON_FACE),
    HeldOut("toblerone", toblerone, "toblerone.stl", base.stl_binary, 650.0, PRISM_ON_FACE),
    HeldOut("marker", marker, "marker.ply", base.ply_binary, 600.0, LIE_ALONG_X, scan=True),
    HeldOut("clamp", clamp, "clamp.obj", base.obj_text, 7850.0, scan=True),
    HeldOut("banana", banana, "banana.ply", base.ply_binary, 950.0, FLAT, scan=True),
    HeldOut("padlock", padlock, "padlock.stl", base.stl_binary, 6000.0, scan=True),
    HeldOut("tumbler", tumbler, "tumbler.obj", base.obj_text, 2500.0),
    HeldOut("espresso_cup", espresso_cup, "espresso_cup.ply", base.ply_binary, 2400.0, scan=True),
    HeldOut("spray_bottle", spray_bottle, "spray_bottle.stl", base.stl_binary, 1000.0, scan=True),
    HeldOut("book", book, "book.stl", base.stl_binary, 750.0),
    HeldOut("bolt", bolt, "bolt.obj", base.obj_text, 7850.0, LIE_ALONG_X),
    HeldOut("dumbbell", dumbbell, "dumbbell.ply", base.ply_binary, 7200.0, LIE_ALONG_X),
    HeldOut("wedge", wedge, "wedge.stl", base.stl_ascii, 1200.0, FLAT),
    HeldOut("light_bulb", light_bulb, "light_bulb.ply", base.ply_binary, 250.0),
]


def float32(mesh):
    """What the files hold: float32 coordinates."""
    return Mesh(mesh.vertices.astype(np.float32).astype(np.float64), mesh.faces)


def placed(mesh, pose):
    return (mesh if pose is None else mesh.transformed(pose)).standing_on_floor()


def build_all():
    """[(file name, bytes, summary line)] of every object, checked."""
    files = []
    for item in OBJECTS:
        try:
            mesh, sdf = item.build()
            clean = float32(placed(mesh, item.pose))
            report = base.check_mesh(clean)
            files.append(output(item.name, item.file_name, item.writer, clean, report, item.density))
            if item.scan:
                rng = np.random.default_rng(zlib.crc32(item.name.encode()))
                scan = float32(placed(scan_of(sdf, mesh, rng), item.pose))
                scan_report = base.check_mesh(scan)
                damaged, done = damage(scan, rng)
                damaged = float32(damaged)
                check_damage(damaged, done)
                files.append(output(item.name + "_scan", item.name + "_scan.ply", base.ply_binary, damaged,
                                    scan_report, item.density, done))
        except MeshError as error:
            raise MeshError(f"'{item.name}': {error}") from error
    return files


def output(name, file_name, writer, mesh, report, density, done=None):
    lo, hi = mesh.vertices.min(axis=0) * 100, mesh.vertices.max(axis=0) * 100
    size = " x ".join(f"{v:.1f}" for v in hi - lo)
    volume = report.volumes.sum()
    line = (f"{name:<17} {file_name:<22} triangles {len(mesh.faces):6d}  size {size:>17} cm  "
            f"volume {volume * 1e6:7.1f} cm^3  density {density:6.0f}  mass {volume * density * 1000:7.1f} g")
    if done is not None:
        line += f"  damage: {done.holes} triangles removed, {done.slivers} slivers, {done.flaps} flap"
    sidecar = (json.dumps({"density": density}) + "\n").encode("ascii")
    return [(file_name, writer(mesh, name)), (Path(file_name).stem + ".json", sidecar)], line


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, metavar="DIR", default=Path(__file__).resolve().parent / "meshes",
                        help="output folder (default: meshes/ next to this script)")
    args = parser.parse_args(argv)
    try:
        built = build_all()
    except MeshError as error:
        print(f"generate_heldout: {error}; nothing written", file=sys.stderr)
        return 1
    args.out.mkdir(parents=True, exist_ok=True)
    for files, line in built:
        for file_name, data in files:
            base.write_atomically(args.out / file_name, data)
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
