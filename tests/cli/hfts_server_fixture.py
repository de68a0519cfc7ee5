"""Starts and stops a real hfts-server for the service tests (standard library only).

build_databases() builds the mug and blob databases and the hand map into a
directory with hfts-preprocess (about half a second); RunningServer starts
hfts-server on an ephemeral port and reads the port from its first line.
"""

import json
import os
import re
import signal
import socket
import subprocess
import time


def build_databases(preprocess, source_dir, out_dir, objects=("mug", "blob")):
    meshes = os.path.join(source_dir, "objects", "meshes")
    files = sorted(f for f in os.listdir(meshes) if os.path.splitext(f)[0] in objects)
    for f in files:
        subprocess.run([preprocess, os.path.join(meshes, f), "-o", out_dir, "-q"], check=True,
                       capture_output=True, timeout=120)
    subprocess.run([preprocess, "--hand", os.path.join(source_dir, "robots", "kr5_sdh",
                                                       "kr5_sdh.json"), "-o", out_dir],
                   check=True, capture_output=True, timeout=120)


class RunningServer:
    """hfts-server as a child process; its request log goes to log_path."""

    def __init__(self, binary, source_dir, db_dir, log_path, *extra):
        self.log_path = log_path
        self.log = open(log_path, "wb")
        self.process = subprocess.Popen(
            [binary, "--db", db_dir, "--port", "0",
             "--robot", os.path.join(source_dir, "robots", "kr5_sdh", "kr5_sdh.json"),
             "--scenes", os.path.join(source_dir, "objects", "scenes"), *map(str, extra)],
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
