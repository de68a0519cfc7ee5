#!/usr/bin/env python3
"""End-to-end tests of the hfts-preprocess command line and of the h5py
example in docs/database.md. Run by ctest with Debian's /usr/bin/python3."""

import argparse
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

BINARY = None
SOURCE_DIR = None


def run(*args, check=None):
    result = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True, timeout=240)
    if check is not None:
        assert result.returncode == check, (result.returncode, result.stdout, result.stderr)
    return result


class PreprocessCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-cli-")
        cls.meshes = os.path.join(SOURCE_DIR, "objects", "meshes")
        cls.out = os.path.join(cls.tmp, "db")
        cls.build = run(cls.meshes, "-o", cls.out, "-j", "2")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def assert_usage_errors(self, mesh, out, cases):
        """Each (option, value) is a usage error (exit 2) naming the option."""
        for option, value in cases:
            result = run(mesh, "-o", out, option, value)
            self.assertEqual(result.returncode, 2, (option, value))
            self.assertIn(option, result.stderr)

    def test_directory_builds_every_bundled_object_with_a_summary(self):
        self.assertEqual(self.build.returncode, 0, self.build.stderr)
        # The sidecars (kettlebell.json, washer.json) are not meshes.
        names = sorted(os.path.splitext(f)[0] for f in os.listdir(self.meshes)
                       if not f.endswith(".json"))
        self.assertEqual(sorted(os.path.splitext(f)[0] for f in os.listdir(self.out)), names)
        self.assertIn("nodes per level", self.build.stdout)
        for name in names:
            self.assertRegex(self.build.stdout,
                             rf"{name}\s+\d+\s+\d+\s+20/80/\d+\s+\d+\s+[\d.]+\s+[\d.]+\s+ok")
        self.assertRegex(self.build.stdout, r"box\s+\d+\s+\d+\s+20/80/\d+\s+1\s")
        self.assertIn(f"{len(names)} built, 0 failed", self.build.stdout)

    def test_inspect_json_has_the_documented_keys(self):
        result = run("--inspect", os.path.join(self.out, "mug.h5"), "--json", check=0)
        summary = json.loads(result.stdout)
        self.assertEqual(summary["branching"], [20, 4, 4])
        self.assertEqual(summary["format_version"], 4)
        parts = summary["convex_parts"]
        self.assertGreater(parts["count"], 10)  # the mug is far from convex
        self.assertGreaterEqual(parts["volume_ratio"], 1.0 - 1e-9)  # the parts cover the solid
        self.assertLessEqual(parts["volume_ratio"], 1.05)
        self.assertEqual(summary["density"], 1000.0)
        self.assertAlmostEqual(summary["mass"], 1000.0 * summary["volume"])
        self.assertEqual(summary["parameters"]["convex_parts_max"], 1024)
        grid = summary["distance_grid"]
        self.assertTrue(grid["signed"])
        self.assertEqual(len(grid["dims"]), 3)
        self.assertLessEqual(grid["dims"][0] * grid["dims"][1] * grid["dims"][2], 1 << 18)
        self.assertEqual(summary["parameters"]["distance_grid_margin"], 0.03)
        self.assertEqual(summary["nodes_per_level"][:2], [20, 80])
        self.assertGreater(summary["num_contacts"], 1000)
        self.assertEqual(len(summary["center_of_mass"]), 3)
        self.assertGreater(summary["rho"], 0.04)
        text = run("--inspect", os.path.join(self.out, "mug.h5"), check=0).stdout
        self.assertIn("nodes per level 20 / 80 /", text)
        self.assertRegex(text, r"convex parts    \d+, their volumes 1\.0\d* x the solid's")
        self.assertRegex(text, r"density         1000 kg/m\^3 \(mass 1\d\d(\.\d+)? g\)")

    def test_the_bundled_sidecars_set_the_density_of_their_objects(self):
        for name, density in (("kettlebell", 7200.0), ("washer", 7850.0), ("mug", 1000.0)):
            summary = json.loads(run("--inspect", os.path.join(self.out, name + ".h5"), "--json",
                                     check=0).stdout)
            self.assertEqual(summary["density"], density, name)

    def test_density_comes_from_the_option_unless_a_sidecar_says_otherwise(self):
        src = os.path.join(self.tmp, "dense")
        os.makedirs(src)
        for mesh in ("box.stl", "l_bracket.ply"):
            shutil.copy(os.path.join(self.meshes, mesh), src)
        with open(os.path.join(src, "l_bracket.json"), "w") as f:
            json.dump({"density": 2700}, f)
        out = os.path.join(self.tmp, "dense-out")
        result = run(src, "-o", out, "--density", "1200", check=0)
        self.assertIn("2 built, 0 failed", result.stdout)  # the sidecar is no mesh
        density = {name: json.loads(run("--inspect", os.path.join(out, name + ".h5"), "--json",
                                        check=0).stdout)["density"]
                   for name in ("box", "l_bracket")}
        self.assertEqual(density, {"box": 1200.0, "l_bracket": 2700.0})

    def test_a_bad_sidecar_fails_its_object_naming_the_file_and_the_key(self):
        cases = [({"density": -5}, "density: must be in [10, 25000] kg/m^3, got -5"),
                 ({"density": "heavy"}, "density: must be a number (kg/m^3), got \"heavy\""),
                 ({"densty": 900}, "densty: unknown key (a sidecar may hold: density)"),
                 ([2300], "must be a JSON object")]
        for content, message in cases:
            src = os.path.join(self.tmp, "sidecar-" + str(len(os.listdir(self.tmp))))
            os.makedirs(src)
            shutil.copy(os.path.join(self.meshes, "box.stl"), src)
            with open(os.path.join(src, "box.json"), "w") as f:
                json.dump(content, f)
            result = run(src, "-o", os.path.join(src, "out"))
            self.assertEqual(result.returncode, 1, content)
            self.assertIn("sidecar '" + os.path.join(src, "box.json") + "'", result.stderr)
            self.assertIn(message, result.stderr)
            self.assertIn("0 built, 1 failed", result.stdout)
        with open(os.path.join(src, "box.json"), "w") as f:
            f.write("{density: 2300")
        self.assertIn("is not valid JSON", run(src, "-o", os.path.join(src, "out")).stderr)

    def test_convex_part_options_are_stored_and_checked(self):
        out = os.path.join(self.tmp, "parts")
        torus = os.path.join(self.meshes, "torus.stl")
        run(torus, "-o", out, "--convex-parts-max", "4", "--convex-parts-tolerance", "0.5",
            check=0)
        summary = json.loads(run("--inspect", os.path.join(out, "torus.h5"), "--json",
                                 check=0).stdout)
        self.assertLessEqual(summary["convex_parts"]["count"], 4)
        self.assertEqual(summary["parameters"]["convex_parts_max"], 4)
        self.assertEqual(summary["parameters"]["convex_parts_tolerance"], 0.5)
        self.assert_usage_errors(torus, out, (("--convex-parts-max", "0"),
                                              ("--convex-parts-max", "2000"),
                                              ("--convex-parts-tolerance", "-0.1"),
                                              ("--density", "5"), ("--density", "30000")))
        result = run(torus, "-o", out, "--convex-parts-tolerance", "1")
        self.assertEqual(result.returncode, 2)
        self.assertIn("convex_parts_tolerance: must be in [0, 1)", result.stderr)

    def test_a_mesh_with_a_hole_gets_the_volume_centroid_of_its_capped_surface(self):
        # A 6 x 4 x 2 cm box without its top face (a flat hole of 38 % of
        # what is left): exact float coordinates, ten triangles.
        corners = [(x, y, z) for z in (0, 0.02) for y in (0, 0.04) for x in (0, 0.06)]
        faces = [(0, 2, 1), (1, 2, 3), (0, 1, 4), (1, 5, 4), (2, 6, 3), (3, 6, 7),
                 (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]  # no (4, 5, 6), (5, 7, 6)
        folder = os.path.join(self.tmp, "holed")
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "holed_box.obj"), "w") as f:
            f.writelines(f"v {x} {y} {z}\n" for x, y, z in corners)
            f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
        out = os.path.join(self.tmp, "holed_db")
        result = run(folder, "-o", out, check=0)
        self.assertIn("holed_box.obj' is not a closed manifold (4 boundary, 0 non-manifold",
                      result.stderr)
        self.assertIn("holed_box.obj': the centre of mass is the volume centroid of the mesh with "
                      "its boundary capped (1 boundary part capped, caps 38 % of the surface, "
                      "volume ambiguous by 0 %)", result.stderr)
        summary = json.loads(run("--inspect", os.path.join(out, "holed_box.h5"), "--json",
                                 check=0).stdout)
        self.assertEqual(summary["center_of_mass_method"], "repaired_mesh")
        self.assertFalse(summary["closed"])
        # assimp reads single precision: exact up to float rounding.
        self.assertAlmostEqual(summary["volume"], 0.06 * 0.04 * 0.02, delta=1e-11)
        for got, want in zip(summary["center_of_mass"], (0.03, 0.02, 0.01)):
            self.assertAlmostEqual(got, want, delta=1e-8)

    def test_robot_scales_the_filters_to_its_smallest_fingertip_pad(self):
        robot = os.path.join(SOURCE_DIR, "robots", "kr5_sdh", "kr5_sdh.json")
        mesh = os.path.join(self.meshes, "small_cube.stl")
        out = os.path.join(self.tmp, "sdh_db")
        result = run(mesh, "-o", out, "--robot", robot, check=0)
        self.assertIn("filters scaled to the smallest fingertip pad of kr5_sdh: 14 mm",
                      result.stderr)
        parameters = json.loads(run("--inspect", os.path.join(out, "small_cube.h5"), "--json",
                                    check=0).stdout)["parameters"]
        self.assertAlmostEqual(parameters["pad_radius"], 0.014, places=9)
        self.assertAlmostEqual(parameters["patch_radius"], 0.007, places=9)
        self.assertEqual(parameters["max_hull_distance"], 0.01)
        self.assertEqual(parameters["min_neighbours"], 10)
        self.assertEqual(parameters["filters"], ["curvature", "concavity", "clearance",
                                                 "neighbours"])
        default = json.loads(run("--inspect", os.path.join(self.out, "small_cube.h5"), "--json",
                                 check=0).stdout)["parameters"]
        self.assertEqual((default["pad_radius"], default["patch_radius"]), (0.008, 0.004))
        both = run(mesh, "-o", out, "--robot", robot, "--pad-radius", "0.01")
        self.assertEqual(both.returncode, 2)
        self.assertRegex(both.stderr, r"--(robot|pad-radius) excludes --(pad-radius|robot)")

    def test_export_ply_writes_every_contact_coloured_by_cluster(self):
        ply = os.path.join(self.tmp, "mug.ply")
        run("--export-ply", os.path.join(self.out, "mug.h5"), ply, check=0)
        with open(ply) as f:
            lines = f.read().splitlines()
        count = int(next(l for l in lines if l.startswith("element vertex")).split()[-1])
        body = lines[lines.index("end_header") + 1:]
        self.assertEqual(len(body), count)
        colours = {tuple(l.split()[6:9]) for l in body}
        self.assertEqual(len(colours), 20)

    def test_failing_objects_are_reported_and_the_others_still_complete(self):
        src = os.path.join(self.tmp, "mixed")
        os.makedirs(src)
        shutil.copy(os.path.join(self.meshes, "box.stl"), src)
        with open(os.path.join(src, "broken.stl"), "wb") as f:
            f.write(b"solid broken\nthis is not an stl\n")
        with open(os.path.join(src, "empty.obj"), "w"):
            pass
        out = os.path.join(self.tmp, "mixed-out")
        result = run(src, "-o", out)
        self.assertEqual(result.returncode, 1)
        self.assertTrue(os.path.exists(os.path.join(out, "box.h5")))
        self.assertEqual(sorted(os.listdir(out)), ["box.h5"])  # no temporary leftovers
        self.assertIn("broken.stl", result.stderr)
        self.assertIn("empty.obj': the file is empty", result.stderr)
        self.assertIn("1 built, 2 failed", result.stdout)

    def write_box_view(self, name, eye, spacing=0.002):
        """A PLY of what a camera at `eye` sees of a 6 x 4 x 10 cm box on
        z = 0 (the faces turned towards it), as hfts-render-depth writes one."""
        size = (0.06, 0.04, 0.10)
        centre = (0.0, 0.0, 0.05)
        points = []
        for axis in range(3):
            for sign in (-1.0, 1.0):
                face = list(centre)
                face[axis] += sign * size[axis] / 2
                if sign * (eye[axis] - face[axis]) <= 0:
                    continue  # turned away
                u, v = (axis + 1) % 3, (axis + 2) % 3
                nu, nv = int(round(size[u] / spacing)), int(round(size[v] / spacing))
                for i in range(nu + 1):
                    for j in range(nv + 1):
                        p = list(face)
                        p[u] += -size[u] / 2 + i * spacing
                        p[v] += -size[v] / 2 + j * spacing
                        points.append(p)
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n" % len(points))
            f.writelines("%.6f %.6f %.6f\n" % tuple(p) for p in points)
        return path

    def test_views_of_an_object_build_its_database(self):
        front = self.write_box_view("box_front.ply", (0.5, 0.2, 0.4))
        back = self.write_box_view("box_back.ply", (-0.5, -0.2, 0.4))
        out = os.path.join(self.tmp, "views")
        one = run(front, "--viewpoint", "0.5,0.2,0.4", "-o", out, check=0)
        self.assertRegex(one.stdout, r"box_front\s+\d+\s+\d+\s+20/\d+/\d+\s+1\s.*ok")
        self.assertIn("partial view", one.stderr)  # the warning: a stand-in solid
        both = run(front, back, "--viewpoint", "0.5,0.2,0.4", "--viewpoint", "-0.5,-0.2,0.4",
                   "--name", "box_seen", "-o", out, check=0)
        self.assertIn("box_seen", both.stdout)
        summary = json.loads(run("--inspect", os.path.join(out, "box_seen.h5"), "--json",
                                 check=0).stdout)
        self.assertEqual([v["viewpoint"] for v in summary["partial_views"]],
                         [[0.5, 0.2, 0.4], [-0.5, -0.2, 0.4]])
        self.assertEqual(summary["source_mesh"], "box_front.ply,box_back.ply")
        # The two views' common solid is about the box (6 x 4 x 10 cm).
        self.assertLess(summary["volume"], 1.2 * 0.06 * 0.04 * 0.10)
        self.assertGreater(summary["volume"], 0.9 * 0.06 * 0.04 * 0.10)
        self.assertIn("partial views   2",
                      run("--inspect", os.path.join(out, "box_seen.h5"), check=0).stdout)
        self.assertIsNone(json.loads(run("--inspect", os.path.join(self.out, "mug.h5"), "--json",
                                         check=0).stdout)["partial_views"])
        # Usage errors (exit 2) name the option; a cloud that cannot be read fails (exit 1).
        for args, message in [
                ((front, back, "--viewpoint", "0.5,0.2,0.4"), "one --viewpoint per cloud"),
                ((front, "--viewpoint", "0.5,0.2"), "--viewpoint expects X,Y,Z"),
                ((front, "--viewpoint", "0.5,0.2,nan"), "--viewpoint expects X,Y,Z"),
                ((front, "--viewpoint", "0.5,0.2,0.4", "--hidden-depth", "-1"), "--hidden-depth"),
                ((front, "--viewpoint", "0.5,0.2,0.4", "--floor", "1"), "--floor"),
                ((front, "--hidden-depth", "0.1"), "--viewpoint"),
                ((front, back), "several inputs")]:
            result = run(*args, "-o", out)
            self.assertEqual(result.returncode, 2, (args, result.stderr))
            self.assertIn(message, result.stderr)
        missing = run(os.path.join(self.tmp, "nothing.ply"), "--viewpoint", "0,0,1", "-o", out)
        self.assertEqual(missing.returncode, 1, missing.stderr)
        self.assertIn("nothing.ply", missing.stderr)

    def test_depth_views_carve_what_the_cameras_saw_through(self):
        # The bundled table from one camera, the mug's pixels masked.
        render = os.path.join(os.path.dirname(BINARY), "hfts-render-depth")
        scene = os.path.join(SOURCE_DIR, "objects", "scenes", "table.json")
        seen = os.path.join(self.tmp, "seen")
        subprocess.run([render, scene, "-o", seen, "--db", self.out, "--eye", "0.15,-0.75,0.95",
                        "--look-at", "0.55,0,0.05", "--name", "right", "--partial"],
                       check=True, capture_output=True)
        out = os.path.join(self.tmp, "carved")
        built = run(os.path.join(seen, "right_partial.json"), "--depth-views", "--name", "mug_seen",
                    "-o", out, check=0)
        self.assertIn("mug_seen", built.stdout)
        self.assertIn("support plane", built.stderr)  # the floor it carved above
        summary = json.loads(run("--inspect", os.path.join(out, "mug_seen.h5"), "--json",
                                 check=0).stdout)
        self.assertEqual(len(summary["partial_views"]), 1)
        self.assertEqual(summary["source_mesh"], "right_partial.json")
        # The far side no camera saw is hidden space beside the solid, on the
        # table (z = -0.001) and within the view's reach.
        hidden = summary["hidden_space"]
        self.assertGreater(hidden["boxes"], 0)
        self.assertGreater(hidden["volume"], 0.0)
        self.assertGreaterEqual(hidden["min"][2], -0.001 - 3 * hidden["voxel"])
        self.assertLess(hidden["max"][2], 0.5)
        self.assertIn("no camera saw free",
                      run("--inspect", os.path.join(out, "mug_seen.h5"), check=0).stdout)
        # A scene without a masked depth image has no views of the object.
        none = run(scene, "--depth-views", "-o", out)
        self.assertEqual(none.returncode, 1, none.stderr)
        self.assertIn("has no depth_image with a mask", none.stderr)
        both = run(scene, "--depth-views", "--viewpoint", "0,0,1", "-o", out)
        self.assertEqual(both.returncode, 2, both.stderr)

    def test_bad_arguments_get_clear_errors(self):
        result = run(self.meshes, "-o", self.tmp, "--filters", "curvature,magic")
        self.assertEqual(result.returncode, 2)
        self.assertIn("unknown contact filter 'magic'", result.stderr)
        self.assertNotEqual(run(self.meshes, "-o", self.tmp, "--branching", "20,0").returncode, 0)
        self.assertNotEqual(run(self.meshes, "-o", self.tmp, "--sample-density", "-3").returncode,
                            0)
        result = run(os.path.join(self.tmp, "nothing-here"), "-o", self.tmp)
        self.assertEqual(result.returncode, 1)
        self.assertIn("neither a mesh file nor a directory", result.stderr)
        result = run("--inspect", os.path.join(self.meshes, "box.stl"))
        self.assertEqual(result.returncode, 1)
        self.assertIn("not an HDF5 file", result.stderr)
        self.assertEqual(run().returncode, 2)
        self.assertEqual(run(self.meshes, "-o", self.tmp, "--no-such-option").returncode, 2)
        self.assertEqual(run(self.meshes, "-o", self.tmp, "--min-neighbours", "-1").returncode, 2)
        self.assertEqual(run("--help").returncode, 0)

    def test_distance_grid_options_are_stored_and_checked(self):
        out = os.path.join(self.tmp, "grid")
        box = os.path.join(self.meshes, "box.stl")
        run(box, "-o", out, "--distance-grid-spacing", "0.004", "--distance-grid-margin", "0.01",
            check=0)
        summary = json.loads(run("--inspect", os.path.join(out, "box.h5"), "--json", check=0).stdout)
        self.assertEqual(summary["distance_grid"]["spacing"], 0.004)
        self.assertEqual(summary["parameters"]["distance_grid_margin"], 0.01)
        self.assertIn("distance grid", run("--inspect", os.path.join(out, "box.h5"), check=0).stdout)
        self.assert_usage_errors(box, out, (("--distance-grid-spacing", "-1"),
                                            ("--distance-grid-margin", "-0.1"),
                                            ("--distance-grid-margin", "x")))
        result = run(box, "-o", out, "--distance-grid-margin", "nan")
        self.assertEqual(result.returncode, 2)
        self.assertIn("distance_grid_margin: must be >= 0", result.stderr)
        result = run(box, "-o", out, "--distance-grid-spacing", "0.00001")
        self.assertEqual(result.returncode, 1)
        self.assertIn("distance_grid_spacing", result.stderr)
        self.assertIn("choose a coarser spacing", result.stderr)

    def test_filters_can_be_switched_off(self):
        out = os.path.join(self.tmp, "unfiltered")
        run(os.path.join(self.meshes, "box.stl"), "-o", out, "--filters", "none", check=0)
        summary = json.loads(run("--inspect", os.path.join(out, "box.h5"), "--json", check=0).stdout)
        self.assertEqual(summary["filters"], [])
        self.assertEqual(summary["num_contacts"], summary["num_samples"])

    def test_quiet_still_reports_errors(self):
        src = os.path.join(self.tmp, "quiet")
        os.makedirs(src)
        with open(os.path.join(src, "bad.obj"), "w") as f:
            f.write("v 0 0 0\n")
        result = run(src, "-o", os.path.join(self.tmp, "quiet-out"), "-q")
        self.assertEqual(result.returncode, 1)
        self.assertIn("bad.obj", result.stderr)
        self.assertNotIn("[1/1]", result.stderr)

    def test_same_input_gives_identical_bytes(self):
        out2 = os.path.join(self.tmp, "again")
        run(os.path.join(self.meshes, "torus.stl"), "-o", out2, "-q", check=0)
        with open(os.path.join(self.out, "torus.h5"), "rb") as a, \
                open(os.path.join(out2, "torus.h5"), "rb") as b:
            self.assertEqual(a.read(), b.read())

    def read_glb(self, path):
        with open(path, "rb") as f:
            data = f.read()
        magic, version, length = struct.unpack_from("<4sII", data, 0)
        self.assertEqual((magic, version, length), (b"glTF", 2, len(data)))
        size, kind = struct.unpack_from("<I4s", data, 12)
        self.assertEqual(kind, b"JSON")
        return json.loads(data[20:20 + size])

    def test_export_scene_writes_robot_obstacles_and_object_as_gltf(self):
        for scene in ("table", "shelf", "bin"):
            glb = os.path.join(self.tmp, scene + ".glb")
            result = run("--export-scene", os.path.join(SOURCE_DIR, "objects", "scenes", scene + ".json"),
                         glb, "--db", self.out, check=0)
            self.assertIn("wrote scene '" + scene + "'", result.stdout)
            doc = self.read_glb(glb)
            names = {n.get("name", "") for n in doc["nodes"]}
            self.assertTrue(any(n.startswith("palm") for n in names), names)
            self.assertTrue(any(n.startswith("thumb_distal") for n in names), names)
            self.assertGreaterEqual(len(doc["meshes"]), 40)
            self.assertEqual(len(doc["materials"]), 8)  # arm .. path, points

    def test_export_scene_rejects_bad_configurations_and_missing_databases(self):
        scene = os.path.join(SOURCE_DIR, "objects", "scenes", "table.json")
        glb = os.path.join(self.tmp, "bad.glb")
        result = run("--export-scene", scene, glb, "--db", self.out, "--config", "0,0,0")
        self.assertEqual(result.returncode, 2)
        self.assertIn("has 3 values, expected 13", result.stderr)
        result = run("--export-scene", scene, glb, "--db", self.out,
                     "--config", "0,5,0,0,0,0,0,0,0,0,0,0,0")
        self.assertEqual(result.returncode, 2)
        self.assertIn("'a2'", result.stderr)
        result = run("--export-scene", scene, glb, "--db", os.path.join(self.tmp, "nowhere"))
        self.assertEqual(result.returncode, 1)
        self.assertIn("no database for target object 'mug'", result.stderr)
        result = run("--export-scene", scene, os.path.join(self.tmp, "scene.obj"), "--db", self.out)
        self.assertEqual(result.returncode, 2)
        self.assertIn("must end in .glb", result.stderr)
        self.assertFalse(os.path.exists(glb))

    def test_hand_map_is_built_deterministically(self):
        robot = os.path.join(SOURCE_DIR, "robots", "kr5_sdh", "kr5_sdh.json")
        first, second = os.path.join(self.tmp, "hand1"), os.path.join(self.tmp, "hand2")
        result = run("--hand", robot, "-o", first, check=0)
        self.assertIn("8192 grasp postures", result.stdout)
        run("--hand", robot, "-o", second, check=0)
        with open(os.path.join(first, "kr5_sdh_hand_map.h5"), "rb") as a, \
                open(os.path.join(second, "kr5_sdh_hand_map.h5"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        self.assertEqual(run("--hand", robot).returncode, 2)
        # With the hand map beside the database, --inspect reports graspability.
        database = os.path.join(first, "mug.h5")
        shutil.copy(os.path.join(self.out, "mug.h5"), database)
        summary = json.loads(run("--inspect", database, "--json", check=0).stdout)["graspability"]
        self.assertEqual((summary["robot"], summary["sampled"], summary["tolerance"]),
                         ("kr5_sdh", 1000, 0.005))
        self.assertGreater(summary["reachable"], 0)
        self.assertLessEqual(summary["reachable"], summary["stable"])
        self.assertAlmostEqual(summary["fraction"], summary["reachable"] / 1000)
        text = run("--inspect", database, check=0).stdout
        self.assertRegex(text, r"graspability    0\.\d+ for kr5_sdh in free space: \d+ of 1000")
        # Without one it says how to build it.
        text = run("--inspect", os.path.join(self.out, "mug.h5"), check=0).stdout
        self.assertIn("graspability    unknown: no hand map", text)
        self.assertIn("hfts-preprocess --hand", text)
        result = run("--hand", os.path.join(self.tmp, "missing.json"), "-o", first)
        self.assertEqual(result.returncode, 1)
        self.assertIn("missing.json", result.stderr)

    def test_check_robot_passes_the_bundled_robot(self):
        robot = os.path.join(SOURCE_DIR, "robots", "kr5_sdh", "kr5_sdh.json")
        result = run("--check-robot", robot, check=0)
        self.assertIn("the robot is ready for planning", result.stdout)
        for topic in ("model: 'kr5_sdh': 13 DoF (6 arm, 7 hand)", "hand: ", "arm IK: closed form",
                      "home: free of self collisions", "spheres: "):
            self.assertIn(topic, result.stdout)
        self.assertNotIn("error", result.stdout)

    def edited_robot(self, name, edit):
        """The KR5 + SDH config with `edit` applied, in a temporary folder
        (the URDF beside it)."""
        folder = os.path.join(self.tmp, "robot-" + name)
        os.makedirs(folder, exist_ok=True)
        source = os.path.join(SOURCE_DIR, "robots", "kr5_sdh")
        shutil.copy(os.path.join(source, "kr5_sdh.urdf"), folder)
        with open(os.path.join(source, "kr5_sdh.json")) as f:
            config = json.load(f)
        edit(config)
        path = os.path.join(folder, "robot.json")
        with open(path, "w") as f:
            json.dump(config, f)
        return path

    def test_check_robot_names_what_is_wrong(self):
        def missing_key(c):
            del c["pregrasp_offset"]

        def no_disabled_pairs(c):
            c["disabled_collisions"] = []

        def tips_on_the_palm(c):
            for tip in c["fingertips"]:
                tip.update(link="palm", point=[0, 0, 0.1], normal=[0, 0, 1])

        def five_fingertips(c):
            c["fingertips"] += c["fingertips"][:2]

        cases = [
            (missing_key, "error    config: ", "pregrasp_offset: is required"),
            (no_disabled_pairs, "error    home: links '", "to disabled_collisions"),
            (tips_on_the_palm, "error    hand: ", "no grasp posture"),
            (five_fingertips, "error    fingertips: ", "2 to 4 fingertips"),
        ]
        for edit, line, hint in cases:
            result = run("--check-robot", self.edited_robot(edit.__name__, edit))
            self.assertEqual(result.returncode, 1, (edit.__name__, result.stdout))
            self.assertIn(line, result.stdout, edit.__name__)
            self.assertIn(hint, result.stdout, edit.__name__)
            self.assertIn("not ready for planning", result.stdout)

    def test_database_md_python_example_runs(self):
        with open(os.path.join(SOURCE_DIR, "docs", "database.md")) as f:
            blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
        self.assertTrue(blocks, "docs/database.md has no python example")
        script = os.path.join(self.tmp, "example.py")
        with open(script, "w") as f:
            f.write(blocks[0])
        result = subprocess.run([sys.executable, script, os.path.join(self.out, "mug.h5")],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("mug", result.stdout)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", required=True)
    parser.add_argument("--source-dir", required=True)
    args, rest = parser.parse_known_args()
    BINARY, SOURCE_DIR = args.binary, args.source_dir
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
