#!/usr/bin/env python3
"""The clients' retries on a lost connection (hfts-client and
client/python/hfts_client.py), against a scripted stand-in for a server:
each connection it accepts either answers every request, drops the
connection after reading one, or closes it halfway through writing the
answer, the ways an instance behind a balancer dies mid-call. Standard library only; run by ctest with /usr/bin/python3.

    test_client_retries.py --client build/bin/hfts-client
"""

import argparse
import json
import os
import socket
import subprocess
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "client",
                                "python"))
import hfts_client  # noqa: E402  (the module under test, client/python)

CLIENT = None  # the hfts-client program


class ScriptedServer:
    """Listens on an ephemeral loopback port; connection k follows script[k]
    ("drop": read one request, then close; "half": read one request, send
    the first half of its answer, then close; "answer": answer every request
    with its method and the connection's number). listen_after delays
    listen() so that the first connects are refused."""

    def __init__(self, script, listen_after=0.0):
        self.script = list(script)
        self.requests = []  # (connection number, request) in arrival order
        self._socket = socket.socket()
        self._socket.bind(("127.0.0.1", 0))
        self.port = self._socket.getsockname()[1]
        self._listen_after = listen_after
        if not listen_after:
            self._socket.listen()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def connections(self):
        return len({number for number, _ in self.requests})

    def close(self):
        self._socket.close()

    def _serve(self):
        if self._listen_after:
            time.sleep(self._listen_after)
            self._socket.listen()
        for number, behaviour in enumerate(self.script):
            try:
                peer, _ = self._socket.accept()
            except OSError:
                return
            with peer, peer.makefile("rb") as reader:
                for line in reader:
                    request = json.loads(line)
                    self.requests.append((number, request))
                    if behaviour == "drop":
                        break
                    result = {"method": request["method"], "connection": number}
                    answer = json.dumps({"jsonrpc": "2.0", "id": request["id"],
                                         "result": result}).encode() + b"\n"
                    if behaviour == "half":
                        peer.sendall(answer[:len(answer) // 2])
                        break
                    peer.sendall(answer)


class Scripted(unittest.TestCase):
    def serve(self, *script, listen_after=0.0):
        server = ScriptedServer(script, listen_after)
        self.addCleanup(server.close)
        return server


class CommandLineClient(Scripted):
    def client(self, server, *args):
        return subprocess.run([CLIENT, "--port", str(server.port), "--json", *args],
                              capture_output=True, text=True, timeout=60)

    def test_a_dropped_call_is_sent_again_on_a_new_connection(self):
        server = self.serve("drop", "answer")
        result = self.client(server, "plan", "--scene", "table", "--seed", "7")
        # The stand-in's result has no "success": hfts-client cannot print it
        # as a plan, but it must have got it from the second connection.
        self.assertEqual(server.connections(), 2)
        first, second = (request for _, request in server.requests)
        self.assertEqual(first["params"], second["params"])
        self.assertEqual(second["params"]["seed"], 7)
        self.assertIn("the server closed the connection; trying again (attempt 2 of 3)",
                      result.stderr)

    def test_info_through_a_retry(self):
        server = self.serve("drop", "drop", "answer")
        result = self.client(server, "info")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(json.loads(result.stdout), {"method": "server.info", "connection": 2})
        self.assertIn("attempt 3 of 3", result.stderr)

    def test_an_answer_cut_off_midway_is_asked_for_again(self):
        server = self.serve("half", "answer")
        result = self.client(server, "info")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(json.loads(result.stdout), {"method": "server.info", "connection": 1})
        self.assertIn("the server closed the connection; trying again (attempt 2 of 3)",
                      result.stderr)

    def test_retries_run_out(self):
        server = self.serve("drop", "drop", "drop", "answer")
        result = self.client(server, "info")
        self.assertEqual(result.returncode, 1)
        self.assertIn("the server closed the connection", result.stderr.splitlines()[-1])
        self.assertEqual(server.connections(), 3)

    def test_no_retries_when_asked_for_none(self):
        server = self.serve("drop", "answer")
        result = self.client(server, "--retries", "0", "info")
        self.assertEqual(result.returncode, 1)
        self.assertEqual(server.connections(), 1)

    def test_shutdown_is_never_repeated(self):
        server = self.serve("drop", "answer")
        result = self.client(server, "shutdown")
        self.assertEqual(result.returncode, 1)
        self.assertEqual(server.connections(), 1)

    def test_connecting_is_retried_until_the_server_listens(self):
        server = self.serve("answer", listen_after=0.3)
        result = self.client(server, "--retries", "5", "info")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("cannot connect to 127.0.0.1:", result.stderr)

    def test_a_negative_retry_count_is_refused(self):
        server = self.serve("answer")
        result = self.client(server, "--retries", "-1", "info")
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("--retries", result.stderr)
        self.assertEqual(server.connections(), 0)


class PythonClient(Scripted):
    def test_a_dropped_call_is_sent_again(self):
        server = self.serve("drop", "answer")
        with hfts_client.HftsClient("127.0.0.1", server.port, timeout=30, backoff=0.05) as client:
            self.assertEqual(client.plan("table", seed=3), {"method": "plan", "connection": 1})
            self.assertEqual(client.reconnections, 1)
            # The new connection serves the calls that follow.
            self.assertEqual(client.info(), {"method": "server.info", "connection": 1})
        (_, first), (_, second), _ = server.requests
        self.assertEqual(first["params"], second["params"])

    def test_an_answer_cut_off_midway_is_asked_for_again(self):
        # Not a JSON error: half a line is a lost connection.
        server = self.serve("half", "answer")
        with hfts_client.HftsClient("127.0.0.1", server.port, timeout=30, backoff=0.05) as client:
            self.assertEqual(client.plan("table", seed=5), {"method": "plan", "connection": 1})
            self.assertEqual(client.reconnections, 1)
        (_, first), (_, second) = server.requests
        self.assertEqual(first["params"], second["params"])

    def test_retries_run_out(self):
        server = self.serve("drop", "drop")
        with hfts_client.HftsClient("127.0.0.1", server.port, timeout=30, retries=1,
                                    backoff=0.05) as client:
            with self.assertRaises(ConnectionError):
                client.info()
        self.assertEqual(server.connections(), 2)

    def test_a_call_after_a_failed_one_connects_again(self):
        server = self.serve("drop", "drop", "answer")
        with hfts_client.HftsClient("127.0.0.1", server.port, timeout=30, retries=0) as client:
            with self.assertRaises(ConnectionError):
                client.info()
            with self.assertRaises(ConnectionError):
                client.info()
            self.assertEqual(client.info()["connection"], 2)

    def test_cancel_and_shutdown_are_never_repeated(self):
        for method in ("cancel", "shutdown"):
            server = self.serve("drop", "answer")
            with hfts_client.HftsClient("127.0.0.1", server.port, timeout=30,
                                        backoff=0.05) as client:
                with self.assertRaises(ConnectionError):
                    client.call(method, {"id": 1} if method == "cancel" else {})
            self.assertEqual(server.connections(), 1, method)

    def test_connecting_is_retried_until_the_server_listens(self):
        server = self.serve("answer", listen_after=0.3)
        with hfts_client.HftsClient("127.0.0.1", server.port, timeout=30, retries=5,
                                    backoff=0.1) as client:
            self.assertGreaterEqual(client.reconnections, 1)
            self.assertEqual(client.info()["connection"], 0)

    def test_nonsense_settings_are_refused(self):
        with self.assertRaises(ValueError):
            hfts_client.HftsClient("127.0.0.1", 1, retries=-1)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--client", required=True)
    args, rest = parser.parse_known_args()
    CLIENT = os.path.abspath(args.client)
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
