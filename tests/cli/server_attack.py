#!/usr/bin/env python3
"""The memory attack of issue 17 against a running hfts-server, measured.

N connections each send one message of M bytes without its newline (a JSON
text that never ends) and stay open. Meanwhile the server's resident memory
is sampled and a normal client asks `server.info` on a fresh connection
every 0.2 s; afterwards the attackers close and the memory is followed back
down. Used by test_hfts_server_limits.py (small numbers) and by hand for
docs/reliability.md:

    /usr/bin/python3 tests/cli/server_attack.py --port 7450 --pid PID \\
        --connections 200 --mib 15

Against a server with TLS and tokens (docs/security.md): --ca-file FILE
makes every connection speak TLS, --token-file FILE makes the probes
authenticate (the attackers do not, unless --attackers-authenticate: an
attacker without a token is what tokens are for).

Standard library only.
"""

import argparse
import json
import multiprocessing
import os
import socket
import sys
import threading
import time

PREFIX = b'{"jsonrpc":"2.0","id":1,"method":"plan","params":{"scene":"'
# --ca-file and --token-file: the TLS context of every connection, and the
# token of the probes (and, with --attackers-authenticate, the attackers).
ACCESS = {"tls": None, "token": None, "attackers_authenticate": False}


def connect(host, port, timeout, authenticate):
    """A connection as ACCESS says: TLS when it has a context, `auth` first
    when `authenticate` and it has a token (raises OSError when refused)."""
    sock = socket.create_connection((host, port), timeout=timeout)
    if ACCESS["tls"] is not None:
        sock = ACCESS["tls"].wrap_socket(sock, server_hostname=host)
    if authenticate and ACCESS["token"] is not None:
        sock.sendall(json.dumps({"jsonrpc": "2.0", "id": "auth", "method": "auth",
                                 "params": {"token": ACCESS["token"]}}).encode() + b"\n")
        if read_line(sock, wait=timeout) is None:
            raise ConnectionError("auth not answered")
    return sock


def resident_bytes(pid):
    with open(f"/proc/{pid}/status", encoding="ascii") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError(f"no VmRSS for process {pid}")


class Attacker(threading.Thread):
    """One connection sending `size` bytes of a message that never ends."""

    def __init__(self, host, port, size, chunk=256 << 10):
        super().__init__(daemon=True)
        self.host, self.port, self.size, self.chunk = host, port, size, chunk
        self.sent = 0
        self.outcome = None  # "sent", "closed by server", "connect failed"
        self.response = None
        self.socket = None

    def run(self):
        try:
            self.socket = connect(self.host, self.port, 30, ACCESS["attackers_authenticate"])
        except OSError as e:
            self.outcome = f"connect failed: {e}"
            return
        block = PREFIX + b"a" * (self.chunk - len(PREFIX))
        filler = b"a" * self.chunk
        try:
            while self.sent < self.size:
                data = block if self.sent == 0 else filler
                data = data[:self.size - self.sent]
                self.socket.sendall(data)
                self.sent += len(data)
            self.outcome = "sent"
        except OSError:
            self.outcome = "closed by server"
        self.response = read_line(self.socket, wait=0.05)

    def close(self):
        if self.socket is not None:
            if self.response is None:
                self.response = read_line(self.socket, wait=0.0)
            self.socket.close()


def read_line(sock, wait):
    """A response line already sent to `sock`, as JSON, or None."""
    try:
        sock.settimeout(wait if wait > 0 else 0.001)
        data = b""
        while not data.endswith(b"\n"):
            part = sock.recv(65536)
            if not part:
                break
            data += part
        return json.loads(data) if data.strip() else None
    except (OSError, ValueError):
        return None


def info_latency(host, port):
    """Seconds for server.info on a fresh connection, or None when refused."""
    start = time.monotonic()
    try:
        with connect(host, port, 10, authenticate=True) as s:
            s.sendall(b'{"jsonrpc":"2.0","id":"probe","method":"server.info"}\n')
            reply = json.loads(s.makefile("rb").readline())
    except (OSError, ValueError):
        return None
    return time.monotonic() - start if reply.get("id") == "probe" else None


def run_attackers(host, port, connections, size, hold, report, cpus):
    """In a child process (so that the probes do not share its interpreter):
    starts the attackers, waits for them, then for `hold` (an Event), closes
    them and reports their outcomes. At the lowest priority, and on `cpus`
    when given: on a small machine its 200 sending threads would otherwise
    take the CPU from the server and the probes, which a remote attacker
    does not."""
    os.nice(19)
    if cpus:
        os.sched_setaffinity(0, cpus)
    attackers = [Attacker(host, port, size) for _ in range(connections)]
    for a in attackers:
        a.start()
    for a in attackers:
        a.join()
    report.put("sent")
    hold.wait()
    codes = {}
    for a in attackers:
        a.close()
        code = (a.response or {}).get("error", {}).get("code")
        key = f"{a.outcome}, error {code}" if code else a.outcome
        codes[key] = codes.get(key, 0) + 1
    report.put(codes)


def attack(host, port, pid, connections, size, settle=10.0, log=None, attacker_cpus=None):
    """Runs the attack; returns a dict of what was measured (bytes, seconds)."""
    say = log or (lambda *_: None)
    time.sleep(0.5)
    idle = resident_bytes(pid)
    context = multiprocessing.get_context("fork")
    hold, report = context.Event(), context.Queue()
    child = context.Process(target=run_attackers,
                            args=(host, port, connections, size, hold, report, attacker_cpus),
                            daemon=True)
    start = time.monotonic()
    child.start()
    peak, latencies, timeline, refused_probes = idle, [], [], 0
    next_probe = start
    while report.empty() and child.is_alive():
        peak = max(peak, resident_bytes(pid))
        if time.monotonic() >= next_probe:
            latency = info_latency(host, port)
            if latency is None:
                refused_probes += 1
            else:
                latencies.append(latency)
                timeline.append((round(time.monotonic() - start, 2), round(latency, 4)))
            next_probe = time.monotonic() + 0.2
        time.sleep(0.02)
    attack_seconds = time.monotonic() - start
    report.get(timeout=60)
    peak = max(peak, resident_bytes(pid))
    held = resident_bytes(pid)
    say(f"attack over after {attack_seconds:.1f} s: resident {held / 2**20:.0f} MiB "
        f"(idle {idle / 2**20:.0f} MiB, peak {peak / 2**20:.0f} MiB)")
    hold.set()
    codes = report.get(timeout=60)
    child.join()
    after, deadline = resident_bytes(pid), time.monotonic() + settle
    while time.monotonic() < deadline and after > 1.02 * idle:
        time.sleep(0.1)
        after = resident_bytes(pid)
    latencies.sort()
    return {
        "idle": idle, "peak": peak, "held": held, "after": after,
        "attack_seconds": attack_seconds, "outcomes": codes,
        "probes": len(latencies), "refused_probes": refused_probes,
        "latency_median": latencies[len(latencies) // 2] if latencies else None,
        "latency_max": latencies[-1] if latencies else None,
        "probe_timeline": timeline,  # (seconds since the attack began, latency)
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--pid", type=int, required=True, help="the server's process id")
    parser.add_argument("--connections", type=int, default=200)
    parser.add_argument("--mib", type=float, default=15.0, help="bytes sent per connection (MiB)")
    parser.add_argument("--attacker-cpus", type=int, nargs="+",
                        help="run the attackers on these CPUs only (pin the server elsewhere, "
                        "e.g. with taskset, to model attackers on other machines)")
    parser.add_argument("--ca-file", help="speak TLS, trusting these CA certificates")
    parser.add_argument("--token-file", help="the probes authenticate with this file's token")
    parser.add_argument("--attackers-authenticate", action="store_true",
                        help="the attackers authenticate too (with --token-file's token)")
    args = parser.parse_args()
    if args.ca_file:
        import ssl
        ACCESS["tls"] = ssl.create_default_context(cafile=args.ca_file)
    if args.token_file:
        with open(args.token_file, encoding="utf-8") as f:
            ACCESS["token"] = f.readline().strip()
    ACCESS["attackers_authenticate"] = args.attackers_authenticate
    result = attack(args.host, args.port, args.pid, args.connections, int(args.mib * 2**20),
                    log=print, attacker_cpus=args.attacker_cpus)
    mib = {k: round(result[k] / 2**20, 1) for k in ("idle", "peak", "held", "after")}
    print(json.dumps({**result, **{k + "_mib": v for k, v in mib.items()}}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
