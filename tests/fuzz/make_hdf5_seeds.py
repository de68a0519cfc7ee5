#!/usr/bin/python3
"""Writes the HDF5 seeds of the fuzz corpora (run with Debian's python3).

corpus/object_database/: tiny databases of three bundled meshes, built by
hfts-preprocess with few samples, a 4-2 hierarchy and a coarse distance grid. corpus/hand_map/: the
first rows of a built hand map, rewritten the way hfts_db writes files
(HDF5 1.10 format, chunked, Fletcher32, no timestamps), so that it still
loads. Usage: make_hdf5_seeds.py BUILD_DIR (with bin/hfts-preprocess and
databases/kr5_sdh_hand_map.h5, i.e. after scripts/demo.sh).
"""
import pathlib
import subprocess
import sys
import tempfile

import h5py

HERE = pathlib.Path(__file__).resolve().parent
SOURCE = HERE.parent.parent
MESHES = ["small_cube.stl", "tile.obj", "l_bracket.ply"]
HAND_MAP_ROWS = 32


def object_databases(build: pathlib.Path) -> None:
    out = HERE / "corpus" / "object_database"
    for mesh in MESHES:
        subprocess.run([build / "bin" / "hfts-preprocess", SOURCE / "objects" / "meshes" / mesh,
                        "-o", out, "--max-samples", "300", "--sample-density", "2000000",
                        "--min-neighbours", "2", "--branching", "4", "2",
                        "--distance-grid-spacing", "0.01", "--distance-grid-margin", "0.005",
                        "-q"], check=True)


def copy_attributes(source, target) -> None:
    for name in source.attrs:
        target.attrs.create(name, source.attrs[name], dtype=source.attrs.get_id(name).dtype)


def copy_group(source, target, rows: int) -> None:
    copy_attributes(source, target)
    for name, item in source.items():
        if isinstance(item, h5py.Group):
            copy_group(item, target.create_group(name, track_order=False), rows)
            continue
        data = item[:rows]
        dataset = target.create_dataset(name, data=data, chunks=data.shape, fletcher32=True,
                                        track_times=False)
        copy_attributes(item, dataset)


def hand_map(build: pathlib.Path) -> None:
    source = build / "databases" / "kr5_sdh_hand_map.h5"
    target = HERE / "corpus" / "hand_map" / f"kr5_sdh_{HAND_MAP_ROWS}.h5"
    target.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(source, "r") as src, h5py.File(target, "w", libver=("v110", "v110"),
                                                  track_order=False) as dst:
        copy_group(src, dst, HAND_MAP_ROWS)
        dst["parameters"].attrs.modify("num_samples", HAND_MAP_ROWS)


if __name__ == "__main__":
    build_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else SOURCE / "build")
    object_databases(build_dir)
    hand_map(build_dir)
