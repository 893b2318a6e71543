#!/usr/bin/env python3
"""The asteroid modes' tiers: how many grains and steps each runs, and what it costs on this machine.

Runs each bundled asteroid scene at the given tiers on one thread for PROBE seconds, reads the
last progress line (step, share of the run, grain-steps per second), stops the run with SIGINT
and extrapolates the whole run's wall time from the share done. The early steps of a run are
not its average (a cloud's contacts grow as it collapses; a heap's settle as it comes to rest),
so the figure is an estimate, stated as such; the quick tier's measured wall times are in
docs/asteroid.md beside it.

    python3 bench/asteroid_tier_costs.py [--tiers standard paper] [--probe 90] [--binary build/mrjam]
"""
import argparse
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = [("coalesce", "examples/asteroid/coalesce_119Am.json"),
          ("spinup", "examples/asteroid/spinup_119Am.json"),
          ("avalanche", "examples/asteroid/avalanche_5mT.json")]
PROGRESS = re.compile(r"step (\d+)/(\d+) \(([\d.]+)% of the run\).*?([\d.e+]+) grain-steps/s")


def probe(binary, mode, scene, tier, seconds, work):
    out = os.path.join(work, f"{mode}_{tier}")
    with open(os.path.join(ROOT, scene)) as f:
        s = json.load(f)
    s["output"] = {"directory": out}
    path = out + ".json"
    with open(path, "w") as f:
        json.dump(s, f)
    cmd = [binary, "asteroid", mode, path, "--report", out + "_report.json", "--fidelity", tier, "--threads", "1"]
    start = time.time()
    p = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
    last = None
    while time.time() - start < seconds:
        line = p.stderr.readline()
        if not line:
            break
        m = PROGRESS.search(line)
        if m:
            last = (time.time() - start, float(m.group(3)), float(m.group(4)))
    p.send_signal(signal.SIGINT)
    p.wait()
    return last


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tiers", nargs="+", default=["standard", "paper"])
    ap.add_argument("--probe", type=float, default=90, help="seconds of each run to measure")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "mrjam"))
    a = ap.parse_args()
    print("| mode | tier | grain-steps/s (1 thread) | share of the run in the probe | whole run, extrapolated |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="mrjam_tiers_") as work:
        for mode, scene in SCENES:
            for tier in a.tiers:
                r = probe(a.binary, mode, scene, tier, a.probe, work)
                if not r:
                    print(f"| {mode} | {tier} | no progress line in {a.probe:.0f} s | | |")
                    continue
                elapsed, pct, rate = r
                whole = elapsed * 100 / pct if pct > 0 else float("inf")
                print(f"| {mode} | {tier} | {rate:.3g} | {pct:.2f} % in {elapsed:.0f} s | "
                      f"{whole / 3600:.1f} h |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
