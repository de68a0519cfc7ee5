#!/usr/bin/env python3
"""Plans through HAProxy, which speaks TLS to the clients, in front of three
hfts-server instances with tokens (scripts/scale_out.sh --tls,
deploy/haproxy/hfts.cfg, docs/security.md): the
health check (which authenticates) sees every instance; one instance
killed mid-load loses no request, because the clients (Python and
hfts-client, with a plan token) send their calls again and a plan is
determined by its seed; a plan token cannot shut an instance down through
the balancer. Standard library only; run by ctest.

    test_scale_out.py --server S --preprocess P --client C --source-dir D
"""

import json
import os
import queue
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import unittest

from hfts_server_fixture import CONFIG, run_tests, wait_until

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "client",
                                "python"))
import hfts_client  # noqa: E402

INSTANCES = 3
PLAN_TOKEN = "scale-out-plan-token-51f0c2"
ADMIN_TOKEN = "scale-out-admin-token-8d3e7a"
SEEDS = range(1, 19)
PYTHON_CLIENTS = 4  # threads with one connection each, kept across calls
COMMAND_LINE_CLIENTS = 2  # threads that run hfts-client once per plan


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Balancer:
    """scripts/scale_out.sh as a child process."""

    def __init__(self, run_dir):
        self.run_dir = run_dir
        self.port = free_port()
        tokens = os.path.join(run_dir, "tokens")
        self.token_file = os.path.join(run_dir, "plan.token")
        for path, text in ((tokens, f"plan {PLAN_TOKEN} clients\nadmin {ADMIN_TOKEN} ops\n"),
                           (self.token_file, PLAN_TOKEN + "\n")):
            with open(path, "w") as f:
                f.write(text)
            os.chmod(path, 0o600)
        script = os.path.join(CONFIG.source_dir, "scripts", "scale_out.sh")
        self.process = subprocess.Popen(
            [script, str(INSTANCES), "--port", str(self.port), "--base-port", "0",
             "--db", CONFIG.db_dir, "--bin", os.path.dirname(CONFIG.server), "--dir", run_dir,
             "--auth-tokens", tokens, "--check-token", self.token_file, "--tls",
             "--", "--quiet"],
            stdout=subprocess.PIPE, text=True)
        self.ca_file = os.path.join(run_dir, "cert.pem")  # scale_out.sh --tls makes it
        self.instances = {}  # name in the HAProxy config -> pid
        for line in self.process.stdout:
            words = line.split()
            if words[0] == "instance":
                self.instances[f"hfts{words[1]}"] = int(words[3])
            if line.startswith("balancer listening"):
                return
        raise RuntimeError(f"scale_out.sh ended ({self.process.wait()}) before the balancer "
                           "was ready")

    def stats(self):
        """HAProxy's view of each instance: name -> (status, current connections)."""
        with socket.socket(socket.AF_UNIX) as s:
            s.connect(os.path.join(self.run_dir, "haproxy.sock"))
            s.sendall(b"show stat\n")
            text = b"".join(iter(lambda: s.recv(65536), b"")).decode()
        header, *rows = [line.split(",") for line in text.splitlines() if line]
        column = {name: i for i, name in enumerate(header[0].lstrip("# ").split(",") + header[1:])}
        return {row[1]: (row[column["status"]], int(row[column["scur"]]))
                for row in rows if row[0] == "hfts_servers" and row[1].startswith("hfts")}

    def stop(self):
        self.process.send_signal(signal.SIGTERM)
        return self.process.wait(timeout=30)


def plan_params(seed):
    # Without the physics check: the balancer is under test, not the grasps.
    return {"scene": "table", "seed": seed, "time_limit": 20, "parameters": {"physics_check": 0}}


class ScaleOut(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.run_dir = os.environ.get("RUN_DIR") or tempfile.mkdtemp(prefix="hfts-scale-out-")
        cls.balancer = Balancer(cls.run_dir)

    @classmethod
    def tearDownClass(cls):
        code = cls.balancer.stop()
        for pid in cls.balancer.instances.values():
            wait_until(lambda: not os.path.exists(f"/proc/{pid}"), timeout=10)
            assert not os.path.exists(f"/proc/{pid}"), f"instance {pid} still runs"
        assert code == 0, code

    def plan_all(self, during=None):
        """Plans every seed through the balancer with Python and command-line
        clients at once; during(results so far) runs once after the first few
        answers. Returns seed -> result, and the retries the clients made."""
        work = queue.Queue()
        for seed in SEEDS:
            work.put(seed)
        results, retries, lock = {}, [0], threading.Lock()

        def python_client():
            with hfts_client.HftsClient("127.0.0.1", self.balancer.port, timeout=120,
                                        retries=3, backoff=0.2, token=PLAN_TOKEN,
                                        ca_file=self.balancer.ca_file) as client:
                while True:
                    try:
                        seed = work.get_nowait()
                    except queue.Empty:
                        break
                    result = client.plan(**plan_params(seed))
                    with lock:
                        results[seed] = result
            with lock:
                retries[0] += client.reconnections

        def command_line_client():
            while True:
                try:
                    seed = work.get_nowait()
                except queue.Empty:
                    return
                run = subprocess.run(
                    [CONFIG.client, "--port", str(self.balancer.port), "--retries", "3",
                     "--token-file", self.balancer.token_file,
                     "--ca-file", self.balancer.ca_file, "--json",
                     "plan", "--scene", "table", "--seed", str(seed), "--time-limit", "20",
                     "--param", "physics_check=0"],
                    capture_output=True, text=True, timeout=120)
                self.assertIn(run.returncode, (0, 3), run.stderr)
                with lock:
                    results[seed] = json.loads(run.stdout)
                    retries[0] += run.stderr.count("trying again")

        threads = [threading.Thread(target=python_client) for _ in range(PYTHON_CLIENTS)]
        threads += [threading.Thread(target=command_line_client)
                    for _ in range(COMMAND_LINE_CLIENTS)]
        for thread in threads:
            thread.start()
        if during:
            wait_until(lambda: len(results) >= 4, timeout=120)
            during()
        for thread in threads:
            thread.join(timeout=300)
        return results, retries[0]

    def every_instance_up(self):
        states = {name: status for name, (status, _) in self.balancer.stats().items()}
        return states == {name: "UP" for name in self.balancer.instances}

    def test_a_plan_token_cannot_shut_an_instance_down_through_the_balancer(self):
        self.assertTrue(wait_until(self.every_instance_up, timeout=10), self.balancer.stats())
        with hfts_client.HftsClient("127.0.0.1", self.balancer.port, timeout=60, retries=0,
                                    token=PLAN_TOKEN, ca_file=self.balancer.ca_file) as client:
            with self.assertRaises(hfts_client.RpcError) as caught:
                client.shutdown()
            self.assertEqual(caught.exception.code, -32003)
        with hfts_client.HftsClient("127.0.0.1", self.balancer.port, timeout=60, retries=0,
                                    ca_file=self.balancer.ca_file) as client:  # no token
            with self.assertRaises(hfts_client.RpcError) as caught:
                client.shutdown()
            self.assertEqual(caught.exception.code, -32009)
        # The balancer speaks TLS only: plain JSON gets no answer.
        with socket.create_connection(("127.0.0.1", self.balancer.port), timeout=30) as s:
            s.sendall(b'{"jsonrpc":"2.0","id":1,"method":"server.info"}\n')
            self.assertNotIn(b'"jsonrpc"', s.makefile("rb").read())
        for pid in self.balancer.instances.values():
            self.assertTrue(os.path.exists(f"/proc/{pid}"), "an instance stopped")
        self.assertTrue(self.every_instance_up(), self.balancer.stats())

    def test_an_instance_killed_mid_load_loses_no_request(self):
        # Every instance passes the health check (auth and server.info answered).
        self.assertTrue(wait_until(self.every_instance_up, timeout=10), self.balancer.stats())
        reference, _ = self.plan_all()
        self.assertEqual(sorted(reference), list(SEEDS))
        self.assertTrue(all(result["success"] for result in reference.values()))

        killed = []

        def kill_the_busiest_instance():
            connections = {name: current for name, (_, current) in self.balancer.stats().items()}
            busiest = max(connections, key=connections.get)
            self.assertGreater(connections[busiest], 0)
            os.kill(self.balancer.instances[busiest], signal.SIGKILL)
            killed.append(busiest)

        results, retries = self.plan_all(during=kill_the_busiest_instance)
        print(f"\n{killed[0]} killed mid-load; the clients sent {retries} calls again",
              file=sys.stderr)
        self.assertEqual(sorted(results), list(SEEDS), "a request was lost")
        self.assertGreaterEqual(retries, 1, "the kill hit no call in flight")
        for seed in SEEDS:
            self.assertEqual(results[seed]["path"], reference[seed]["path"], seed)
            self.assertEqual(results[seed]["plan_seed"], seed)
        # The health check takes the dead instance out; the others stay.
        self.assertTrue(wait_until(lambda: self.balancer.stats()[killed[0]][0] == "DOWN",
                                   timeout=10))
        self.assertEqual(sum(status == "UP" for status, _ in self.balancer.stats().values()),
                         INSTANCES - 1)


if __name__ == "__main__":
    run_tests(with_client=True)
