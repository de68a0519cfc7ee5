#!/usr/bin/python3
"""Renders a binary glTF (.glb) written by `hfts-preprocess --export-scene`
to a PNG from a few viewpoints, so a scene and the robot's posture can be
checked without a 3-D viewer. Uses Debian's python3-numpy and
python3-matplotlib:

    scripts/render_glb.py scene.glb scene.png [--views 3]
"""
import argparse
import json
import struct
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

COMPONENTS = {5126: ("<f4", 4), 5125: ("<u4", 4), 5123: ("<u2", 2), 5121: ("<u1", 1)}
SIZES = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}


def read_glb(path):
    data = open(path, "rb").read()
    magic, _, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or length != len(data):
        sys.exit(f"{path}: not a binary glTF file")
    offset, doc, binary = 12, None, b""
    while offset < length:
        size, kind = struct.unpack_from("<I4s", data, offset)
        chunk = data[offset + 8: offset + 8 + size]
        if kind == b"JSON":
            doc = json.loads(chunk)
        elif kind == b"BIN\x00":
            binary = chunk
        offset += 8 + size
    return doc, binary


def accessor(doc, binary, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    dtype, _ = COMPONENTS[acc["componentType"]]
    count, width = acc["count"], SIZES[acc["type"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    values = np.frombuffer(binary, dtype=dtype, count=count * width, offset=start)
    return values.reshape(count, width) if width > 1 else values


def triangles(doc, binary):
    """Yields (triangles as (n, 3, 3) world points, rgb) for every primitive."""
    def walk(node_index, parent):
        node = doc["nodes"][node_index]
        local = np.array(node.get("matrix", np.eye(4).flatten()), dtype=float).reshape(4, 4).T
        world = parent @ local
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                points = accessor(doc, binary, prim["attributes"]["POSITION"]).astype(float)
                points = points @ world[:3, :3].T + world[:3, 3]
                faces = accessor(doc, binary, prim["indices"]).reshape(-1, 3)
                material = doc["materials"][prim.get("material", 0)]
                rgb = material.get("pbrMetallicRoughness", {}).get("baseColorFactor", [0.7] * 3)[:3]
                yield points[faces], rgb
        for child in node.get("children", []):
            yield from walk(child, world)

    for root in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        yield from walk(root, np.eye(4))


def subdivided(tris, max_edge):
    """Splits triangles until no edge exceeds max_edge, so matplotlib's
    per-polygon depth sort does not let a table top cover what stands on it."""
    out = []
    pending = list(tris)
    while pending:
        t = pending.pop()
        edges = [np.linalg.norm(t[(k + 1) % 3] - t[k]) for k in range(3)]
        k = int(np.argmax(edges))
        if edges[k] <= max_edge:
            out.append(t)
            continue
        a, b, c = t[k], t[(k + 1) % 3], t[(k + 2) % 3]
        m = (a + b) / 2
        pending.extend([np.array([a, m, c]), np.array([m, b, c])])
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("glb")
    parser.add_argument("png")
    parser.add_argument("--views", type=int, default=3)
    parser.add_argument("--center", type=float, nargs=3, help="zoom: centre of the view (m)")
    parser.add_argument("--radius", type=float, default=0.15, help="zoom: half-width (m)")
    args = parser.parse_args()
    doc, binary = read_glb(args.glb)
    parts = list(triangles(doc, binary))
    # glTF is y-up; turn back to the scene's z-up for plotting.
    to_z_up = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], dtype=float)
    parts = [(tris @ to_z_up.T, rgb) for tris, rgb in parts]
    every = np.concatenate([t.reshape(-1, 3) for t, _ in parts])
    low, high = every.min(axis=0), every.max(axis=0)
    if args.center is not None:
        low, high = np.array(args.center) - args.radius, np.array(args.center) + args.radius
        parts = [(t[np.any((t >= low).all(axis=2) & (t <= high).all(axis=2), axis=1)], c)
                 for t, c in parts]
    max_edge = 0.03 * np.linalg.norm(high - low)
    faces, colours = [], []
    for tris, rgb in parts:
        for t in subdivided(tris, max_edge):
            faces.append(t)
            colours.append(rgb)
    views = [(25, -60), (25, 210), (20, 30), (80, -90), (5, -90)][: args.views]
    fig = plt.figure(figsize=(6 * len(views), 6))
    for i, (elev, azim) in enumerate(views):
        ax = fig.add_subplot(1, len(views), i + 1, projection="3d")
        # One collection, so all faces are depth-sorted together.
        ax.add_collection3d(Poly3DCollection(faces, facecolor=colours, edgecolor=(0, 0, 0, 0.05),
                                             linewidth=0.1))
        ax.set_xlim(low[0], high[0]), ax.set_ylim(low[1], high[1]), ax.set_zlim(low[2], high[2])
        ax.set_box_aspect(high - low)
        ax.view_init(elev, azim)
        ax.set_xlabel("x"), ax.set_ylabel("y"), ax.set_zlabel("z")
    fig.tight_layout()
    fig.savefig(args.png, dpi=70)


if __name__ == "__main__":
    main()
