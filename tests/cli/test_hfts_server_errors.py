#!/usr/bin/env python3
"""Integration tests of hfts-server: malformed input of every kind gets the right
error (docs/protocol.md#errors) and the server keeps serving.
Run by ctest with Debian's /usr/bin/python3; standard library only."""

import threading

from hfts_server_fixture import ServerTest, run_tests


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
            ({"scene": "table", "start": start[:12]}, "start",
             "must hold 13 values, one per joint of robot 'kr5_sdh', got 12"),
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
            ({"scene": "table", "parameters": {"p_max": 5}}, "parameters.p_max",
             "must be in [0, 1], got 5"),
            ({"scene": {"name": "x"}}, "scene.robot_base", "is required"),
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


if __name__ == "__main__":
    run_tests()
