#!/usr/bin/env python3
"""What the steady-flow test (lib/jam/steady_flow.cpp) would have decided on finished jam runs.

Reads `mrjam jam` reports (run with steady_window 0, so they hold the whole field period) and,
for each window W and tolerance, prints the field time at which the test would first have called
the flow steady, against the run's real outcome. Same rule as the C++: the flux over [t-2W, t-W]
and [t-W, t] within the tolerance of the larger, both positive; the flow scale (pressure-driven
flow) at t-W and t within the tolerance too.

    python3 bench/jam_steady_check.py out/valve_mix2_30x/report.json ...
"""
import bisect
import json
import sys


def passed_at(rows, t):
    """Net grains passed at the first recorded time >= t (as ThroatFlux::passed_at)."""
    times = [r[0] for r in rows]
    i = bisect.bisect_left(times, t)
    return rows[min(i, len(rows) - 1)][1]


def first_steady(report, window, tolerance):
    res = report["results"]
    rows = res["flux_history"]["rows"]
    on = res["field_switched_on_s"]
    flow = res.get("flow_history", {}).get("rows", [])
    flow_times = [f[0] for f in flow]
    end = res["time_to_arrest_s"] + on if res["jammed"] else rows[-1][0]
    for t, _ in rows:
        if t - on < 2 * window or t > end:
            continue
        r1 = (passed_at(rows, t - window) - passed_at(rows, t - 2 * window)) / window
        r2 = (passed_at(rows, t) - passed_at(rows, t - window)) / window
        if r1 <= 0 or r2 <= 0 or abs(r2 - r1) > tolerance * max(r1, r2):
            continue
        if flow:
            s_then = flow[min(bisect.bisect_left(flow_times, t - window), len(flow) - 1)][1]
            s_now = flow[min(bisect.bisect_right(flow_times, t), len(flow)) - 1][1]
            if abs(s_now - s_then) > tolerance * max(s_now, s_then):
                continue
        return t - on
    return None


def main(paths):
    for path in paths:
        report = json.load(open(path))
        res = report["results"]
        arrest = res["time_to_arrest_s"]
        print(f"{path}: {res['outcome']}" + (f", arrest {arrest * 1e3:.2f} ms after field on" if arrest else ""))
        for window in (0.3e-3, 0.5e-3, 1.0e-3):
            t = first_steady(report, window, 0.15)
            verdict = "never" if t is None else f"steady at {t * 1e3:.2f} ms of field" + (
                " (WRONG: it arrests later)" if res["jammed"] else " (right)")
            print(f"  W {window * 1e3:.1f} ms, tolerance 0.15: {verdict}")


if __name__ == "__main__":
    main(sys.argv[1:])
