#!/usr/bin/env python3
"""Integration tests of hfts-server over raw sockets (docs/protocol.md): every
method, pipelining, batches, concurrency, cancellation, malformed input,
limits and shutdown. Run by ctest with Debian's /usr/bin/python3."""

import argparse
import json
import math
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import unittest

from hfts_server_fixture import RunningServer, build_databases, wait_until

SERVER = PREPROCESS = SOURCE_DIR = None
DB_DIR = None
TABLE = {"scene": "table", "seed": 1, "time_limit": 20}
BIN = {"scene": "bin", "seed": 1, "time_limit": 20}
# The mug 3 m away: no grasp has an arm IK solution, so the planner runs
# until its time limit (or until it is cancelled).
ENDLESS = {"scene": "table", "object_pose": {"position": [3, 0, 0], "orientation": [0, 0, 0, 1]},
           "time_limit": 30}
QUALITY = {"contacts": [
    {"position": [1, 0, 0], "normal": [-1, 0, 0]},
    {"position": [-0.5, 0.8660254037844386, 0], "normal": [0.5, -0.8660254037844386, 0]},
    {"position": [-0.5, -0.8660254037844386, 0], "normal": [0.5, 0.8660254037844386, 0]}]}


def setUpModule():
    global DB_DIR
    DB_DIR = tempfile.mkdtemp(prefix="hfts-server-db-")
    build_databases(PREPROCESS, SOURCE_DIR, DB_DIR)


def tearDownModule():
    shutil.rmtree(DB_DIR, ignore_errors=True)


def start_server(log_dir, *extra):
    return RunningServer(SERVER, SOURCE_DIR, DB_DIR, os.path.join(log_dir, "server.log"), *extra)


class ServerTest(unittest.TestCase):
    """One server for the whole class; OPTIONS are its extra arguments."""
    OPTIONS = ("--workers", "2")

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-server-")
        cls.server = start_server(cls.tmp, *cls.OPTIONS)

    @classmethod
    def tearDownClass(cls):
        code = cls.server.stop()
        shutil.rmtree(cls.tmp, ignore_errors=True)
        assert code == 0, f"hfts-server exited with {code}"

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
        with open(os.path.join(SOURCE_DIR, "objects", "scenes", scene + ".json")) as f:
            start = json.load(f).get("start", robot["home"])
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
        self.assertLess(grasp["fingertip_error"], 0.005)
        self.assertGreater(result["stats"]["path_length_smoothed"], 0.0)


class Methods(ServerTest):
    def test_server_info_reports_the_robot_limits_and_load(self):
        response = self.server.call("server.info", request_id="a")
        self.assertEqual(response["id"], "a")
        info = response["result"]
        self.assertEqual(info["name"], "hfts-server")
        self.assertRegex(info["version"], r"^\d+\.\d+\.\d+$")
        self.assertEqual(info["robot"]["name"], "kr5_sdh")
        self.assertEqual(info["robot"]["joint_names"][:6], ["a1", "a2", "a3", "a4", "a5", "a6"])
        self.assertEqual(len(info["robot"]["lower_limits"]), 13)
        self.assertEqual((info["objects"], info["scenes"]), (2, 3))
        self.assertEqual(info["limits"]["max_message_bytes"], 16 << 20)
        self.assertEqual(info["limits"]["max_time_limit"], 60)
        self.assertEqual(info["load"]["workers"], 2)
        names = {p["name"] for p in info["planner_parameters"]}
        self.assertTrue({"p_max", "kappa", "step_size"} <= names)
        self.assertEqual(set(info["methods"]), {"server.info", "objects.list", "scenes.list",
                                                "plan", "grasp.quality", "cancel", "shutdown",
                                                "reload"})

    def test_objects_list_names_the_databases(self):
        result = self.server.call("objects.list")["result"]
        self.assertEqual([o["name"] for o in result["objects"]], ["blob", "mug"])
        mug = result["objects"][1]
        self.assertEqual(mug["nodes_per_level"], [20, 80, 320])
        self.assertGreater(mug["contacts"], 1000)
        self.assertGreater(mug["rho"], 0.05)
        self.assertEqual(result["skipped"], [])

    def test_scenes_list_describes_the_bundled_scenes(self):
        scenes = self.server.call("scenes.list")["result"]["scenes"]
        self.assertEqual([s["name"] for s in scenes], ["bin", "shelf", "table"])
        table = scenes[2]
        self.assertEqual(table["target_object"], "mug")
        self.assertEqual(table["target_pose"], {"position": [0.55, 0, 0],
                                                "orientation": [0, 0, 0, 1]})
        self.assertIn({"name": "lamp_bar", "type": "box"}, table["obstacles"])
        self.assertEqual(len(table["start"]), 13)
        self.assertIsNone(scenes[0]["start"])

    def test_plan_in_the_table_scene_returns_a_valid_grasp_and_path(self):
        info = self.server.call("server.info")["result"]
        result = self.server.call("plan", TABLE, request_id=7)
        self.assertEqual(result["id"], 7)
        plan = result["result"]
        self.assertValidPlan(plan, "table", info)
        self.assertEqual((plan["scene"], plan["object"], plan["algorithm"], plan["seed"]),
                         ("table", "mug", "coupled", 1))
        self.assertEqual(plan["object_pose"]["position"], [0.55, 0, 0])
        # grasp.quality of the planned contacts (object frame) gives the plan's epsilon back.
        quality = self.server.call("grasp.quality", {"object": "mug",
                                                     "contacts": plan["grasp"]["contacts_object"]})
        self.assertAlmostEqual(quality["result"]["epsilon"], plan["grasp"]["epsilon"], places=12)

    def test_decoupled_plan_with_an_inline_scene_and_parameters(self):
        with open(os.path.join(SOURCE_DIR, "objects", "scenes", "bin.json")) as f:
            scene = json.load(f)
        params = {"scene": scene, "algorithm": "decoupled", "iterations": 30, "seed": 2,
                  "time_limit": 20, "parameters": {"step_size": 0.12, "kappa": 4}}
        plan = self.server.call("plan", params)["result"]
        self.assertValidPlan(plan, "bin", self.server.call("server.info")["result"])
        self.assertEqual((plan["algorithm"], plan["object"]), ("decoupled", "blob"))

    def test_an_unreachable_object_is_a_result_not_an_error(self):
        params = dict(ENDLESS, time_limit=0.3)
        plan = self.server.call("plan", params)["result"]
        self.assertFalse(plan["success"])
        self.assertIn(plan["reason"], ("object_unreachable", "time_limit"))
        self.assertTrue(plan["message"])
        self.assertIsNone(plan["grasp"])
        self.assertEqual(plan["path"], [])
        self.assertLess(plan["stats"]["planning_time"], 0.3 + 0.2)

    def test_grasp_quality_matches_hfts_quality(self):
        result = self.server.call("grasp.quality", QUALITY)["result"]
        self.assertAlmostEqual(result["epsilon"], 0.275925155686099, places=12)
        two = {"contacts": QUALITY["contacts"][:2]}
        self.assertEqual(self.server.call("grasp.quality", two)["result"]["epsilon"], 0.0)

    def test_grasp_quality_of_an_object_uses_its_centre_and_rho(self):
        mug = self.server.call("objects.list")["result"]["objects"][1]
        explicit = dict(QUALITY, center=mug["center_of_mass"], torque_scale=mug["rho"])
        by_name = dict(QUALITY, object="mug")
        self.assertEqual(self.server.call("grasp.quality", by_name)["result"],
                         self.server.call("grasp.quality", explicit)["result"])

    def test_cancel_of_an_unknown_id_says_so(self):
        response = self.server.call("cancel", {"id": 12345}, request_id=2)
        self.assertEqual(response["result"], {"id": 12345, "cancelled": False})

    def test_shutdown_is_refused_from_another_machine(self):
        address = non_loopback_address()
        if address is None:
            self.skipTest("no non-loopback address to connect from")
        other = start_server(self.tmp, "--bind", "0.0.0.0", "--workers", "1")
        try:
            with socket.create_connection((address, other.port), timeout=30) as s:
                s.sendall(b'{"jsonrpc":"2.0","id":1,"method":"shutdown"}\n')
                response = json.loads(s.makefile("rb").readline())
            self.assertError(response, -32003, request_id=1)
            self.assertIsNone(other.process.poll())
        finally:
            self.assertEqual(other.stop(), 0)

    def test_one_log_line_per_request(self):
        with self.server.connect() as c:
            c.request("server.info", request_id="log-1")
            c.read()
            c.send("not json\n")
            c.read()
            c.request("no.such.method", request_id="log-2")
            c.read()
        log = self.server.log_text()
        lines = [l for l in log.splitlines() if '"log-' in l]
        self.assertEqual(len(lines), 2, log)
        self.assertRegex(lines[0], r'^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z 127\.0\.0\.1:\d+ '
                                   r'id="log-1" server\.info \d+\.\d{6}s ok$')
        self.assertRegex(lines[1], r'id="log-2" no\.such\.method [\d.]+s error -32601 ')
        self.assertRegex(log, r"127\.0\.0\.1:\d+ id=null - [\d.]+s error -32700 parse error")


class Pipelining(ServerTest):
    def test_pipelined_requests_keep_their_ids(self):
        requests = [
            {"jsonrpc": "2.0", "id": "plan", "method": "plan", "params": BIN},
            {"jsonrpc": "2.0", "id": 1, "method": "server.info"},
            {"jsonrpc": "2.0", "id": 2.5, "method": "grasp.quality", "params": QUALITY},
            {"jsonrpc": "2.0", "id": None, "method": "scenes.list"},
            {"jsonrpc": "2.0", "method": "objects.list"},  # a notification: no response
            {"jsonrpc": "2.0", "id": "bad", "method": "plan", "params": {"scene": "moon"}},
        ]
        with self.server.connect() as c:
            c.send("".join(json.dumps(r) + "\n" for r in requests))
            responses = [c.read() for _ in range(5)]
        by_id = {json.dumps(r["id"]): r for r in responses}
        self.assertEqual(set(by_id), {'"plan"', "1", "2.5", "null", '"bad"'})
        self.assertEqual(by_id["1"]["result"]["name"], "hfts-server")
        self.assertAlmostEqual(by_id["2.5"]["result"]["epsilon"], 0.275925155686099, places=12)
        self.assertEqual(len(by_id["null"]["result"]["scenes"]), 3)
        self.assertError(by_id['"bad"'], -32602, "scene", "bad", "unknown scene 'moon'")
        self.assertTrue(by_id['"plan"']["result"]["success"])
        self.assertEqual(responses[-1]["id"], "plan", "the plan finishes last")

    def test_a_batch_is_answered_with_one_array(self):
        batch = [{"jsonrpc": "2.0", "id": 1, "method": "server.info"},
                 {"jsonrpc": "2.0", "method": "server.info"},
                 {"jsonrpc": "2.0", "id": 2, "method": "plan", "params": BIN},
                 {"jsonrpc": "2.0", "id": 3, "method": "grasp.quality", "params": {}},
                 17]
        with self.server.connect() as c:
            c.send(json.dumps(batch) + "\n")
            responses = c.read()
            self.assertServes(c)
        self.assertIsInstance(responses, list)
        self.assertEqual(sorted(json.dumps(r["id"]) for r in responses), ["1", "2", "3", "null"])
        by_id = {json.dumps(r["id"]): r for r in responses}
        self.assertTrue(by_id["2"]["result"]["success"])
        self.assertError(by_id["3"], -32602, "contacts", 3)
        self.assertError(by_id["null"], -32600)

    def test_a_batch_of_notifications_gets_no_response(self):
        with self.server.connect() as c:
            c.send(json.dumps([{"jsonrpc": "2.0", "method": "server.info"}] * 3) + "\n")
            c.request("server.info", request_id="after")
            self.assertEqual(c.read()["id"], "after")

    def test_a_json_text_without_newline_is_answered(self):
        with self.server.connect() as c:
            c.send('{"jsonrpc": "2.0", "id": "no-newline", "method": "server.info"}')
            self.assertEqual(c.read()["id"], "no-newline")
            c.send('{"jsonrpc":"2.0","id":"a","method":"scenes.list"}'
                   '{"jsonrpc":"2.0","id":"b","method":"scenes.list"}  \r\n')
            self.assertEqual([c.read()["id"], c.read()["id"]], ["a", "b"])
            self.assertServes(c)

    def test_sixteen_concurrent_clients_all_get_correct_plans(self):
        reference = {name: self.server.call("plan", params)["result"]
                     for name, params in (("table", TABLE), ("bin", BIN))}
        for plan in reference.values():
            self.assertTrue(plan["success"], plan["message"])
        results = [None] * 16
        barrier = threading.Barrier(16)

        def client(i):
            params = TABLE if i % 4 == 0 else BIN
            with self.server.connect(timeout=120) as c:
                barrier.wait()
                results[i] = (params["scene"], c.call("plan", params, request_id=f"c{i}"))

        threads = [threading.Thread(target=client, args=(i,)) for i in range(16)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for i, (scene, response) in enumerate(results):
            self.assertEqual(response["id"], f"c{i}")
            plan = response["result"]
            expected = reference[scene]
            # Same seed, same request: the same grasp and path, whoever planned it.
            self.assertEqual(plan["path"], expected["path"])
            self.assertEqual(plan["grasp"], expected["grasp"])
            for key in ("iterations", "goal_sampling_calls", "collision_checks"):
                self.assertEqual(plan["stats"][key], expected["stats"][key])


class Malformed(ServerTest):
    def exchange(self, data):
        """Sends data on a fresh connection; returns the response and checks
        the connection still serves."""
        with self.server.connect() as c:
            c.send(data)
            response = c.read()
            self.assertServes(c)
        return response

    def test_binary_garbage_is_a_parse_error(self):
        self.assertError(self.exchange(bytes(range(256)).replace(b"\n", b"") + b"\n"), -32700)
        self.assertError(self.exchange(b"\xff\xfe{\x00}\n"), -32700)

    def test_a_truncated_json_text_is_a_parse_error(self):
        response = self.exchange('{"jsonrpc": "2.0", "id": 1, "method": "serv\n')
        self.assertError(response, -32700, contains="parse error")

    def test_an_empty_line_is_a_parse_error(self):
        self.assertError(self.exchange("\n"), -32700, contains="empty line")
        self.assertError(self.exchange("   \t\r\n"), -32700, contains="empty line")

    def test_non_finite_numbers_are_rejected(self):
        for text in ("NaN", "Infinity", "-Infinity", "1e400"):
            request = '{"jsonrpc":"2.0","id":1,"method":"plan","params":{"scene":"table",' \
                      '"time_limit":%s}}\n' % text
            self.assertError(self.exchange(request), -32700)

    def test_requests_that_are_not_json_rpc_are_invalid(self):
        cases = [('{"id": 1, "method": "server.info"}', 1),
                 ('{"jsonrpc": "1.0", "id": 2, "method": "server.info"}', 2),
                 ('{"jsonrpc": "2.0", "id": 3, "method": 42}', 3),
                 ('{"jsonrpc": "2.0", "id": 4, "method": "server.info", "params": 5}', 4),
                 ('{"jsonrpc": "2.0", "id": 5, "method": "server.info", "extra": 1}', 5),
                 ('{"jsonrpc": "2.0", "id": {"a": 1}, "method": "server.info"}', None),
                 ('"just a string"', None), ("[]", None),
                 ("[" * 100 + "]" * 100, None)]
        for text, request_id in cases:
            with self.subTest(text=text[:40]):
                self.assertError(self.exchange(text + "\n"), -32600, request_id=request_id)

    def test_an_unknown_method_is_method_not_found(self):
        self.assertError(self.exchange('{"jsonrpc":"2.0","id":9,"method":"plan.all"}\n'), -32601,
                         request_id=9, contains="plan.all")

    def test_invalid_params_name_the_field(self):
        start = [0, -1.5707963, 1.5707963, 0, 1.5707963, 0, 0, -0.2, 0.2, -0.2, 0.2, -0.2, 0.2]
        cases = [
            ({"scene": "table", "start": start[:12]}, "start", "13 numbers, got 12"),
            ({"scene": "table", "start": start[:-1] + [4.0]}, "start", "thumb_distal_joint"),
            ({"scene": "table", "start": start[:3] + ["x"] + start[4:]}, "start[3]", "number"),
            ({"scene": "table", "object_pose": {"position": [0.5, 0, 0],
                                                "orientation": [0, 0, 0, 0]}},
             "object_pose.orientation", "zero norm"),
            ({"scene": "table", "object_pose": {"position": [0.5, 0]}}, "object_pose.position",
             "3 numbers"),
            ({"scene": "table", "object": "teapot"}, "object", "unknown object 'teapot'"),
            ({"scene": "table", "object": "../mug"}, "object", "path characters"),
            ({"scene": "kitchen"}, "scene", "unknown scene 'kitchen' (known: bin, shelf, table)"),
            ({"scene": "/etc/passwd"}, "scene", "path characters"),
            ({"scene": 5}, "scene", "scene name or an inline scene"),
            ({}, "scene", "required"),
            ({"scene": "table", "time_limit": -1}, "time_limit", "> 0"),
            ({"scene": "table", "time_limit": "soon"}, "time_limit", "number"),
            ({"scene": "table", "algorithm": "fast"}, "algorithm", "coupled"),
            ({"scene": "table", "iterations": 5}, "iterations", "decoupled"),
            ({"scene": "table", "seed": -1}, "seed", ">= 0"),
            ({"scene": "table", "colour": "red"}, "colour", "unknown field"),
            ({"scene": "table", "parameters": {"warp": 9}}, "parameters.warp", "unknown"),
            ({"scene": "table", "parameters": {"time_limit": 9}}, "parameters.time_limit",
             "top-level"),
            ({"scene": "table", "parameters": {"p_max": 5}}, "parameters.p_max", "p_max"),
            ({"scene": {"name": "x"}}, "scene", "robot_base"),
        ]
        for params, field, words in cases:
            with self.subTest(field=field, params=params):
                response = self.server.call("plan", params, request_id="p")
                self.assertError(response, -32602, field, "p", words)
        quality = self.server.call("grasp.quality", {"contacts": [{"position": [1, 0],
                                                                   "normal": [1, 0, 0]}]})
        self.assertError(quality, -32602, "contacts[0].position", 1)
        self.assertError(self.server.call("server.info", {"verbose": True}), -32602, "verbose", 1)
        self.assertError(self.server.call("server.info", [1, 2]), -32602, "params", 1)

    def test_a_line_over_the_size_limit_closes_the_connection(self):
        with self.server.connect() as c:
            line = b'{"jsonrpc": "2.0", "id": 1, "method": "server.info", "params": {"x": "' + \
                   b"a" * (20 << 20) + b'"}}\n'
            sender = threading.Thread(target=lambda: sendall_ignoring_reset(c.socket, line))
            sender.start()
            response = c.read()
            closed = c.read()
            sender.join()
        self.assertError(response, -32004, contains="16777216")
        self.assertIsNone(closed, "the server closes the connection")
        self.assertEqual(self.server.call("server.info")["result"]["name"], "hfts-server")


def sendall_ignoring_reset(sock, data):
    try:
        sock.sendall(data)
    except OSError:
        pass


class OneWorker(ServerTest):
    OPTIONS = ("--workers", "1", "--queue", "1", "--max-time-limit", "30")

    def running(self):
        return self.server.call("server.info")["result"]["load"]["running"]

    def assertWorkerFreed(self):
        """The worker is idle again and serves the next plan at once."""
        self.assertTrue(wait_until(lambda: self.running() == 0, timeout=2.0))
        began = time.monotonic()
        plan = self.server.call("plan", BIN)["result"]
        self.assertTrue(plan["success"])
        self.assertLess(time.monotonic() - began, plan["stats"]["planning_time"] + 1.0)

    def test_cancel_stops_a_running_plan(self):
        with self.server.connect() as c:
            c.request("plan", ENDLESS, request_id="long")
            self.assertTrue(wait_until(lambda: self.running() == 1))
            began = time.monotonic()
            c.request("cancel", {"id": "long"}, request_id="stop")
            responses = {r["id"]: r for r in (c.read(), c.read())}
            stopped = time.monotonic() - began
        self.assertEqual(responses["stop"]["result"], {"id": "long", "cancelled": True})
        plan = responses["long"]["result"]
        self.assertFalse(plan["success"])
        self.assertEqual(plan["reason"], "cancelled")
        self.assertLess(stopped, 1.0)
        self.assertWorkerFreed()

    def test_disconnecting_cancels_the_clients_plans(self):
        c = self.server.connect()
        c.request("plan", ENDLESS, request_id="abandoned")
        self.assertTrue(wait_until(lambda: self.running() == 1))
        c.close()
        self.assertWorkerFreed()
        self.assertRegex(self.server.log_text(), r'id="abandoned" plan [\d.]+s ok cancelled')

    def test_a_full_queue_answers_busy(self):
        with self.server.connect() as c:
            c.request("plan", ENDLESS, request_id=0)
            self.assertTrue(wait_until(lambda: self.running() == 1))
            c.request("plan", ENDLESS, request_id=1)
            c.request("plan", ENDLESS, request_id=2)
            busy = c.read()  # one plan runs, one waits, no room for the third
            self.assertError(busy, -32001, request_id=2, contains="busy")
            c.request("cancel", {"id": 0}, request_id="c0")
            c.request("cancel", {"id": 1}, request_id="c1")
            responses = {r["id"]: r for r in (c.read() for _ in range(4))}
        self.assertEqual(responses[0]["result"]["reason"], "cancelled")
        self.assertEqual(responses[1]["result"]["reason"], "cancelled")
        self.assertEqual(responses[1]["result"]["message"], "cancelled before it started")
        self.assertWorkerFreed()

    def test_the_time_limit_is_capped(self):
        plan = self.server.call("plan", dict(BIN, time_limit=1000))["result"]
        self.assertEqual(plan["time_limit"], 30)
        self.assertEqual(self.server.call("plan", dict(BIN, time_limit=5))["result"]["time_limit"], 5)


class Lifecycle(unittest.TestCase):
    """Each test starts (and ends) its own server."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hfts-server-life-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def assertGracefulStop(self, stop):
        """A plan is running when stop() is called: it is cancelled, its
        reply is still sent, and the server exits with 0."""
        server = start_server(self.tmp, "--workers", "1")
        c = server.connect()
        c.request("plan", ENDLESS, request_id="running")
        self.assertTrue(wait_until(
            lambda: server.call("server.info")["result"]["load"]["running"] == 1))
        idle = server.connect()
        stop(server)
        reply = c.read()
        self.assertEqual(reply["id"], "running")
        self.assertEqual(reply["result"]["reason"], "cancelled")
        self.assertIsNone(c.read(), "then the connection is closed")
        self.assertIsNone(idle.read(), "idle connections are closed too")
        self.assertEqual(server.process.wait(timeout=10), 0)
        self.assertEqual(server.stop(), 0)
        self.assertIn("shutting down", server.log_text())
        c.close()
        idle.close()
        with self.assertRaises(OSError):
            socket.create_connection((server.host, server.port), timeout=5)

    def test_shutdown_request_stops_the_server_cleanly(self):
        def shutdown(server):
            with server.connect() as c:
                self.assertEqual(c.call("shutdown")["result"], {"shutting_down": True})
        self.assertGracefulStop(shutdown)

    def test_sigterm_and_sigint_stop_the_server_cleanly(self):
        self.assertGracefulStop(lambda server: server.process.send_signal(signal.SIGTERM))
        self.assertGracefulStop(lambda server: server.process.send_signal(signal.SIGINT))

    def test_reload_reads_the_database_directory_again(self):
        db = os.path.join(self.tmp, "db")
        shutil.copytree(DB_DIR, db)
        os.remove(os.path.join(db, "blob.h5"))
        server = RunningServer(SERVER, SOURCE_DIR, db, os.path.join(self.tmp, "log"),
                               "--workers", "1")
        try:
            names = lambda: [o["name"] for o in server.call("objects.list")["result"]["objects"]]
            self.assertEqual(names(), ["mug"])
            shutil.copy(os.path.join(DB_DIR, "blob.h5"), db)
            with open(os.path.join(db, "broken.h5"), "wb") as f:
                f.write(b"not a database")
            result = server.call("reload")["result"]
            self.assertEqual(result["objects"], ["blob", "mug"])
            self.assertEqual(result["scenes"], ["bin", "shelf", "table"])
            self.assertEqual(len(result["skipped"]), 1)
            self.assertIn("broken.h5", result["skipped"][0])
            self.assertEqual(names(), ["blob", "mug"])
            self.assertTrue(server.call("plan", BIN)["result"]["success"])
            os.remove(os.path.join(db, "kr5_sdh_hand_map.h5"))
            failed = server.call("reload")
            self.assertEqual(failed["error"]["code"], -32005)
            self.assertIn("hand reachability map", failed["error"]["message"])
            self.assertEqual(names(), ["blob", "mug"], "the old data is still served")
        finally:
            self.assertEqual(server.stop(), 0)

    def test_a_server_that_cannot_start_says_why_and_exits_with_1(self):
        def run(*args):
            return subprocess.run([SERVER, *args], capture_output=True, text=True,
                                  timeout=60, cwd=SOURCE_DIR, stdin=subprocess.DEVNULL)
        missing = run("--port", "0", "--db", os.path.join(self.tmp, "none"))
        self.assertEqual(missing.returncode, 1)
        self.assertIn("none does not exist", missing.stderr)
        bad_bind = run("--port", "0", "--db", DB_DIR, "--bind", "localhost:80")
        self.assertEqual(bad_bind.returncode, 1)
        self.assertIn("bind address 'localhost:80' is not an IPv4 or IPv6 address", bad_bind.stderr)
        server = start_server(self.tmp, "--workers", "1")
        try:
            taken = run("--db", DB_DIR, "--port", str(server.port))
            self.assertEqual(taken.returncode, 1)
            self.assertIn(f"cannot listen on 127.0.0.1:{server.port}", taken.stderr)
        finally:
            self.assertEqual(server.stop(), 0)


def non_loopback_address():
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.connect(("192.0.2.1", 9))  # no packet is sent: this only picks a route
            address = s.getsockname()[0]
        return None if address.startswith("127.") else address
    except OSError:
        return None


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--server", required=True)
    parser.add_argument("--preprocess", required=True)
    parser.add_argument("--source-dir", required=True)
    args, rest = parser.parse_known_args()
    SERVER, PREPROCESS, SOURCE_DIR = map(os.path.abspath,
                                         (args.server, args.preprocess, args.source_dir))
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
