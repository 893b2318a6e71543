#!/usr/bin/env python3
"""Wall time and grain-steps per second of the bundled valve cases, two builds side by side.

    python3 bench/jam_speed.py BEFORE_MRJAM AFTER_MRJAM [--tiers quick,standard] [--cases mix2_20x,mix2_40x]
                               [--threads N] [--max-time "1.2 ms"] [--after-model KEY=VALUE ...]
                               [--out out/jam_speed]

Each case (examples/table32/<case>.json, the experiment's closed-first protocol in the curved
brackets' applied field) runs at each tier with each build in turn, one run at a time, with
`--threads N` or (by default) each build's own default thread count, the builds alternating so
that both see the same machine.
`--max-time` cuts the protocol's pressure period (protocol/max_time) for a quicker comparison of
speed alone; without it the runs are the real answers and their outcomes are compared too.
`--after-model KEY=VALUE` sets a key of the scene's model block in the AFTER runs only (a speed
setting against none, with one build given twice), e.g. --after-model heavier_below="44 um".
Prints one row per run: tier, case, build, outcome, grains through the throat in all, wall time,
CPU time, grain-steps per second (the report's own count over its wall time); then the speed-up.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scene_for(case, out_dir, max_time, model):
    path = os.path.join(HERE, "examples", "table32", case + ".json")
    scene = json.load(open(path))
    field = scene.get("field", {})
    if "file" in field and not os.path.isabs(field["file"]):
        field["file"] = os.path.normpath(os.path.join(os.path.dirname(path), field["file"]))
    scene.setdefault("output", {})["directory"] = os.path.join(out_dir, "out")
    if max_time:
        scene["protocol"]["max_time"] = max_time
    scene.setdefault("model", {}).update(model)
    return scene


def run_one(mrjam, case, tier, threads, out_dir, max_time, model):
    os.makedirs(out_dir, exist_ok=True)
    scene_path = os.path.join(out_dir, "scene.json")
    json.dump(scene_for(case, out_dir, max_time, model), open(scene_path, "w"), indent=1)
    report_path = os.path.join(out_dir, "report.json")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.time()
    with open(os.path.join(out_dir, "log.txt"), "w") as log:
        command = [mrjam, "jam", scene_path, "--fidelity", tier, "--report", report_path]
        if threads > 0:
            command += ["--threads", str(threads)]
        status = subprocess.call(command, stdout=log, stderr=log)
    wall = time.time() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    row = {"status": status, "wall_s": wall, "cpu_s": cpu}
    if status == 0 and os.path.exists(report_path):
        report = json.load(open(report_path))
        res = report.get("results", {})
        row["outcome"] = res.get("outcome", "?")
        row["grains_passed"] = res.get("grains_passed_total")
        perf = report.get("performance", {})
        row["grain_steps_per_s"] = perf.get("grain_steps_per_s")
        row["steps"] = perf.get("steps_run")
        row["fidelity"] = report.get("fidelity")
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--tiers", default="quick,standard")
    ap.add_argument("--cases", default="mix2_20x,mix2_40x")
    ap.add_argument("--threads", type=int, default=0, help="0: each build's own default")
    ap.add_argument("--max-time", default="")
    ap.add_argument("--after-model", nargs="*", default=[], metavar="KEY=VALUE",
                    help="model-block keys for the AFTER runs (VALUE as JSON, else a string)")
    ap.add_argument("--out", default="out/jam_speed")
    a = ap.parse_args()
    after_model = {}
    for item in a.after_model:
        key, sep, value = item.partition("=")
        if not sep or not key:
            sys.exit("--after-model: expected KEY=VALUE, got %r" % item)
        try:
            after_model[key] = json.loads(value)
        except ValueError:
            after_model[key] = value
    builds = {"before": os.path.realpath(a.before), "after": os.path.realpath(a.after)}
    for name, path in builds.items():
        if not os.access(path, os.X_OK):
            sys.exit("no executable mrjam for %s at %s" % (name, path))
    rows = []
    print("| tier | case | build | outcome | grains through | wall (s) | CPU (s) | grain-steps/s |")
    print("|---|---|---|---|---|---|---|---|")
    for tier in a.tiers.split(","):
        for case in a.cases.split(","):
            for name in ("before", "after"):
                out_dir = os.path.abspath(os.path.join(a.out, tier, case, name))
                model = after_model if name == "after" else {}
                r = run_one(builds[name], case, tier, a.threads, out_dir, a.max_time, model)
                r.update(tier=tier, case=case, build=name)
                rows.append(r)
                gs = r.get("grain_steps_per_s")
                print("| %s | %s | %s | %s | %s | %.0f | %.0f | %s |" % (
                    tier, case, name, r.get("outcome", "exit %d" % r["status"]), r.get("grains_passed", "-"),
                    r["wall_s"], r["cpu_s"], "%.3g" % gs if gs else "-"), flush=True)
    print()
    for tier in a.tiers.split(","):
        for case in a.cases.split(","):
            pair = {r["build"]: r for r in rows if r["tier"] == tier and r["case"] == case}
            if len(pair) == 2 and pair["after"]["wall_s"] > 0:
                print("%s %s: %.2fx faster (wall)" % (tier, case, pair["before"]["wall_s"] / pair["after"]["wall_s"]))
    json.dump(rows, open(os.path.join(a.out, "jam_speed.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
