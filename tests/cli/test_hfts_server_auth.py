#!/usr/bin/env python3
"""Integration tests of hfts-server's access control (docs/security.md): tokens
and roles, the failed-auth delay and throttle, SIGHUP, the fair share between
clients, TLS with both clients, the start-up checks.
Run by ctest with Debian's /usr/bin/python3; standard library only."""

import os
import shutil
import signal
import socket
import ssl
import subprocess
import sys
import tempfile
import time
import unittest

from hfts_server_fixture import (CONFIG, ENDLESS, NO_PHYSICS, TABLE, RunningServer, run_tests,
                                 wait_until)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "client",
                                "python"))
import hfts_client  # noqa: E402  (client/python)
import server_attack  # noqa: E402  (tests/cli)

PLAN_TOKEN = "plan-token-6b0d5f2e9c1a4b7d"
ADMIN_TOKEN = "admin-token-3e8f1c7a2d9b5e40"
TOKENS = f"# test tokens\nplan {PLAN_TOKEN} alice\nadmin {ADMIN_TOKEN} operator\n"
UNAUTHORIZED, FORBIDDEN = -32009, -32003
QUICK_PLAN = {"scene": "table", "seed": 1, "time_limit": 5, "parameters": NO_PHYSICS}


def write_tokens(path, text, mode=0o600):
    with open(path, "w") as f:
        f.write(text)
    os.chmod(path, mode)


class WithTokens(unittest.TestCase):
    """A server with a plan and an admin token (a new one per test: some stop it)."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hfts-auth-")
        self.tokens = os.path.join(self.tmp, "tokens")
        write_tokens(self.tokens, TOKENS)
        self.server = RunningServer(os.path.join(self.tmp, "server.log"), "--workers", "1",
                                    "--auth-tokens", self.tokens)

    def tearDown(self):
        self.server.stop()
        shutil.rmtree(self.tmp, ignore_errors=True)

    def authenticated(self, token):
        c = self.server.connect()
        response = c.call("auth", {"token": token}, request_id="auth")
        self.assertIn("result", response, response)
        return c

    def assertRefused(self, response, code, contains, request_id=1):
        self.assertEqual(response["id"], request_id, response)
        self.assertEqual(response["error"]["code"], code, response)
        self.assertIn(contains, response["error"]["message"])

    def test_every_method_without_a_token_is_refused_and_has_no_effect(self):
        with self.server.connect() as c:
            for method, params in (("server.info", None), ("objects.list", None),
                                   ("scenes.list", None), ("plan", QUICK_PLAN),
                                   ("grasp.quality", {"contacts": []}), ("cancel", {"id": 1}),
                                   ("reload", None), ("shutdown", None)):
                self.assertRefused(c.call(method, params), UNAUTHORIZED, "call auth with a token")
            self.assertIsNone(self.server.process.poll())  # still running
        log = self.server.log_text().splitlines()
        self.assertEqual(sum("error -32009" in line for line in log), 8)
        self.assertFalse([line for line in log if " reload " in line and " ok" in line])
        with self.authenticated(ADMIN_TOKEN) as c:
            load = c.call("server.info")["result"]["load"]
        self.assertEqual((load["running"], load["queued"]), (0, 0))
        self.assertNotIn("shutting down", self.server.log_text())

    def test_a_plan_token_plans_but_cannot_reload_or_shut_down(self):
        with self.authenticated(PLAN_TOKEN) as c:
            info = c.call("server.info")["result"]
            self.assertTrue(info["authentication"])
            self.assertTrue(c.call("plan", QUICK_PLAN)["result"]["success"])
            self.assertRefused(c.call("reload"), FORBIDDEN, "reload needs the admin role")
            self.assertRefused(c.call("shutdown"), FORBIDDEN, "shutdown needs the admin role")
        self.assertIsNone(self.server.process.poll())
        self.assertIn("auth", self.server.log_text())
        self.assertIn("ok role plan (alice)", self.server.log_text())
        self.assertNotIn(PLAN_TOKEN, self.server.log_text())  # the log never shows a token

    def test_an_admin_token_reloads_and_shuts_down(self):
        with self.authenticated(ADMIN_TOKEN) as c:
            self.assertIn("objects", c.call("reload")["result"])
            self.assertEqual(c.call("shutdown")["result"], {"shutting_down": True})
        self.assertEqual(self.server.process.wait(timeout=30), 0)

    def test_a_wrong_token_is_answered_late_and_the_connection_closed(self):
        with self.server.connect() as c:
            began = time.monotonic()
            response = c.call("auth", {"token": "not-a-token-of-this-server"}, request_id="a")
            waited = time.monotonic() - began
            self.assertRefused(response, UNAUTHORIZED, "not accepted", request_id="a")
            self.assertGreaterEqual(waited, 0.9)
            self.assertIsNone(c.read())  # closed
        self.assertIn("error -32009", self.server.log_text())

    def test_repeated_failures_from_one_address_are_throttled(self):
        for _ in range(5):
            with self.server.connect() as c:
                c.call("auth", {"token": "guess-guess-guess-guess"})
        # Now even the right token is refused from this address, unchecked.
        with self.server.connect() as c:
            self.assertRefused(c.call("auth", {"token": ADMIN_TOKEN}), UNAUTHORIZED,
                               "too many failed authentications from 127.0.0.1")
        self.assertIsNone(self.server.process.poll())

    def test_sighup_rereads_the_tokens_and_a_removed_token_stops_working(self):
        plan = self.authenticated(PLAN_TOKEN)
        new_token = "rotated-token-9f3b2a6c4d1e"
        write_tokens(self.tokens, f"admin {ADMIN_TOKEN}\nplan {new_token} bob\n")
        self.server.process.send_signal(signal.SIGHUP)
        self.assertTrue(wait_until(lambda: "token file re-read: 2 tokens" in
                                   self.server.log_text()))
        self.assertRefused(plan.call("server.info"), UNAUTHORIZED, "no longer accepted")
        plan.close()
        with self.authenticated(new_token) as c:
            self.assertIn("result", c.call("scenes.list"))
        # A broken file leaves the tokens in force.
        write_tokens(self.tokens, "superuser x\n")
        self.server.process.send_signal(signal.SIGHUP)
        self.assertTrue(wait_until(lambda: "the old tokens stay in force" in
                                   self.server.log_text()))
        with self.authenticated(new_token) as c:
            self.assertIn("result", c.call("scenes.list"))


    def client(self, *args, env=None):
        return subprocess.run([CONFIG.client, "--port", str(self.server.port), *args],
                              capture_output=True, text=True, timeout=60,
                              env=dict(os.environ, **(env or {})))

    def test_hfts_client_sends_the_token_of_its_file_or_environment(self):
        plan_file = os.path.join(self.tmp, "plan.token")
        write_tokens(plan_file, PLAN_TOKEN + "\n")
        result = self.client("--token-file", plan_file, "--json", "info")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn('"authentication": true', result.stdout)
        result = self.client("--token-file", plan_file, "shutdown")
        self.assertEqual(result.returncode, 1)
        self.assertIn("shutdown needs the admin role", result.stderr)
        result = self.client("info")  # no token at all
        self.assertEqual(result.returncode, 1)
        self.assertIn("call auth with a token first", result.stderr)
        result = self.client("shutdown", env={"HFTS_TOKEN": ADMIN_TOKEN})
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(self.server.process.wait(timeout=30), 0)

    def test_the_python_client_authenticates_and_reports_a_refusal(self):
        with hfts_client.HftsClient(self.server.host, self.server.port, timeout=60,
                                    token=PLAN_TOKEN) as client:
            self.assertTrue(client.info()["authentication"])
            with self.assertRaises(hfts_client.RpcError) as caught:
                client.reload()
            self.assertEqual(caught.exception.code, FORBIDDEN)
        with self.assertRaises(hfts_client.RpcError) as caught:
            hfts_client.HftsClient(self.server.host, self.server.port, timeout=60,
                                   token="not-a-token-of-this-server")
        self.assertEqual(caught.exception.code, UNAUTHORIZED)


class FairShare(unittest.TestCase):
    """Two workers; a client (a token) may have 3 plans queued or running."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hfts-fair-")
        tokens = os.path.join(self.tmp, "tokens")
        write_tokens(tokens, TOKENS)
        self.server = RunningServer(os.path.join(self.tmp, "server.log"), "--workers", "2",
                                    "--auth-tokens", tokens, "--max-plans-per-client", "3")

    def tearDown(self):
        self.assertEqual(self.server.stop(), 0)
        shutil.rmtree(self.tmp, ignore_errors=True)

    def connect(self, token):
        c = self.server.connect()
        self.assertIn("result", c.call("auth", {"token": token}, request_id="auth"))
        return c

    def test_a_flooding_client_leaves_room_for_another(self):
        def slow(seconds):  # a plan that runs its whole time limit
            return dict(ENDLESS, time_limit=seconds, parameters=NO_PHYSICS)
        flood = [self.connect(PLAN_TOKEN), self.connect(PLAN_TOKEN)]  # one client, two links
        try:
            # f0 frees a worker after 2 s, f1 holds the other for 12 s, f2 waits.
            for i, seconds in enumerate((2, 12, 6)):
                flood[0].request("plan", slow(seconds), request_id=f"f{i}")
            with self.connect(ADMIN_TOKEN) as watch:
                def load():
                    return watch.call("server.info")["result"]["load"]
                self.assertTrue(wait_until(lambda: (load()["running"], load()["queued"]) == (2, 1)))
            # The same token on another connection is the same client: over its cap.
            busy = flood[1].call("plan", slow(2), request_id="f3")
            self.assertEqual(busy["error"]["code"], -32001, busy)
            self.assertIn("this client already has 3 plans", busy["error"]["message"])
            with self.connect(ADMIN_TOKEN) as other:
                other.request("plan", dict(TABLE, time_limit=20), request_id="other")
                answer = other.read()
            self.assertTrue(answer["result"]["success"], answer)
            replies = [flood[0].read()["id"] for _ in range(3)]
            self.assertEqual(sorted(replies), ["f0", "f1", "f2"])
            # The first free worker (f0's, after 2 s) took it before the
            # flood's f2, which came first, so it was answered first: in
            # arrival order it would have started after f2's 6 s (f1 holds
            # the other worker for 12 s), whatever the machine's load.
            log = self.server.log_text()
            self.assertLess(log.index("id=\"other\" plan"), log.index("id=\"f2\" plan"))
        finally:
            for c in flood:
                c.close()


def make_certificate(directory, host="localhost"):
    """A self-signed certificate for host and 127.0.0.1: (certificate, key) paths."""
    cert, key = os.path.join(directory, "cert.pem"), os.path.join(directory, "key.pem")
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", key,
                    "-out", cert, "-days", "2", "-subj", f"/CN={host}", "-addext",
                    f"subjectAltName=DNS:{host},IP:127.0.0.1"],
                   check=True, capture_output=True)
    return cert, key


class Tls(unittest.TestCase):
    """A server with tokens that speaks TLS with a self-signed certificate."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-tls-")
        cls.cert, key = make_certificate(cls.tmp)
        tokens = os.path.join(cls.tmp, "tokens")
        write_tokens(tokens, TOKENS)
        cls.token_file = os.path.join(cls.tmp, "plan.token")
        write_tokens(cls.token_file, PLAN_TOKEN + "\n")
        cls.server = RunningServer(os.path.join(cls.tmp, "server.log"), "--workers", "1",
                                   "--auth-tokens", tokens, "--tls-cert", cls.cert,
                                   "--tls-key", key)

    @classmethod
    def tearDownClass(cls):
        code = cls.server.stop()
        shutil.rmtree(cls.tmp, ignore_errors=True)
        assert code == 0, code

    def client(self, *args):
        return subprocess.run([CONFIG.client, "--port", str(self.server.port), "--retries", "0",
                               *args], capture_output=True, text=True, timeout=60)

    def test_a_round_trip_with_the_python_client(self):
        for host in ("127.0.0.1", "localhost"):
            with hfts_client.HftsClient(host, self.server.port, timeout=60, token=PLAN_TOKEN,
                                        ca_file=self.cert) as client:
                info = client.info()
                self.assertTrue(info["tls"])
                self.assertTrue(info["authentication"])
                self.assertTrue(client.plan(**QUICK_PLAN)["success"])

    def test_a_round_trip_with_hfts_client(self):
        result = self.client("--ca-file", self.cert, "--token-file", self.token_file, "--json",
                             "info")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn('"tls": true', result.stdout)
        result = self.client("--host", "localhost", "--tls", "--ca-file", self.cert,
                             "--token-file", self.token_file, "scenes")
        self.assertEqual(result.returncode, 0, result.stderr)

    def test_both_clients_refuse_a_certificate_they_cannot_verify(self):
        with self.assertRaises(ssl.SSLCertVerificationError):
            hfts_client.HftsClient("127.0.0.1", self.server.port, timeout=60, retries=0,
                                   token=PLAN_TOKEN, tls=True)  # the system's CAs only
        result = self.client("--tls", "--token-file", self.token_file, "info")
        self.assertEqual(result.returncode, 1)
        self.assertIn("certificate verify failed", result.stderr)
        # Another CA's certificate, for the right host: refused too.
        other = tempfile.mkdtemp(prefix="hfts-tls-other-")
        try:
            other_cert, _ = make_certificate(other)
            result = self.client("--ca-file", other_cert, "--token-file", self.token_file, "info")
            self.assertEqual(result.returncode, 1)
            self.assertIn("certificate verify failed", result.stderr)
        finally:
            shutil.rmtree(other, ignore_errors=True)
        self.assertNotIn(PLAN_TOKEN, self.server.log_text())

    def test_a_flood_of_unfinished_messages_over_tls_leaves_the_server_serving(self):
        # The flood of docs/reliability.md, scaled down, over TLS: connections
        # refused over the input budget are drained and closed while their
        # reads may still be in flight (two TLS reads at once crashed it).
        server = RunningServer(os.path.join(self.tmp, "flood.log"), "--workers", "1",
                               "--max-buffered-mib", "16", "--tls-cert", self.cert,
                               "--tls-key", os.path.join(self.tmp, "key.pem"))
        try:
            server_attack.ACCESS["tls"] = ssl.create_default_context(cafile=self.cert)
            result = server_attack.attack(server.host, server.port, server.process.pid,
                                          connections=24, size=6 << 20)
            self.assertIsNone(server.process.poll(), "the server died")
            self.assertGreater(result["outcomes"].get("sent, error -32007", 0) +
                               result["outcomes"].get("closed by server, error -32007", 0), 0,
                               result)
            self.assertGreater(result["probes"], 0, result)
            self.assertEqual(result["refused_probes"], 0, result)
        finally:
            server_attack.ACCESS["tls"] = None
            self.assertEqual(server.stop(), 0)

    def test_a_plain_client_gets_nothing_but_a_closed_connection(self):
        with socket.create_connection(("127.0.0.1", self.server.port), timeout=30) as s:
            s.sendall(b'{"jsonrpc":"2.0","id":1,"method":"server.info"}\n')
            self.assertEqual(s.makefile("rb").readline(), b"")
        self.assertIsNone(self.server.process.poll())


class WithoutTokens(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hfts-auth-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def start(self, *args):
        return subprocess.run(
            [CONFIG.server, "--db", CONFIG.db_dir, "--port", "0",
             "--robot", os.path.join(CONFIG.source_dir, "robots", "kr5_sdh", "kr5_sdh.json"),
             "--scenes", os.path.join(CONFIG.source_dir, "objects", "scenes"), *args],
            capture_output=True, text=True, timeout=60)

    def test_auth_succeeds_and_says_there_is_no_authentication(self):
        server = RunningServer(os.path.join(self.tmp, "log"), "--workers", "1")
        try:
            response = server.call("auth", {"token": "anything-at-all-here"})
            self.assertEqual(response["result"], {"role": "admin", "authentication": False})
        finally:
            self.assertEqual(server.stop(), 0)

    def test_a_non_loopback_address_needs_tokens_or_insecure(self):
        result = self.start("--bind", "0.0.0.0")
        self.assertEqual(result.returncode, 1)
        self.assertIn("without tokens", result.stderr)
        self.assertIn("--auth-tokens FILE", result.stderr)
        server = RunningServer(os.path.join(self.tmp, "log"), "--bind", "0.0.0.0", "--insecure",
                               "--workers", "1")
        try:
            self.assertIn("warning: --insecure", server.log_text())
        finally:
            self.assertEqual(server.stop(), 0)

    def test_tls_needs_a_certificate_and_a_key_that_load(self):
        cert, key = make_certificate(self.tmp)
        result = self.start("--tls-cert", cert)
        self.assertEqual(result.returncode, 1)
        self.assertIn("needs both a certificate (--tls-cert) and a key (--tls-key)", result.stderr)
        result = self.start("--tls-cert", cert + ".missing", "--tls-key", key)
        self.assertEqual(result.returncode, 1)
        self.assertIn("cannot use the TLS certificate '" + cert + ".missing'", result.stderr)
        result = self.start("--tls-cert", cert, "--tls-key", cert)  # not a key
        self.assertEqual(result.returncode, 1)
        self.assertIn("cannot use the TLS private key", result.stderr)

    def test_a_token_file_every_user_may_read_is_refused(self):
        tokens = os.path.join(self.tmp, "tokens")
        write_tokens(tokens, TOKENS, mode=0o644)
        result = self.start("--auth-tokens", tokens)
        self.assertEqual(result.returncode, 1)
        self.assertIn("chmod 600", result.stderr)
        write_tokens(tokens, "plan short\n")
        result = self.start("--auth-tokens", tokens)
        self.assertEqual(result.returncode, 1)
        self.assertIn("line 1: a token must have 16 to 1024 characters", result.stderr)

    def test_a_plan_token_from_another_machine_cannot_shut_down(self):
        address = non_loopback_address()
        if address is None:
            self.skipTest("no non-loopback address to connect from")
        tokens = os.path.join(self.tmp, "tokens")
        write_tokens(tokens, TOKENS)
        server = RunningServer(os.path.join(self.tmp, "log"), "--bind", "0.0.0.0",
                               "--auth-tokens", tokens, "--workers", "1")
        try:
            with socket.create_connection((address, server.port), timeout=30) as s:
                reader = s.makefile("rb")
                for message in (b'{"jsonrpc":"2.0","id":1,"method":"auth",'
                                b'"params":{"token":"' + PLAN_TOKEN.encode() + b'"}}\n',
                                b'{"jsonrpc":"2.0","id":2,"method":"shutdown"}\n'):
                    s.sendall(message)
                    response = reader.readline()
                self.assertIn(b'"code":-32003', response)
            self.assertIsNone(server.process.poll())
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
    run_tests()
