"""Runs a real hfts-server for the service's integration tests (standard library only).

run_tests() parses --server, --preprocess, --source-dir and --client,
builds the mug and blob databases and the hand maps of the bundled robots
(KR5 + SDH, Panda + gripper, UR5e + Allegro-like hand) into a temporary
directory once (CONFIG.db_dir, about a second) and runs the module's tests. RunningServer starts hfts-server on an ephemeral port and reads the
port from its first line; ServerTest gives a test class one server.
"""

import argparse
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import types
import unittest

from cli_support import build_databases

CONFIG = types.SimpleNamespace(server=None, client=None, preprocess=None, source_dir=None,
                               db_dir=None)

# The service's tests plan without the physics check (seconds of simulation
# per goal reached; whether plans hold is the planner's tests' and the
# demo's): they test the service.
NO_PHYSICS = {"physics_check": 0}
# The same as hfts-client's (and the Python client program's) arguments.
NO_PHYSICS_ARGS = [a for name, value in NO_PHYSICS.items() for a in ("--param", f"{name}={value}")]
TABLE = {"scene": "table", "seed": 1, "time_limit": 20, "parameters": NO_PHYSICS}
BIN = {"scene": "bin", "seed": 1, "time_limit": 20, "parameters": NO_PHYSICS}
# The mug 1.3 m in front of the KR5's shoulder: inside the ball that bounds
# the fingertips' reach (so the plan is not refused at once as out of
# reach), beyond what the arm reaches (about 1.2 m): no grasp has an arm IK
# solution, so the planner runs until its time limit (or until cancelled).
FAR_AWAY = {"position": [1.3, 0, 0.335], "orientation": [0, 0, 0, 1]}
ENDLESS = {"scene": "table", "object_pose": FAR_AWAY, "time_limit": 30}
QUALITY = {"contacts": [
    {"position": [1, 0, 0], "normal": [-1, 0, 0]},
    {"position": [-0.5, 0.8660254037844386, 0], "normal": [0.5, -0.8660254037844386, 0]},
    {"position": [-0.5, -0.8660254037844386, 0], "normal": [0.5, 0.8660254037844386, 0]}]}
QUALITY_EPSILON = 0.275925155686099  # docs/grasp_quality.md


def run_tests(with_client=False):
    parser = argparse.ArgumentParser()
    for option in ("--server", "--preprocess", "--source-dir"):
        parser.add_argument(option, required=True)
    parser.add_argument("--client", required=with_client)
    args, rest = parser.parse_known_args()
    for key, value in vars(args).items():
        setattr(CONFIG, key, value and os.path.abspath(value))
    CONFIG.db_dir = tempfile.mkdtemp(prefix="hfts-service-db-")
    try:
        build_databases(CONFIG.preprocess, CONFIG.source_dir, CONFIG.db_dir, ["mug", "blob"],
                        robots=("kr5_sdh", "panda_gripper", "ur5e_allegro"))
        program = unittest.main(argv=[sys.argv[0], *rest], verbosity=2, exit=False)
    finally:
        shutil.rmtree(CONFIG.db_dir, ignore_errors=True)
    sys.exit(0 if program.result.wasSuccessful() else 1)


class RunningServer:
    """hfts-server as a child process; its request log goes to log_path."""

    def __init__(self, log_path, *extra, db_dir=None):
        self.log_path = log_path
        self.log = open(log_path, "wb")
        self.process = subprocess.Popen(
            [CONFIG.server, "--db", db_dir or CONFIG.db_dir, "--port", "0",
             "--robot", os.path.join(CONFIG.source_dir, "robots", "kr5_sdh", "kr5_sdh.json"),
             "--scenes", os.path.join(CONFIG.source_dir, "objects", "scenes"), *map(str, extra)],
            stdout=subprocess.PIPE, stderr=self.log, stdin=subprocess.DEVNULL)
        line = self.process.stdout.readline().decode()
        match = re.match(r"hfts-server listening on ([\d.]+):(\d+)$", line.strip())
        if not match:
            self.process.kill()
            raise RuntimeError(f"unexpected first line {line!r}; log: {self.log_text()}")
        self.host, self.port = match.group(1), int(match.group(2))

    def log_text(self):
        with open(self.log_path, encoding="utf-8", errors="replace") as f:
            return f.read()

    def connect(self, timeout=60):
        return Connection(self.host, self.port, timeout)

    def call(self, method, params=None, request_id=1):
        with self.connect() as c:
            return c.call(method, params, request_id)

    def running(self):
        """Plans running now, as server.info reports."""
        return self.call("server.info")["result"]["load"]["running"]

    def stop(self, sig=signal.SIGTERM, timeout=30):
        """Signals the server (if it still runs) and returns its exit code."""
        if self.process.poll() is None:
            self.process.send_signal(sig)
        try:
            code = self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            code = self.process.wait()
        self.process.stdout.close()
        self.log.close()
        return code


class Connection:
    """A raw socket to the server: send bytes, read response lines."""

    def __init__(self, host, port, timeout=60):
        self.socket = socket.create_connection((host, port), timeout=timeout)
        self.reader = self.socket.makefile("rb")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self.reader.close()
        self.socket.close()

    def send(self, data):
        self.socket.sendall(data if isinstance(data, bytes) else data.encode())

    def request(self, method, params=None, request_id=1):
        message = {"jsonrpc": "2.0", "id": request_id, "method": method}
        if params is not None:
            message["params"] = params
        self.send(json.dumps(message) + "\n")

    def read(self):
        """The next response line as JSON; None at end of stream."""
        line = self.reader.readline()
        return json.loads(line) if line else None

    def call(self, method, params=None, request_id=1):
        self.request(method, params, request_id)
        return self.read()


def wait_until(condition, timeout=10.0, step=0.02):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(step)
    return False


class ServerTest(unittest.TestCase):
    """One server for the whole class; OPTIONS are its extra arguments."""
    OPTIONS = ("--workers", "2")

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-server-")
        cls.server = RunningServer(os.path.join(cls.tmp, "server.log"), *cls.OPTIONS)

    @classmethod
    def tearDownClass(cls):
        code = cls.server.stop()
        shutil.rmtree(cls.tmp, ignore_errors=True)
        assert code == 0, f"hfts-server exited with {code}"

    def client(self, *args):
        """hfts-client (CONFIG.client) against this server."""
        return subprocess.run([CONFIG.client, "--port", str(self.server.port), *map(str, args)],
                               capture_output=True, text=True, timeout=120)

    def assertError(self, response, code, field=None, request_id=None, contains=None):
        self.assertIn("error", response, response)
        self.assertEqual(response["jsonrpc"], "2.0")
        self.assertEqual(response["id"], request_id, response)
        self.assertEqual(response["error"]["code"], code, response)
        if field is not None:
            self.assertEqual(response["error"]["data"]["field"], field, response)
            self.assertTrue(response["error"]["message"].startswith(field + ":"), response)
        if contains is not None:
            self.assertIn(contains, response["error"]["message"])

    def assertServes(self, connection):
        """The connection (and a fresh one) still answers."""
        self.assertEqual(connection.call("server.info", request_id="alive")["id"], "alive")
        self.assertEqual(self.server.call("scenes.list")["id"], 1)

    def assertValidPlan(self, result, scene, info):
        self.assertTrue(result["success"], result["message"])
        self.assertEqual(result["reason"], "none")
        robot = info["robot"]
        self.assertEqual(result["joint_names"], robot["joint_names"])
        self.assertGreaterEqual(len(result["path"]), 3)
        with open(os.path.join(CONFIG.source_dir, "objects", "scenes", scene + ".json")) as f:
            start = json.load(f).get("start", robot["home"])
        if isinstance(start, dict):  # starts per robot name
            start = start.get(robot["name"], robot["home"])
        for a, b in zip(result["path"][0], start):
            self.assertAlmostEqual(a, b, places=12)
        for q in result["path"]:
            self.assertEqual(len(q), 13)
            for value, low, high in zip(q, robot["lower_limits"], robot["upper_limits"]):
                self.assertTrue(low - 1e-9 <= value <= high + 1e-9)
        grasp = result["grasp"]
        self.assertGreater(grasp["epsilon"], 0.0)
        self.assertEqual(len(grasp["contacts_world"]), 3)
        self.assertEqual(grasp["hand_joint_names"], robot["hand_joint_names"])
        for a, b in zip(result["path"][-1][6:], grasp["hand_configuration"]):
            self.assertAlmostEqual(a, b, places=12)
        # The default robot's bound (server.info lists its parameter defaults).
        bound = next(float(p["default"]) for p in info["planner_parameters"]
                     if p["name"] == "max_fingertip_error")
        self.assertLessEqual(grasp["fingertip_error"], bound + 1e-9)
        # The grasp as executed: force closure where the pads touch, no
        # fingertip deeper than the default max_penetration.
        self.assertGreater(grasp["epsilon"], 0.0)
        self.assertGreaterEqual(grasp["planned_epsilon"], 0.0)
        self.assertLessEqual(grasp["penetration"], 0.001 + 1e-12)
        self.assertGreater(result["stats"]["path_length_smoothed"], 0.0)
