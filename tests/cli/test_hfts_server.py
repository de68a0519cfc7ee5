#!/usr/bin/env python3
"""Integration tests of hfts-server over raw sockets (docs/protocol.md): every
method, pipelining, batches and 16 concurrent clients.
Run by ctest with Debian's /usr/bin/python3; standard library only."""

import json
import os
import threading

from hfts_server_fixture import (BIN, CONFIG, ENDLESS, NO_PHYSICS, QUALITY, QUALITY_EPSILON,
                                 TABLE, ServerTest, run_tests)


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
        self.assertEqual(info["limits"]["max_threads"], 2)  # one per planning worker
        self.assertEqual(info["load"]["workers"], 2)
        names = {p["name"] for p in info["planner_parameters"]}
        self.assertTrue({"p_max", "kappa", "step_size"} <= names)
        self.assertEqual(set(info["methods"]), {"auth", "server.info", "objects.list",
                                                "scenes.list", "plan", "grasp.quality", "cancel",
                                                "shutdown", "reload"})
        self.assertFalse(info["authentication"])

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
        # The mug rests on the table: its bottom 1 mm above the table's top (z = -1 mm).
        for got, want in zip(plan["object_pose"]["position"], [0.55, 0, 0]):
            self.assertAlmostEqual(got, want, places=12)
        # grasp.quality of the planned contacts (object frame) gives the plan's epsilon back.
        quality = self.server.call("grasp.quality", {"object": "mug",
                                                     "contacts": plan["grasp"]["contacts_object"]})
        self.assertAlmostEqual(quality["result"]["epsilon"], plan["grasp"]["epsilon"], places=12)

    def test_decoupled_plan_with_an_inline_scene_and_parameters(self):
        with open(os.path.join(CONFIG.source_dir, "objects", "scenes", "bin.json")) as f:
            scene = json.load(f)
        params = {"scene": scene, "algorithm": "decoupled", "iterations": 30, "seed": 2,
                  "time_limit": 20, "parameters": {"step_size": 0.12, "kappa": 4, **NO_PHYSICS}}
        plan = self.server.call("plan", params)["result"]
        self.assertValidPlan(plan, "bin", self.server.call("server.info")["result"])
        self.assertEqual((plan["algorithm"], plan["object"]), ("decoupled", "blob"))

    def test_a_racing_plan_names_the_seed_that_replays_it(self):
        info = self.server.call("server.info")["result"]
        raced = self.server.call("plan", dict(BIN, parameters={"threads": 2, **NO_PHYSICS}))["result"]
        self.assertValidPlan(raced, "bin", info)
        self.assertEqual(raced["seed"], 1)
        replayed = self.server.call("plan", dict(BIN, seed=raced["plan_seed"]))["result"]
        self.assertEqual(replayed["plan_seed"], raced["plan_seed"])
        self.assertEqual(replayed["path"], raced["path"])
        error = self.server.call("plan", dict(BIN, parameters={"threads": 3, **NO_PHYSICS}))["error"]
        self.assertEqual(error["data"]["field"], "parameters.threads")
        self.assertIn("at most 2 on this server", error["message"])

    def test_an_unreachable_object_is_a_result_not_an_error(self):
        params = dict(ENDLESS, time_limit=0.3)
        plan = self.server.call("plan", params)["result"]
        self.assertFalse(plan["success"])
        self.assertIn(plan["reason"], ("object_unreachable", "no_valid_goal"))
        self.assertTrue(plan["message"])
        self.assertIsNone(plan["grasp"])
        self.assertEqual(plan["path"], [])
        self.assertLess(plan["stats"]["planning_time"], 0.3 + 0.2)

    def test_grasp_quality_matches_hfts_quality(self):
        result = self.server.call("grasp.quality", QUALITY)["result"]
        self.assertAlmostEqual(result["epsilon"], QUALITY_EPSILON, places=12)
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
        self.assertAlmostEqual(by_id["2.5"]["result"]["epsilon"], QUALITY_EPSILON, places=12)
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


if __name__ == "__main__":
    run_tests()
