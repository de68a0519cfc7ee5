#!/usr/bin/env python3
"""Integration tests of hfts-server: cancellation, disconnects, the queue bound,
the time-limit cap, shutdown, signals, reload and start-up failures.
Run by ctest with Debian's /usr/bin/python3; standard library only."""

import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
import unittest

from hfts_server_fixture import (BIN, CONFIG, ENDLESS, RunningServer, ServerTest, run_tests,
                                 wait_until)


class OneWorker(ServerTest):
    OPTIONS = ("--workers", "1", "--queue", "1", "--max-time-limit", "30")

    def assertWorkerFreed(self):
        """The worker is idle again and serves the next plan at once."""
        self.assertTrue(wait_until(lambda: self.server.running() == 0, timeout=2.0))
        began = time.monotonic()
        plan = self.server.call("plan", BIN)["result"]
        self.assertTrue(plan["success"])
        self.assertLess(time.monotonic() - began, plan["stats"]["planning_time"] + 1.0)

    def test_cancel_stops_a_running_plan(self):
        with self.server.connect() as c:
            c.request("plan", ENDLESS, request_id="long")
            self.assertTrue(wait_until(lambda: self.server.running() == 1))
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
        self.assertTrue(wait_until(lambda: self.server.running() == 1))
        c.close()
        self.assertWorkerFreed()
        self.assertRegex(self.server.log_text(), r'id="abandoned" plan [\d.]+s ok cancelled')

    def test_a_full_queue_answers_busy(self):
        with self.server.connect() as c:
            c.request("plan", ENDLESS, request_id=0)
            self.assertTrue(wait_until(lambda: self.server.running() == 1))
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
        plan = self.server.call("plan", dict(BIN, time_limit=5))["result"]
        self.assertEqual(plan["time_limit"], 5)


class Lifecycle(unittest.TestCase):
    """Each test starts (and ends) its own server."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hfts-server-life-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def assertGracefulStop(self, stop):
        """A plan is running when stop() is called: it is cancelled, its
        reply is still sent, and the server exits with 0."""
        server = RunningServer(os.path.join(self.tmp, "server.log"), "--workers", "1")
        c = server.connect()
        c.request("plan", ENDLESS, request_id="running")
        self.assertTrue(wait_until(lambda: server.running() == 1))
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
        shutil.copytree(CONFIG.db_dir, db)
        os.remove(os.path.join(db, "blob.h5"))
        server = RunningServer(os.path.join(self.tmp, "log"), "--workers", "1", db_dir=db)
        try:
            names = lambda: [o["name"] for o in server.call("objects.list")["result"]["objects"]]
            self.assertEqual(names(), ["mug"])
            shutil.copy(os.path.join(CONFIG.db_dir, "blob.h5"), db)
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
            return subprocess.run([CONFIG.server, *args], capture_output=True, text=True,
                                  timeout=60, cwd=CONFIG.source_dir, stdin=subprocess.DEVNULL)
        missing = run("--port", "0", "--db", os.path.join(self.tmp, "none"))
        self.assertEqual(missing.returncode, 1)
        self.assertIn("none does not exist", missing.stderr)
        bad_bind = run("--port", "0", "--db", CONFIG.db_dir, "--bind", "localhost:80")
        self.assertEqual(bad_bind.returncode, 1)
        self.assertIn("bind address 'localhost:80' is not an IPv4 or IPv6 address", bad_bind.stderr)
        server = RunningServer(os.path.join(self.tmp, "server.log"), "--workers", "1")
        try:
            taken = run("--db", CONFIG.db_dir, "--port", str(server.port))
            self.assertEqual(taken.returncode, 1)
            self.assertIn(f"cannot listen on 127.0.0.1:{server.port}", taken.stderr)
        finally:
            self.assertEqual(server.stop(), 0)


if __name__ == "__main__":
    run_tests()
