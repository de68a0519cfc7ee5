#!/usr/bin/env python3
"""Plans per second through HAProxy against the number of hfts-server
instances (scripts/scale_out.sh), beside one server without the balancer.

Every configuration gets the same plans (bundled scenes, seeds 1..K) from
the same number of concurrent clients; the configurations take turns
round by round, so that the machine's drift spreads over all of them.
Prints one line per configuration: mean plans per second over the rounds
with a 95 % interval, and the ratio to the single server without
HAProxy. The run's numbers go to docs/performance.md.

    /usr/bin/python3 tests/cli/scale_out_throughput.py --instances 1 2 3 4 \
        --workers 1 --clients 8 --plans 24 --rounds 5
"""

import argparse
import os
import queue
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "client", "python"))
import hfts_client  # noqa: E402

SCENES = ("table", "bin", "shelf")
T_975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(instances, workers, db):
    """Returns (port, process): scale_out.sh for instances >= 1, or one
    hfts-server on its own for instances == 0."""
    run_dir = tempfile.mkdtemp(prefix="hfts-throughput-")
    port = free_port()
    if instances == 0:
        command = [os.path.join(ROOT, "build", "bin", "hfts-server"), "--db", db, "--port",
                   str(port), "--workers", str(workers), "--quiet"]
        ready = "listening on"
    else:
        command = [os.path.join(ROOT, "scripts", "scale_out.sh"), str(instances), "--port",
                   str(port), "--base-port", "0", "--workers", str(workers), "--db", db,
                   "--dir", run_dir, "--", "--quiet"]
        ready = "balancer listening"
    process = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE, text=True)
    for line in process.stdout:
        if ready in line:
            return port, process
    raise RuntimeError(f"{command[0]} ended before it was ready")


def plans_per_second(port, clients, plans, time_limit):
    work = queue.Queue()
    for i in range(plans):
        work.put({"scene": SCENES[i % len(SCENES)], "seed": 1 + i, "time_limit": time_limit})
    failures = []

    def client():
        with hfts_client.HftsClient("127.0.0.1", port, timeout=300) as c:
            while True:
                try:
                    params = work.get_nowait()
                except queue.Empty:
                    return
                try:
                    c.plan(**params)
                except hfts_client.RpcError as e:
                    failures.append(e)

    threads = [threading.Thread(target=client) for _ in range(clients)]
    begin = time.monotonic()
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    if failures:
        raise RuntimeError(f"{len(failures)} plans failed: {failures[0]}")
    return plans / (time.monotonic() - begin)


def interval(values):
    mean = statistics.fmean(values)
    if len(values) < 2:
        return mean, 0.0
    half = T_975.get(len(values) - 1, 1.96) * statistics.stdev(values) / len(values) ** 0.5
    return mean, half


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--instances", type=int, nargs="+", default=[1, 2, 3, 4])
    parser.add_argument("--workers", type=int, default=1, help="planning threads per instance")
    parser.add_argument("--clients", type=int, default=8)
    parser.add_argument("--plans", type=int, default=24, help="plans per round")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--time-limit", type=float, default=20.0)
    parser.add_argument("--db", default=os.path.join(ROOT, "build", "databases"))
    args = parser.parse_args()
    if min(args.instances) < 1 or args.rounds < 1 or args.plans < 1 or args.clients < 1:
        parser.error("instances, rounds, plans and clients must be >= 1")

    configurations = [0] + args.instances  # 0: one server, no HAProxy
    rates = {n: [] for n in configurations}
    for round_number in range(args.rounds):
        order = configurations if round_number % 2 == 0 else configurations[::-1]
        for n in order:
            port, process = start(n, args.workers, args.db)
            try:
                rates[n].append(plans_per_second(port, args.clients, args.plans,
                                                 args.time_limit))
            finally:
                process.send_signal(signal.SIGTERM)
                process.wait(timeout=60)
            print(f"round {round_number + 1}, {n} instance(s): {rates[n][-1]:.2f} plans/s",
                  file=sys.stderr)

    print(f"{args.plans} plans per round ({', '.join(SCENES)}; seeds 1..{args.plans}), "
          f"{args.clients} clients, {args.workers} worker(s) per instance, {args.rounds} rounds, "
          f"{os.cpu_count()} cores")
    print("| instances | plans/s (95 % interval) | ratio to one server without HAProxy |")
    print("| --- | --- | --- |")
    for n in configurations:
        mean, half = interval(rates[n])
        ratios = [r / b for r, b in zip(rates[n], rates[0])]
        ratio, ratio_half = interval(ratios)
        label = "1, no HAProxy" if n == 0 else str(n)
        print(f"| {label} | {mean:.2f} [{mean - half:.2f}, {mean + half:.2f}] | "
              f"{ratio:.2f} [{ratio - ratio_half:.2f}, {ratio + ratio_half:.2f}] |")


if __name__ == "__main__":
    main()
