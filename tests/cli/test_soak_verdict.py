#!/usr/bin/env python3
"""The soak's memory verdict (tests/cli/soak.py, judge_memory) on synthetic
resident-memory series: in-flight plans make the samples jump by tens of
MiB, which must not read as a leak; a leak of a fraction of a MiB per second
must, both in the trend under traffic and after all clients have closed."""
import os
import random
import sys
import types
import unittest

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import soak  # noqa: E402

MIB = soak.MIB
DURATION = 30.0  # the ctest smoke: half a minute sampled every 0.5 s
INTERVAL = 0.5
OPTIONS = types.SimpleNamespace(rss_tolerance_pct=5.0, rss_tolerance_mib=20.0)


def series(rng, leak_mib_per_s, base_mib=110.0):
    """Samples of a server whose plans in flight add 0-30 MiB at random
    (about one sample in four), over a steady base that grows by the leak."""
    samples = []
    t = INTERVAL
    while t <= DURATION + 1e-9:
        in_flight = rng.uniform(0.0, 30.0) if rng.random() < 0.25 else rng.uniform(0.0, 4.0)
        rss = base_mib + leak_mib_per_s * t + in_flight
        samples.append({"t": round(t, 2), "phase": "run", "rss": rss * MIB, "fds": 27,
                        "threads": 7})
        t += INTERVAL
    baseline = {"t": 0.0, "rss": base_mib * MIB}
    final = {"rss": (base_mib + leak_mib_per_s * DURATION + rng.uniform(-2.0, 3.0)) * MIB}
    return samples, baseline, final


def verdict(samples, baseline, final):
    return soak.judge_memory(OPTIONS, samples, DURATION, baseline, final)


class SlopeTest(unittest.TestCase):
    def test_exact_on_a_line(self):
        points = [(t, 3.0 + 2.0 * t) for t in range(10)]
        self.assertAlmostEqual(soak.slope(points), 2.0)

    def test_two_spikes_at_the_end_do_not_tilt_it(self):
        points = [(t, 100.0) for t in range(18)] + [(18, 130.0), (19, 130.0)]
        self.assertEqual(soak.slope(points), 0.0)


class MemoryVerdictTest(unittest.TestCase):
    def test_plans_in_flight_are_not_a_leak(self):
        rng = random.Random(7)
        failing = []
        for _ in range(300):
            facts, failures = verdict(*series(rng, 0.0))
            self.assertTrue(facts["judged"])
            if failures:
                failing.append(failures)
        self.assertEqual(failing, [])

    def test_a_leak_is_caught_under_traffic_and_after_close(self):
        # 1.5 MiB/s: 30 MiB over the judged 20 s, 45 MiB by the end.
        rng = random.Random(11)
        for _ in range(300):
            _, failures = verdict(*series(rng, 1.5))
            self.assertTrue(any("trends up" in f for f in failures), failures)
            self.assertTrue(any("not back after all clients closed" in f for f in failures),
                            failures)

    def test_memory_kept_after_close_is_caught_alone(self):
        samples, baseline, _ = series(random.Random(3), 0.0)
        final = {"rss": baseline["rss"] + 25 * MIB}
        facts, failures = verdict(samples, baseline, final)
        self.assertAlmostEqual(facts["after_close_growth_mib"], 25.0)
        self.assertEqual(len(failures), 1)
        self.assertIn("not back after all clients closed", failures[0])

    def test_too_few_samples_are_not_judged(self):
        samples, baseline, final = series(random.Random(5), 5.0)
        facts, failures = soak.judge_memory(OPTIONS, samples[:4], DURATION, baseline, final)
        self.assertFalse(facts["judged"])
        self.assertEqual(failures, [])


if __name__ == "__main__":
    unittest.main()
