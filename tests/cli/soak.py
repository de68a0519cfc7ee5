#!/usr/bin/env python3
"""Soak test of hfts-server (issue 17, item 4): mixed traffic for a while,
then "nothing grows, nothing is left unanswered, nothing died".

    /usr/bin/python3 tests/cli/soak.py MINUTES [--out DIR] [--clients 64]
        [--server BIN --db DIR | --host H --port P [--pid PID]]

Starts hfts-server (default limits, the bundled scenes, build/databases or,
with --preprocess, the mug, blob and bottle databases built into a
temporary directory) or drives a running one, with N client threads of
mixed traffic: plans (every scene, 0.2-2 s, random seeds, coupled and
decoupled, some racing or at a placement), plans cancelled by id, plans
abandoned by closing (or resetting) the socket, plans followed by a
half-close, grasp.quality, server.info / objects.list / scenes.list,
batches, notifications, malformed lines (each with its expected error
code) and large messages below the size limit; every client reconnects
every 5-40 actions. Every request sent on a connection kept open must be
answered (result or error; -32001 "busy" is a valid refusal).

Every --interval seconds it samples the server's VmRSS, Threads, open file
descriptors and load (server.info) and the latency percentiles of each
request type answered in that interval. Writes samples.csv, summary.json,
soak.png (and server.log when it started the server) to --out.

Verdict (exit 1 on any failure, 0 otherwise): no request unanswered, no
wrong answer (unexpected error code, -32603, unknown id), the server alive
throughout; resident memory: the median of the last third of the run at
most max(5 %, 20 MiB) above the median of the middle third (the first
third is warm-up), and its trend over those two thirds (Theil-Sen: the
median of the slopes between pairs of samples) projects less than that
tolerance; after all clients have closed and a settle, resident memory is
within that tolerance of the baseline measured before the traffic, and
open descriptors, threads and the input budget are back at it; a server
it started exits 0 on SIGTERM.
Standard library, plus matplotlib for the plot.
"""

import argparse
import collections
import csv
import json
import math
import os
import random
import shutil
import signal
import socket
import sys
import tempfile
import threading
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hfts_server_fixture import CONFIG, FAR_AWAY, QUALITY, RunningServer  # noqa: E402

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MIB = 1 << 20
RESERVATION = 128 << 10  # input budget reserved per connection (docs/reliability.md)
BUSY = "error -32001"
# Request types whose latency is reported (one CSV column group each).
KINDS = ["plan", "plan_cancelled", "plan_halfclose", "cancel", "grasp.quality", "server.info",
         "objects.list", "scenes.list", "batch", "malformed", "large"]
# Actions of a client and their weights.
WEIGHTS = {"info": 20, "quality": 14, "plan": 20, "cancel": 9, "malformed": 12, "large": 2,
           "batch": 4, "notification": 3, "abandon": 6, "halfclose": 3}
# Malformed lines: the line (ID is replaced by the request id) and the error code.
MALFORMED = [
    ('{"jsonrpc":"2.0","id":ID,"method":"server.info"', -32700),
    ('', -32700),
    ('\x01\xff not json at all', -32700),
    ('{"jsonrpc":"2.0","id":ID,"method":"plan","params":{"time_limit":1e400}}', -32700),
    ('NaN', -32700),
    ('42', -32600),
    ('[]', -32600),
    ('{"jsonrpc":"1.0","id":ID,"method":"server.info"}', -32600),
    ('{"jsonrpc":"2.0","id":{"a":1},"method":"server.info"}', -32600),
    ('{"jsonrpc":"2.0","id":ID,"method":7}', -32600),
    ('{"jsonrpc":"2.0","id":ID,"method":"server.info","params":' + "[" * 80 + "]" * 80 + "}",
     -32600),
    ('{"jsonrpc":"2.0","id":ID,"method":"no.such.method"}', -32601),
    ('{"jsonrpc":"2.0","id":ID,"method":"plan","params":{"scene":"table","time_limit":"soon"}}',
     -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"plan","params":[1,2]}', -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"plan","params":{"scene":"kitchen"}}', -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"plan","params":{"scene":"../etc/passwd"}}', -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"plan","params":{"scene":"table","start":[0,1,2]}}',
     -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"plan","params":{"scene":"bin","parameters":{"p_max":5}}}',
     -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"grasp.quality","params":{"contacts":[]}}', -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"cancel","params":{}}', -32602),
    ('{"jsonrpc":"2.0","id":ID,"method":"server.info","params":{"verbose":true}}', -32602),
]
PAD = b"a" * (8 * MIB)
# The latencies in the plot (p50 and p99); the CSV has all of KINDS.
PLOTTED = ["plan", "plan_cancelled", "cancel", "grasp.quality", "server.info", "malformed",
           "large"]


# With --tls and --auth (docs/security.md): every Link speaks TLS with this
# context and authenticates with this token before its first request.
ACCESS = {"tls": None, "token": None}


class Link:
    """One TCP connection: sends bytes, reads response lines before a deadline."""

    def __init__(self, host, port, timeout=30):
        self.socket = socket.create_connection((host, port), timeout=timeout)
        # Pipelined requests must not wait for the server's delayed ACK (Nagle).
        self.socket.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        if ACCESS["tls"] is not None:
            self.socket = ACCESS["tls"].wrap_socket(self.socket, server_hostname=host)
        self.buffer = bytearray()
        if ACCESS["token"] is not None:
            self.send(message("auth", {"token": ACCESS["token"]}, "auth"))
            reply = self.read_line(time.monotonic() + timeout)
            if reply is None or b'"result"' not in reply:
                raise ConnectionError(f"auth refused: {reply!r}")

    def half_close(self):
        """No more bytes to the server (TCP half-close; under TLS the TLS
        layer stays, so that replies can still be read)."""
        socket.socket.shutdown(self.socket, socket.SHUT_WR)

    def send(self, data):
        self.socket.settimeout(120)
        self.socket.sendall(data)

    def read_line(self, deadline):
        """The next line (bytes); None at end of stream; raises TimeoutError."""
        while (end := self.buffer.find(b"\n")) < 0:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError
            self.socket.settimeout(remaining)
            try:
                chunk = self.socket.recv(1 << 16)
            except socket.timeout:
                raise TimeoutError from None
            if not chunk:
                return None
            self.buffer += chunk
        line = bytes(self.buffer[:end])
        del self.buffer[:end + 1]
        return line

    def close(self, reset=False):
        if reset:  # an abortive close: the peer sees ECONNRESET
            self.socket.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\0\0\0\0\0\0\0")
        self.socket.close()


def message(method, params=None, request_id=None):
    """A JSON-RPC request as one line; request_id None makes a notification."""
    m = {"jsonrpc": "2.0", "method": method}
    if request_id is not None:
        m["id"] = request_id
    if params is not None:
        m["params"] = params
    return (json.dumps(m, separators=(",", ":")) + "\n").encode()


def percentile(sorted_values, q):
    if not sorted_values:
        return None
    return sorted_values[min(len(sorted_values) - 1, int(math.ceil(q * len(sorted_values))) - 1)]


def latency_stats(values):
    v = sorted(values)
    return {"n": len(v), "p50": percentile(v, 0.5), "p90": percentile(v, 0.9),
            "p99": percentile(v, 0.99), "max": v[-1] if v else None}


class Recorder:
    """Outcomes, latencies and problems of all clients (thread-safe)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.counts = collections.Counter()  # (kind, outcome)
        self.reasons = collections.Counter()  # plan results by reason
        self.interval = collections.defaultdict(list)  # kind -> latencies since the last sample
        self.latencies = collections.defaultdict(list)  # kind -> all latencies
        self.unanswered = []
        self.problems = []

    def answered(self, kind, outcome, latency, result=None):
        with self.lock:
            self.counts[kind, outcome] += 1
            if outcome != BUSY:  # a refusal's latency says nothing about the method
                self.interval[kind].append(latency)
                self.latencies[kind].append(latency)
            if isinstance(result, dict) and "reason" in result:
                self.reasons[result["reason"]] += 1
            if isinstance(result, dict) and "cancelled" in result:
                self.reasons["cancel call: " + str(result["cancelled"]).lower()] += 1

    def count(self, kind, outcome):
        with self.lock:
            self.counts[kind, outcome] += 1

    def lost(self, kind, request_id, why, sent_at):
        with self.lock:
            self.counts[kind, "unanswered"] += 1
            self.unanswered.append({"kind": kind, "id": request_id, "why": why,
                                    "after": round(time.monotonic() - sent_at, 3),
                                    "at": time.strftime("%H:%M:%S")})

    def problem(self, text):
        with self.lock:
            self.problems.append(time.strftime("%H:%M:%S ") + text)

    def take_interval(self):
        with self.lock:
            taken, self.interval = self.interval, collections.defaultdict(list)
        return {kind: latency_stats(v) for kind, v in taken.items()}


class Client(threading.Thread):
    """One simulated client: weighted random actions on a connection it
    replaces every 5-40 actions, until `stop` is set."""

    def __init__(self, index, options, scenes, objects, recorder, stop):
        super().__init__(daemon=True, name=f"client-{index}")
        self.index, self.o, self.scenes, self.objects = index, options, scenes, objects
        self.rec, self.stop = recorder, stop
        self.rng = random.Random(options.seed * 1000 + index)
        self.link, self.left, self.next_id = None, 0, 0
        self.pending = {}  # id -> (kind, sent at, accepted outcomes)

    def run(self):
        time.sleep(self.rng.uniform(0, 2))
        actions, weights = zip(*WEIGHTS.items())
        while not self.stop.is_set():
            action = self.rng.choices(actions, weights)[0]
            try:
                if action not in ("abandon", "halfclose"):  # they use connections of their own
                    self.connection()
                getattr(self, "do_" + action)()
            except OSError as e:  # connect refused, reset: the monitor judges the server
                self.rec.count("connect", type(e).__name__)
                self.drop(f"connection failed: {e}")
                time.sleep(1)
            except Exception as e:  # a bug of this driver: counted, the client goes on
                self.rec.problem(f"client {self.index}: {action} raised {e!r}")
                self.drop(f"{action} raised {e!r}")
            time.sleep(self.rng.uniform(0, 0.3))
        self.drop("client stopped")

    # --- the connection kept open -------------------------------------------------

    def connection(self):
        if self.link is None or self.left <= 0:
            self.drop("reconnect")
            self.link = Link(self.o.host, self.o.port)
            self.rec.count("connect", "ok")
            self.left = self.rng.randint(5, 40)
        self.left -= 1
        return self.link

    def drop(self, why):
        for request_id, (kind, sent, _) in self.pending.items():
            self.rec.lost(kind, request_id, why, sent)
        self.pending.clear()
        if self.link is not None:
            self.link.close()
            self.link = None

    def new_id(self):
        self.next_id += 1
        return self.next_id if self.next_id % 2 else f"c{self.index}-{self.next_id}"

    def send(self, link, kind, data, request_id, accepted=("result",)):
        self.pending[request_id] = (kind, time.monotonic(), accepted)
        link.send(data)

    def call(self, kind, method, params=None, accepted=("result",)):
        request_id = self.new_id()
        self.send(self.link, kind, message(method, params, request_id), request_id, accepted)
        return request_id

    def await_replies(self, link, until=None):
        """Reads replies until nothing is pending (or until `until`, a
        monotonic time, for a wait that may end early)."""
        deadline = time.monotonic() + self.o.answer_timeout
        while self.pending:
            try:
                line = link.read_line(min(deadline, until) if until else deadline)
            except TimeoutError:
                if until and time.monotonic() < deadline:
                    return
                self.drop(f"no answer within {self.o.answer_timeout} s")
                return
            except OSError as e:
                self.drop(f"connection error while waiting: {e}")
                return
            if line is None:
                self.drop("connection closed by the server before answering")
                return
            self.dispatch(line)

    def dispatch(self, line):
        try:
            reply = json.loads(line)
        except ValueError:
            self.rec.problem(f"client {self.index}: a reply that is not JSON: {line[:200]!r}")
            return
        if isinstance(reply, list):
            return self.dispatch_batch(reply, line)
        request_id = reply.get("id") if isinstance(reply, dict) else None
        if request_id is None and len(self.pending) == 1 and "error" in reply:
            request_id = next(iter(self.pending))  # a line whose id could not be read
        if request_id not in self.pending or reply.get("jsonrpc") != "2.0":
            self.rec.problem(f"client {self.index}: unexpected reply {line[:300]!r} "
                             f"(pending {list(self.pending)})")
            return
        kind, sent, accepted = self.pending.pop(request_id)
        outcome = outcome_of(reply)
        self.rec.answered(kind, outcome, time.monotonic() - sent, reply.get("result"))
        if outcome not in accepted:
            self.rec.problem(f"client {self.index}: {kind} id={request_id!r} answered "
                             f"{outcome}, expected {' or '.join(accepted)}: {line[:300]!r}")

    def dispatch_batch(self, replies, line):
        kind, sent, expected = self.pending.pop("batch", ("batch", 0, None))
        ids = sorted(str(r.get("id")) for r in replies if isinstance(r, dict))
        bad = [r for r in replies if outcome_of(r) not in ("result", BUSY)]
        if expected is None or ids != expected or bad:
            self.rec.problem(f"client {self.index}: wrong batch reply {line[:300]!r}, "
                             f"expected ids {expected}")
        self.rec.answered("batch", "result" if not bad else outcome_of(bad[0]),
                          time.monotonic() - sent)

    # --- actions ---------------------------------------------------------------------

    def do_info(self):
        method = self.rng.choice(["server.info"] * 8 + ["objects.list"] * 5 + ["scenes.list"] * 7)
        self.call(method, method)
        self.await_replies(self.link)

    def do_quality(self):
        a = self.rng.uniform(0, 2 * math.pi)
        c, s = math.cos(a), math.sin(a)
        turn = lambda v: [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]  # noqa: E731
        params = {"contacts": [{"position": turn(k["position"]), "normal": turn(k["normal"])}
                               for k in QUALITY["contacts"]],
                  "friction": round(self.rng.uniform(0.2, 1.0), 3)}
        if self.rng.random() < 0.3:
            params["object"] = self.rng.choice(self.objects)
        self.call("grasp.quality", "grasp.quality", params)
        self.await_replies(self.link)

    def plan_params(self, low=0.2, high=2.0):
        scene = self.rng.choice(self.scenes)
        p = {"scene": scene["name"], "time_limit": round(self.rng.uniform(low, high), 2),
             "seed": self.rng.randrange(2 ** 63)}
        if self.rng.random() < 0.3:
            p["algorithm"] = "decoupled"
            p["iterations"] = self.rng.randint(5, 40)
        elif self.rng.random() < 0.1:
            p["parameters"] = {"threads": 2}
        roll = self.rng.random()
        if roll < 0.1 and scene.get("placements"):
            p["object_pose"] = self.rng.choice(scene["placements"])["pose"]
        elif roll < 0.15:
            p["object_pose"] = FAR_AWAY
        return p

    def do_plan(self):
        self.call("plan", "plan", self.plan_params(), accepted=("result", BUSY))
        if self.rng.random() < 0.3:  # pipelined: the answer to this comes first
            self.call("server.info", "server.info")
        self.await_replies(self.link)

    def do_cancel(self):
        p = self.plan_params(2, 8)
        if self.rng.random() < 0.4:
            p["object_pose"] = FAR_AWAY  # runs until cancelled
        plan_id = self.call("plan_cancelled", "plan", p, accepted=("result", BUSY))
        self.await_replies(self.link, until=time.monotonic() + self.rng.uniform(0.05, 1.0))
        if self.link is not None:
            self.call("cancel", "cancel", {"id": plan_id})
            self.await_replies(self.link)

    def do_malformed(self):
        line, code = self.rng.choice(MALFORMED)
        request_id = self.new_id()
        data = (line.replace("ID", json.dumps(request_id)) + "\n").encode("latin-1")
        # The planner checks its parameters on a worker: such a plan may also find the queue full.
        accepted = (f"error {code}", BUSY) if '"parameters"' in line else (f"error {code}",)
        self.send(self.link, "malformed", data, request_id, accepted)
        self.await_replies(self.link)

    def do_large(self):
        size = int(math.exp(self.rng.uniform(math.log(64 << 10), math.log(len(PAD)))))
        request_id = self.new_id()
        head = json.dumps({"jsonrpc": "2.0", "id": request_id, "method": "server.info"})[:-1]
        if self.rng.random() < 0.5:
            data = head.encode() + b',"params":{"pad":"' + PAD[:size] + b'"}}\n'
        else:
            data = (head.replace("server.info", "plan").encode() + b',"params":{"scene":"'
                    + PAD[:size] + b'"}}\n')
        self.send(self.link, "large", data, request_id, ("error -32602",))
        self.await_replies(self.link)

    def do_batch(self):
        calls, ids = [], []
        for method in self.rng.sample(["server.info", "scenes.list", "grasp.quality", "plan",
                                       "objects.list"], self.rng.randint(2, 4)):
            params = {"grasp.quality": QUALITY,
                      "plan": self.plan_params(0.2, 0.5)}.get(method)
            request_id = self.new_id()
            ids.append(str(request_id))
            calls.append({"jsonrpc": "2.0", "id": request_id, "method": method,
                          **({"params": params} if params else {})})
        calls.append({"jsonrpc": "2.0", "method": "server.info"})  # a notification: no element
        link = self.link
        self.pending["batch"] = ("batch", time.monotonic(), sorted(ids))
        link.send((json.dumps(calls) + "\n").encode())
        self.await_replies(link)

    def do_notification(self):
        link = self.link
        method, params = self.rng.choice([("server.info", None), ("scenes.list", None),
                                          ("plan", self.plan_params(0.2, 0.5))])
        link.send(message(method, params))
        self.rec.count("notification", "sent")
        self.call("server.info", "server.info")  # the only answer must be this one's
        self.await_replies(link)

    def do_abandon(self):
        """Plans on a fresh connection, which is then closed unread."""
        link = Link(self.o.host, self.o.port)
        for _ in range(self.rng.randint(1, 3)):
            link.send(message("plan", self.plan_params(1, 5), self.new_id()))
        way = self.rng.choice(["close", "reset", "close inside a message"])
        if way == "close inside a message":
            link.send(b'{"jsonrpc":"2.0","id":1,"method":"plan","params":{"scene":"tab')
        time.sleep(self.rng.uniform(0, 0.5))
        link.close(reset=way == "reset")
        self.rec.count("abandoned plans", way)

    def do_halfclose(self):
        """A plan, then a half-close: the plan is cancelled and answered."""
        link = Link(self.o.host, self.o.port)
        request_id = self.new_id()
        self.send(link, "plan_halfclose", message("plan", self.plan_params(1, 5), request_id),
                  request_id, ("result", BUSY))
        time.sleep(self.rng.uniform(0, 0.3))
        link.half_close()
        saved, self.link = self.link, link
        self.await_replies(link)
        self.link = saved
        try:
            end = link.read_line(time.monotonic() + 30)
            self.rec.count("half-close", "closed by server" if end is None else "extra line")
        except (TimeoutError, OSError) as e:
            self.rec.count("half-close", f"not closed: {type(e).__name__}")
        link.close()


def outcome_of(reply):
    if not isinstance(reply, dict):
        return "not an object"
    if "result" in reply:
        return "result"
    error = reply.get("error")
    return f"error {error.get('code')}" if isinstance(error, dict) else "neither result nor error"


# --- the server's side: /proc and server.info ------------------------------------------


def proc_sample(pid):
    """VmRSS (bytes), Threads and open descriptors of process `pid`."""
    status = {}
    with open(f"/proc/{pid}/status", encoding="ascii") as f:
        for line in f:
            key, _, value = line.partition(":")
            status[key] = value.split()
    return {"rss": int(status["VmRSS"][0]) * 1024, "threads": int(status["Threads"][0]),
            "fds": len(os.listdir(f"/proc/{pid}/fd"))}


def server_load(host, port, timeout=60):
    """server.info's load, on a fresh connection that is closed again."""
    link = Link(host, port)
    try:
        link.send(message("server.info", None, "soak-probe"))
        line = link.read_line(time.monotonic() + timeout)
        return json.loads(line)["result"]["load"]
    finally:
        link.close()


class Monitor:
    """Samples the server every `interval` seconds; `alive()` says whether it runs."""

    def __init__(self, options, recorder, process=None):
        self.o, self.rec, self.process = options, recorder, process
        self.samples = []
        self.t0 = None

    def alive(self):
        if self.process is not None:
            return self.process.poll() is None
        return self.o.pid is None or os.path.exists(f"/proc/{self.o.pid}")

    def measure(self, phase):
        row = {"t": round(time.monotonic() - self.t0, 2), "phase": phase}
        if self.o.pid is not None:
            row.update(proc_sample(self.o.pid))
        try:
            load = server_load(self.o.host, self.o.port)
            row.update({k: load.get(k) for k in ("connections", "running", "queued", "calls",
                                                 "input_budget_used")})
        except (OSError, TimeoutError, ValueError, KeyError, TypeError) as e:
            self.rec.problem(f"monitor: server.info failed: {e!r}")
        return row

    def sample(self):
        row = self.measure("run")
        row["latency"] = self.rec.take_interval()
        self.samples.append(row)
        return row

    def settled(self, baseline_budget, timeout):
        """Waits until no connection but the probe is open and nothing runs or waits."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and self.alive():
            try:
                load = server_load(self.o.host, self.o.port)
                if (load["connections"] == 1 and load["running"] == 0 and load["queued"] == 0
                        and load["input_budget_used"] <= baseline_budget):
                    return load
            except (OSError, TimeoutError, ValueError, KeyError):
                pass
            time.sleep(1)
        return None

    def quiet_measure(self, phase, settle):
        """A measurement with no connection open (after `settle` seconds)."""
        time.sleep(settle)
        row = {"t": round(time.monotonic() - self.t0, 2), "phase": phase}
        if self.o.pid is not None:
            row.update(proc_sample(self.o.pid))
        return row


# --- the run -----------------------------------------------------------------------------


def primer(options, recorder):
    """One of each request before the baseline, so that lazy initialisation
    (per-thread arenas, caches filled once) is not counted as growth."""
    link = Link(options.host, options.port)
    scenes = call_once(link, "scenes.list")["scenes"]
    objects = [o["name"] for o in call_once(link, "objects.list")["objects"]]
    call_once(link, "server.info")
    call_once(link, "grasp.quality", QUALITY)
    for scene in scenes:
        for algorithm in ("coupled", "decoupled"):
            call_once(link, "plan", {"scene": scene["name"], "time_limit": 0.3,
                                     "algorithm": algorithm}, timeout=options.answer_timeout)
    link.close()
    return scenes, objects


def call_once(link, method, params=None, timeout=60):
    link.send(message(method, params, 1))
    line = link.read_line(time.monotonic() + timeout)
    reply = json.loads(line) if line else {}
    if "result" not in reply:
        raise RuntimeError(f"{method} failed: {line!r}")
    return reply["result"]


def drive(options, monitor, recorder, scenes, objects):
    """The traffic phase; returns the clients' stop time."""
    stop = threading.Event()
    clients = [Client(i, options, scenes, objects, recorder, stop) for i in range(options.clients)]
    monitor.t0 = time.monotonic()
    end = monitor.t0 + options.minutes * 60
    for c in clients:
        c.start()
    next_sample = monitor.t0 + options.interval
    try:
        while time.monotonic() < end:
            time.sleep(max(0.0, min(next_sample, end) - time.monotonic()))
            if not monitor.alive():
                recorder.problem("the server died during the run")
                break
            if time.monotonic() >= next_sample:
                row = monitor.sample()
                next_sample += options.interval
                if options.verbose:
                    print(progress_line(row, recorder), flush=True)
    except KeyboardInterrupt:
        recorder.problem("interrupted (SIGINT): the run was cut short")
    stop.set()
    stopped = time.monotonic()
    for c in clients:
        c.join(timeout=max(1.0, stopped + options.answer_timeout + 60 - time.monotonic()))
    hung = [c.name for c in clients if c.is_alive()]
    if hung:
        recorder.problem(f"clients still waiting {options.answer_timeout + 60} s after the stop: "
                         f"{', '.join(hung)}")
    monitor.samples.append({**monitor.measure("drained"), "latency": recorder.take_interval()})
    return stopped - monitor.t0


def progress_line(row, recorder):
    with recorder.lock:
        total = sum(recorder.counts.values())
        lost = len(recorder.unanswered)
    mem = f"rss {row['rss'] / MIB:.0f} MiB fds {row['fds']} threads {row['threads']} " \
        if "rss" in row else ""
    return (f"[{row['t'] / 60:5.1f} min] {mem}conn {row.get('connections')} "
            f"running {row.get('running')} queued {row.get('queued')} outcomes {total} "
            f"unanswered {lost}")


# --- the verdict ---------------------------------------------------------------------------


def median(values):
    v = sorted(values)
    return (v[(len(v) - 1) // 2] + v[len(v) // 2]) / 2 if v else None


def slope(points):
    """Theil-Sen slope of (t, y) points: the median of the slopes between all
    pairs. A sample taken while several large plans are in flight lies 10-20
    MiB above its neighbours; least squares lets two such samples near one end
    of a short window tilt the whole line, the median of pairs does not."""
    pairs = [(y1 - y0) / (t1 - t0) for i, (t0, y0) in enumerate(points)
             for t1, y1 in points[i + 1:] if t1 != t0]
    return median(pairs) if pairs else 0.0


def judge_memory(options, samples, duration, baseline=None, final=None):
    """RSS of the last third against the middle third, and after all clients
    closed against before the traffic; returns (facts, failures)."""
    run = [s for s in samples if s.get("phase") == "run" and "rss" in s]
    middle = [s for s in run if duration / 3 <= s["t"] < 2 * duration / 3]
    last = [s for s in run if s["t"] >= 2 * duration / 3]
    if len(middle) < 3 or len(last) < 3:
        return {"judged": False, "why": "fewer than 3 samples in a third"}, []
    if os.environ.get("HFTS_SANITIZER") in ("address", "thread"):
        # scripts/sanitize.sh: the sanitizer's quarantine and shadow memory,
        # not the server's, make up the resident memory then.
        return {"judged": False, "why": f"under {os.environ['HFTS_SANITIZER']} sanitizer"}, []
    mid_rss, last_rss = median(s["rss"] for s in middle), median(s["rss"] for s in last)
    tolerance = max(options.rss_tolerance_pct / 100 * mid_rss, options.rss_tolerance_mib * MIB)
    window = middle + last
    rate = slope([(s["t"], s["rss"]) for s in window])
    projected = rate * (window[-1]["t"] - window[0]["t"])
    facts = {"judged": True, "middle_median_mib": mid_rss / MIB, "last_median_mib": last_rss / MIB,
             "growth_mib": (last_rss - mid_rss) / MIB, "tolerance_mib": tolerance / MIB,
             "slope_mib_per_min": rate * 60 / MIB, "trend_over_window_mib": projected / MIB,
             "middle_fds_median": median(s["fds"] for s in middle),
             "last_fds_median": median(s["fds"] for s in last),
             "middle_threads_max": max(s["threads"] for s in middle),
             "last_threads_max": max(s["threads"] for s in last)}
    failures = []
    if last_rss - mid_rss > tolerance:
        failures.append(f"resident memory grew: median {mid_rss / MIB:.1f} MiB in the middle "
                        f"third, {last_rss / MIB:.1f} MiB in the last (tolerance "
                        f"{tolerance / MIB:.1f} MiB)")
    if projected > tolerance:
        failures.append(f"resident memory trends up: {rate * 60 / MIB:.2f} MiB/min, "
                        f"{projected / MIB:.1f} MiB over the judged window (tolerance "
                        f"{tolerance / MIB:.1f} MiB)")
    if baseline and final and "rss" in baseline and "rss" in final:
        # With no plan in flight nothing hides a leak: what every request left
        # behind is still resident.
        facts["after_close_growth_mib"] = (final["rss"] - baseline["rss"]) / MIB
        if final["rss"] - baseline["rss"] > tolerance:
            failures.append(f"resident memory not back after all clients closed: "
                            f"{baseline['rss'] / MIB:.1f} MiB before the traffic, "
                            f"{final['rss'] / MIB:.1f} MiB after (tolerance "
                            f"{tolerance / MIB:.1f} MiB)")
    return facts, failures


def judge(options, recorder, monitor, baseline, final, exit_code, duration):
    failures = []
    memory, more = judge_memory(options, monitor.samples, duration, baseline, final)
    failures += more
    if recorder.unanswered:
        failures.append(f"{len(recorder.unanswered)} requests unanswered (first: "
                        f"{recorder.unanswered[0]})")
    if recorder.problems:
        failures.append(f"{len(recorder.problems)} wrong or unexpected answers/events "
                        f"(first: {recorder.problems[0]})")
    internal = sum(n for (_, outcome), n in recorder.counts.items() if outcome == "error -32603")
    if internal:
        failures.append(f"{internal} internal errors (-32603)")
    if not final.get("alive", True):
        failures.append("the server is not running after the traffic")
    for key in ("fds", "threads"):
        if key in baseline and key in final and final[key] != baseline[key]:
            failures.append(f"{key} not back to the baseline after all clients closed: "
                            f"{baseline[key]} before the traffic, {final[key]} after")
    if final.get("settled") is False:
        failures.append(f"the server did not settle (connections, plans or input budget not "
                        f"back to idle) within {options.settle_timeout} s: {final.get('load')}")
    if exit_code is not None and exit_code != 0:
        failures.append(f"the server exited with {exit_code} on SIGTERM (expected 0)")
    return memory, failures


# --- outputs -------------------------------------------------------------------------------


def ms(seconds):
    return "" if seconds is None else f"{seconds * 1000:.4g}"


def write_csv(path, samples):
    stats = ("n", "p50", "p90", "p99", "max")
    head = ["t_s", "phase", "rss_mib", "fds", "threads", "connections", "running", "queued",
            "calls", "input_budget_kib"] + [f"{k}_{s}{'' if s == 'n' else '_ms'}"
                                            for k in KINDS for s in stats]
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(head)
        for s in samples:
            row = [s["t"], s["phase"], f"{s['rss'] / MIB:.1f}" if "rss" in s else "",
                   s.get("fds", ""), s.get("threads", ""), s.get("connections", ""),
                   s.get("running", ""), s.get("queued", ""), s.get("calls", ""),
                   s["input_budget_used"] // 1024 if s.get("input_budget_used") is not None
                   else ""]
            for kind in KINDS:
                st = s.get("latency", {}).get(kind, {"n": 0})
                row += [st["n"]] + [ms(st.get(x)) for x in stats[1:]]
            out.writerow(row)


def plot(path, samples, duration, baseline, final):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        print(f"soak: no plot ({e})")
        return
    run = [s for s in samples if "rss" in s]
    minutes = [s["t"] / 60 for s in run]
    fig, axes = plt.subplots(4, 1, figsize=(11, 12), sharex=True)
    ax = axes[0]
    ax.plot(minutes, [s["rss"] / MIB for s in run], label="VmRSS")
    for point, label, marker in ((baseline, "before the traffic", "o"),
                                 (final, "after all clients closed", "s")):
        if "rss" in point:
            ax.plot(point["t"] / 60, point["rss"] / MIB, marker, label=label)
    ax.set_ylabel("resident memory (MiB)")
    ax = axes[1]
    ax.plot(minutes, [s["fds"] for s in run], label="open descriptors")
    ax.plot(minutes, [s.get("connections") or 0 for s in run], label="connections (server.info)")
    ax.set_ylabel("count")
    ax = axes[2]
    ax.plot(minutes, [s["threads"] for s in run], label="threads")
    ax.plot(minutes, [s.get("running") or 0 for s in run], label="plans running")
    ax.plot(minutes, [s.get("queued") or 0 for s in run], label="plans queued")
    ax.set_ylabel("count")
    ax = axes[3]
    for i, kind in enumerate(PLOTTED):
        points = [(s["t"] / 60, s["latency"][kind]) for s in samples
                  if s.get("latency", {}).get(kind, {}).get("n")]
        if points:
            color = f"C{i % 10}"
            ax.plot([t for t, _ in points], [st["p50"] * 1000 for _, st in points], "-",
                    color=color, label=f"{kind} p50")
            ax.plot([t for t, _ in points], [st["p99"] * 1000 for _, st in points], ":",
                    color=color, label=f"{kind} p99")
    ax.set_yscale("log")
    ax.set_ylabel("latency (ms)")
    ax.set_xlabel("minutes since the clients started")
    for ax in axes:
        for third in (duration / 3, 2 * duration / 3, duration):
            ax.axvline(third / 60, color="grey", linewidth=0.7, linestyle="--")
        ax.axvspan(0, duration / 180, color="grey", alpha=0.1)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        ax.grid(alpha=0.3)
    axes[0].set_title("hfts-server soak (shaded: warm-up; dashed: thirds, end of traffic)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def summarize(options, recorder, monitor, baseline, final, memory, failures, duration,
              exit_code):
    counts = collections.defaultdict(dict)
    for (kind, outcome), n in sorted(recorder.counts.items()):
        counts[kind][outcome] = n
    outcomes = collections.Counter()
    for (kind, outcome), n in recorder.counts.items():
        if kind not in ("connect", "notification", "abandoned plans", "half-close"):
            outcomes[outcome] += n
    peak = max((s["rss"] for s in monitor.samples if "rss" in s), default=None)
    return {
        "verdict": "pass" if not failures else "fail", "failures": failures,
        "minutes": options.minutes, "traffic_seconds": round(duration, 1),
        "clients": options.clients, "interval": options.interval,
        "server": {"started": options.port_given is False, "pid": options.pid,
                   "exit_code": exit_code, "binary": options.binary},
        "started_at": options.started_at,
        "baseline": baseline, "after_close": final, "peak_rss_mib": peak and peak / MIB,
        "memory": memory, "requests_by_outcome": dict(outcomes),
        "answered": sum(n for o, n in outcomes.items() if o != "unanswered"),
        "unanswered": len(recorder.unanswered), "counts": counts,
        "plan_reasons": dict(recorder.reasons),
        "latency_s": {k: latency_stats(v) for k, v in sorted(recorder.latencies.items())},
        "unanswered_details": recorder.unanswered[:50], "problems": recorder.problems[:50],
        "load": os.getloadavg(),
    }


def report(summary):
    b, f, m = summary["baseline"], summary["after_close"], summary["memory"]
    print(f"soak: {summary['traffic_seconds'] / 60:.1f} min of traffic from "
          f"{summary['clients']} clients; {summary['answered']} requests answered, "
          f"{summary['unanswered']} unanswered")
    print("  by outcome: " + ", ".join(f"{o} {n}" for o, n in
                                       sorted(summary["requests_by_outcome"].items())))
    if "rss" in b and "rss" in f:
        mid = f"{m['middle_median_mib']:.1f}" if m.get("judged") else "-"
        last = f"{m['last_median_mib']:.1f}" if m.get("judged") else "-"
        print(f"  resident MiB: before {b['rss'] / MIB:.1f}, middle third {mid}, last third "
              f"{last}, peak {summary['peak_rss_mib']:.1f}, after close {f['rss'] / MIB:.1f}"
              + (f"; trend {m['slope_mib_per_min']:+.2f} MiB/min" if m.get("judged") else ""))
        print(f"  fds {b['fds']} -> {f['fds']}, threads {b['threads']} -> {f['threads']}")
    for kind, st in summary["latency_s"].items():
        print(f"  {kind:15s} n={st['n']:6d} p50 {ms(st['p50']):>7} ms  p90 {ms(st['p90']):>7} ms"
              f"  p99 {ms(st['p99']):>7} ms  max {ms(st['max']):>7} ms")
    if summary["failures"]:
        print("soak: FAIL")
        for failure in summary["failures"]:
            print("  - " + failure)
    else:
        print("soak: PASS (nothing grew, every request was answered, the server lived)")


# --- main ----------------------------------------------------------------------------------


def parse(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("minutes", type=float, help="length of the traffic phase")
    p.add_argument("--out", default=os.path.join(SOURCE_DIR, "build", "soak"))
    p.add_argument("--clients", type=int, default=64)
    p.add_argument("--interval", type=float, help="seconds between samples (default: 5, "
                   "10 for runs of 10 minutes or more)")
    p.add_argument("--server", default=os.path.join(SOURCE_DIR, "build", "bin", "hfts-server"))
    p.add_argument("--db", help="database directory (default: build/databases, or built "
                   "with --preprocess)")
    p.add_argument("--preprocess", help="hfts-preprocess: build the mug, blob and bottle "
                   "databases into a temporary directory")
    p.add_argument("--source-dir", default=SOURCE_DIR)
    p.add_argument("--host", default="127.0.0.1")
    p.add_argument("--port", type=int, help="drive a running server instead of starting one")
    p.add_argument("--pid", type=int, help="its process id, for /proc sampling")
    p.add_argument("--answer-timeout", type=float, default=300.0,
                   help="seconds a request may wait for its answer")
    p.add_argument("--settle", type=float, default=3.0)
    p.add_argument("--settle-timeout", type=float, default=120.0)
    p.add_argument("--rss-tolerance-pct", type=float, default=5.0)
    p.add_argument("--rss-tolerance-mib", type=float, default=20.0)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--auth", action="store_true",
                   help="the started server has tokens; every connection authenticates")
    p.add_argument("--tls", action="store_true",
                   help="the started server speaks TLS (a self-signed certificate in --out)")
    p.add_argument("--verbose", "-v", action="store_true", help="a line per sample")
    o = p.parse_args(argv)
    o.port_given = o.port is not None
    o.started_at = time.strftime("%Y-%m-%dT%H:%M:%S")
    o.binary = None
    if o.interval is None:
        o.interval = 5.0 if o.minutes < 10 else 10.0
    if o.minutes <= 0 or o.clients < 1:
        p.error("MINUTES and --clients must be positive")
    return o


def start_server(o):
    """Starts hfts-server with default limits; returns (RunningServer, temporary db dir)."""
    if not os.access(o.server, os.X_OK):
        sys.exit(f"soak: {o.server} not found; run scripts/build.sh first")
    CONFIG.server, CONFIG.source_dir = os.path.abspath(o.server), os.path.abspath(o.source_dir)
    tmp = None
    if o.db is None and o.preprocess:
        from cli_support import build_databases
        tmp = tempfile.mkdtemp(prefix="hfts-soak-db-")
        build_databases(o.preprocess, o.source_dir, tmp, ["mug", "blob", "bottle"])
    db = o.db or tmp or os.path.join(o.source_dir, "build", "databases")
    if not os.path.isdir(db):
        sys.exit(f"soak: no database directory {db}; build it with scripts/demo.sh "
                 "(or give --db DIR, or --preprocess BIN)")
    o.binary = {"path": CONFIG.server, "modified": time.strftime(  # before a rebuild replaces it
        "%Y-%m-%dT%H:%M:%S", time.localtime(os.path.getmtime(CONFIG.server)))}
    extra = []
    if o.auth:
        token = "soak-plan-token-" + "".join(random.choice("0123456789abcdef") for _ in range(24))
        tokens = os.path.join(o.out, "tokens")
        with open(os.open(tokens, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), "w") as f:
            f.write(f"plan {token} soak\n")
        extra += ["--auth-tokens", tokens]
        ACCESS["token"] = token
    if o.tls:
        import ssl
        import subprocess
        cert, key = os.path.join(o.out, "cert.pem"), os.path.join(o.out, "key.pem")
        subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", key,
                        "-out", cert, "-days", "2", "-subj", "/CN=localhost", "-addext",
                        "subjectAltName=DNS:localhost,IP:127.0.0.1"],
                       check=True, capture_output=True)
        extra += ["--tls-cert", cert, "--tls-key", key]
        ACCESS["tls"] = ssl.create_default_context(cafile=cert)
    server = RunningServer(os.path.join(o.out, "server.log"), *extra, db_dir=db)
    o.host, o.port, o.pid = server.host, server.port, server.process.pid
    return server, tmp


def main(argv=None):
    o = parse(argv)
    os.makedirs(o.out, exist_ok=True)
    server, tmp = (None, None) if o.port_given else start_server(o)
    recorder = Recorder()
    monitor = Monitor(o, recorder, server and server.process)
    monitor.t0 = time.monotonic()
    exit_code, final, duration = None, {}, 0.0
    try:
        print(f"soak: hfts-server on {o.host}:{o.port} (pid {o.pid}); {o.clients} clients for "
              f"{o.minutes:g} min; sampling every {o.interval:g} s; output in {o.out}",
              flush=True)
        try:
            scenes, objects = primer(o, recorder)
        except (OSError, TimeoutError, ValueError, RuntimeError) as e:
            print(f"soak: FAIL: the server did not answer the first requests: {e!r}")
            return 1
        monitor.settled(RESERVATION, o.settle_timeout)
        baseline = monitor.quiet_measure("baseline", o.settle)
        duration = drive(o, monitor, recorder, scenes, objects)
        baseline["t"] = 0.0  # taken just before the clients started
        final = after_close(o, monitor, baseline)
    finally:
        if server is not None:
            exit_code = server.stop(timeout=60)
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)
    monitor.samples.append(final)
    memory, failures = judge(o, recorder, monitor, baseline, final, exit_code, duration)
    summary = summarize(o, recorder, monitor, baseline, final, memory, failures, duration,
                        exit_code)
    with open(os.path.join(o.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    write_csv(os.path.join(o.out, "samples.csv"), [baseline] + monitor.samples)
    plot(os.path.join(o.out, "soak.png"), monitor.samples, duration, baseline, final)
    report(summary)
    if failures and server is not None:
        print(f"  server log: {os.path.join(o.out, 'server.log')}")
    return 1 if failures else 0


def after_close(o, monitor, baseline):
    """The measurement after every client has closed: waits for the server to
    see the closes, then (with no connection open) until descriptors and
    threads are back at the baseline or `settle_timeout` has passed."""
    load = monitor.settled(RESERVATION, o.settle_timeout)
    final = monitor.quiet_measure("after close", o.settle)
    deadline = time.monotonic() + o.settle_timeout
    while (monitor.alive() and "fds" in final and time.monotonic() < deadline
           and (final["fds"], final["threads"]) != (baseline["fds"], baseline["threads"])):
        final = monitor.quiet_measure("after close", 1.0)
    final.update({"settled": load is not None, "load": load, "alive": monitor.alive()})
    return final


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, signal.default_int_handler)
    sys.exit(main())
