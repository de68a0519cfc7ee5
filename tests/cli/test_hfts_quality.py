#!/usr/bin/env python3
"""End-to-end tests of hfts-quality (docs/grasp_quality.md)."""

import argparse
import json
import math
import subprocess
import sys
import unittest

BINARY = None


def quality(request):
    text = request if isinstance(request, str) else json.dumps(request)
    return subprocess.run([BINARY, "-"], input=text, capture_output=True, text=True, timeout=60)


def equator(degrees, **extra):
    contacts = []
    for d in degrees:
        a = math.radians(d)
        p = [math.cos(a), math.sin(a), 0.0]
        contacts.append({"position": p, "normal": [-v for v in p]})
    return {"contacts": contacts, **extra}


class HftsQuality(unittest.TestCase):
    def test_stable_grasp_has_positive_epsilon(self):
        result = quality(equator([0, 120, 240]))
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertGreater(json.loads(result.stdout)["epsilon"], 0.1)

    def test_outward_normals_give_the_same_value(self):
        inward = json.loads(quality(equator([0, 120, 240])).stdout)["epsilon"]
        request = equator([0, 120, 240], normals="outward")
        for c in request["contacts"]:
            c["normal"] = [-v for v in c["normal"]]
        self.assertAlmostEqual(json.loads(quality(request).stdout)["epsilon"], inward, places=12)

    def test_two_contacts_and_more_friction(self):
        self.assertEqual(json.loads(quality(equator([0, 180])).stdout)["epsilon"], 0.0)
        low = json.loads(quality(equator([0, 100, 230], friction=0.3)).stdout)["epsilon"]
        high = json.loads(quality(equator([0, 100, 230], friction=0.8)).stdout)["epsilon"]
        self.assertGreater(high, low)

    def test_soft_fingers_hold_two_opposed_contacts(self):
        hard = json.loads(quality(equator([0, 180])).stdout)["epsilon"]
        soft = quality(equator([0, 180], torsional_friction=0.1))
        self.assertEqual(soft.returncode, 0, soft.stderr)
        self.assertEqual(hard, 0.0)
        self.assertGreater(json.loads(soft.stdout)["epsilon"], 0.0)

    def test_the_largest_request_is_answered(self):
        result = quality(equator([0, 90, 180, 270], cone_edges=64, friction=100))
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertGreater(json.loads(result.stdout)["epsilon"], 60.0)

    def test_bad_requests_name_the_field(self):
        cases = [
            ("{", "request: not valid JSON"),
            ("[]", "request: must be a JSON object"),
            (json.dumps({"contacts": []}), "contacts: must be a non-empty array"),
            (json.dumps(equator([0, 120], friction=-1)), "friction: must be > 0"),
            (json.dumps(equator([0, 120], cone_edges=2.5)), "cone_edges: must be an integer"),
            (json.dumps(equator([0, 120], normals="sideways")), "normals: must be"),
            (json.dumps(equator(range(0, 360, 72), cone_edges=64)),
             "cone_edges: contacts x cone_edges must be at most 256, got 5 x 64"),
            (json.dumps(equator([0] * 65)), "contacts: holds more than 64 contacts"),
            (json.dumps(equator([0, 180], torsional_friction=-1)),
             "torsional_friction: must be >= 0"),
            (json.dumps(equator(range(0, 360, 90), cone_edges=63, torsional_friction=0.01)),
             "cone_edges: contacts x cone_edges (+ 2 torsions per soft contact) must be at most "
             "256, got 4 x 65"),
            (json.dumps(equator([0, 120], weight=3)), "weight: unknown field"),
            (json.dumps({"contacts": [{"position": [0, 0], "normal": [1, 0, 0]}]}),
             "contacts[0].position: must be an array of 3 numbers"),
            (json.dumps({"contacts": [{"position": [0, 0, 0], "normal": [2, 0, 0]}]}),
             "contacts[0].normal: must be a unit vector"),
        ]
        for text, problem in cases:
            result = quality(text)
            self.assertEqual(result.returncode, 2, text)
            self.assertIn(problem, result.stderr, text)
        missing = subprocess.run([BINARY, "/nonexistent.json"], capture_output=True, text=True)
        self.assertEqual(missing.returncode, 1)
        self.assertEqual(subprocess.run([BINARY], capture_output=True).returncode, 2)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", required=True)
    args, rest = parser.parse_known_args()
    BINARY = args.binary
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
