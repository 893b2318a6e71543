#!/usr/bin/env python3
"""Run every bundled example to its report and validate each report against its schema.

    python3 scripts/run_examples.py [--out DIR] [--only PATTERN ...] [--dem] [--threads N]
                                    [--timeout SECONDS] [--mrjam PATH] [--list]

Each example in examples/ runs with its mode's command at its quickest tier (jam scenes with a
continuum block at the continuum tier, unless --dem; the other DEM modes at quick; magnetics at
quick, the 2D model), in its own folder OUT/<example>/ (so an example's output/directory lands
there). Every JSON report found in that folder afterwards is validated with
scripts/check_report_schemas.py's checker. The sweep example runs whole (its points' reports are
validated). This takes hours with --dem (the 10 um scenes), so it is not part of the test suite;
the suite's `examples` test checks only that every example is accepted by its mode.

A rerun with the same --out skips the examples already passed (OUT/results.json), so an
interrupted pass continues. OUT/summary.md tabulates example, command, wall time, exit status and
the reports checked. Exit status: 0 when every selected example ran (exit 0) and every report it
wrote is valid, 1 otherwise, 2 bad usage.
"""
import argparse
import fnmatch
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, os.pardir))
sys.path.insert(0, HERE)
from check_report_schemas import Checker, SCHEMA_DIR  # noqa: E402

ASTEROID_KINDS = ("avalanche", "coalesce", "spinup", "scaling")

# The order a pass runs in, cheapest first (so an interrupted pass has checked the most
# examples): the first pattern an example matches gives its rank. The quick-tier costs on one
# core are from docs (seconds for the continuum tier and a 2D field, minutes for a 44 um valve
# or the 00:100 shear study, 20-30 minutes for the 33:67 one, about an hour for a 10 um valve or an
# asteroid cloud).
COST_ORDER = ("epm_*", "asteroid/scaling*", "table32/*", "sweeps/*", "settle_column.json", "chains_600mT.json",
              "couette_rafts.json", "shear_trendler_00-100.json", "calibration/*", "valve_mix2_*", "design_quick.json",
              "design_*", "asteroid/avalanche*", "shear_*", "valve_10um_*", "asteroid/coalesce*", "asteroid/spinup*")


def cost_rank(name):
    return next((k for k, g in enumerate(COST_ORDER) if fnmatch.fnmatch(name, g)), len(COST_ORDER))


def command_for(name, scene, dem):
    """The mrjam arguments (after the binary) that run examples/<name>, or None for no rule."""
    path = os.path.join(ROOT, "examples", name)
    stem = os.path.splitext(os.path.basename(name))[0]
    if name.startswith("asteroid/"):
        kind = next((k for k in ASTEROID_KINDS if stem.startswith(k)), None)
        return None if kind is None else ["asteroid", kind, path, "--fidelity", "quick", "--report", "report.json"]
    if name.startswith("calibration/") or name.startswith("shear_"):
        return ["shear", path, "--fidelity", "quick", "--report", "report.json"]
    if name.startswith("table32/") or name.startswith("valve_"):
        tier = "continuum" if "continuum" in scene and not dem else "quick"
        return ["jam", path, "--fidelity", tier, "--report", "report.json"]
    if name.startswith("design_"):
        return ["design", path, "--fidelity", "quick", "--report", "report.json"]
    if name.startswith("epm_"):
        return ["magnetics", path, "--fidelity", "quick", "--report", "report.json"]
    if name.startswith("sweeps/"):
        return ["sweep", path, "--out", "sweep", "--yes"]
    if name in ("settle_column.json", "chains_600mT.json", "couette_rafts.json"):
        return ["run", path, "--fidelity", "quick", "--report", "report.json"]
    return None


def examples():
    found = []
    for base, _, files in os.walk(os.path.join(ROOT, "examples")):
        for f in files:
            if f.endswith(".json"):
                found.append(os.path.relpath(os.path.join(base, f), os.path.join(ROOT, "examples")))
    return sorted(found)


def reports_under(folder):
    out = []
    for base, _, files in os.walk(folder):
        out.extend(os.path.join(base, f) for f in files if f.endswith(".json"))
    return sorted(out)


def validate(checker, folder):
    """(reports valid, list of failure lines) for every report under folder."""
    valid, failures = 0, []
    for path in reports_under(folder):
        status, key, lines = checker.check(path)
        if status == "ok":
            valid += 1
        elif status == "fail":
            failures.append("%s (%s): %s" % (os.path.relpath(path, folder), key, "; ".join(lines[:3])))
    return valid, failures


def run_one(binary, name, argv, folder, env, timeout):
    os.makedirs(folder, exist_ok=True)
    start = time.time()
    with open(os.path.join(folder, "log.txt"), "w") as log:
        try:
            rc = subprocess.run([binary] + argv, cwd=folder, env=env, stdout=log, stderr=subprocess.STDOUT,
                                timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            rc = "timeout"
    return rc, time.time() - start


def write_summary(out, results, order):
    lines = ["# Every bundled example run to its report", "",
             "Written by `python3 scripts/run_examples.py` (%s). Wall time on this machine; "
             "`reports` is the number of JSON reports under the example's folder that its schema "
             "accepts." % time.strftime("%Y-%m-%d"), "",
             "| example | command | wall s | exit | reports valid | result |", "|---|---|---:|---|---:|---|"]
    total = 0.0
    for name in order:
        r = results.get(name)
        if r is None:
            continue
        total += r["seconds"]
        cmd = " ".join(["mrjam"] + [os.path.relpath(a, ROOT) if a.startswith(ROOT) else a for a in r["argv"]])
        lines.append("| %s | `%s` | %.0f | %s | %d | %s |" % (name, cmd, r["seconds"], r["exit"], r["valid"],
                                                            "pass" if r["pass"] else "FAIL: " + "; ".join(r["failures"])[:300]))
    lines += ["", "Total wall time: %.0f s (%.1f h)." % (total, total / 3600)]
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def parse_args(argv):
    p = argparse.ArgumentParser(description="Run every bundled example and validate its reports")
    p.add_argument("--out", default=os.path.join(ROOT, "out", "examples"), help="output folder (default out/examples)")
    p.add_argument("--only", nargs="*", default=[], help="glob(s) on the example's path inside examples/")
    p.add_argument("--dem", action="store_true", help="jam scenes with a continuum block run at the DEM quick tier instead (hours: the 10 um ones)")
    p.add_argument("--threads", type=int, default=0, help="--threads for each run (default: mrjam's choice)")
    p.add_argument("--timeout", type=float, default=7200, help="seconds before an example counts as failed")
    p.add_argument("--mrjam", default=os.path.join(ROOT, "build", "mrjam"), help="the binary (default build/mrjam)")
    p.add_argument("--list", action="store_true", help="print the commands and stop")
    args = p.parse_args(argv)
    if args.threads < 0 or args.timeout <= 0:
        p.error("--threads must be >= 0 and --timeout > 0")
    if not args.list and not os.access(args.mrjam, os.X_OK):
        p.error("--mrjam: %s is not an executable (build with scripts/build.sh)" % args.mrjam)
    return args


def main(argv=None):
    args = parse_args(argv)
    order = [n for n in examples() if not args.only or any(fnmatch.fnmatch(n, g) for g in args.only)]
    order.sort(key=lambda n: (cost_rank(n), n))
    plan = []
    for name in order:
        with open(os.path.join(ROOT, "examples", name)) as f:
            argv = command_for(name, json.load(f), args.dem)
        if argv is None:
            sys.stderr.write("error: no rule runs examples/%s: add one to command_for\n" % name)
            return 2
        if args.threads and argv[0] != "magnetics":
            argv += ["--threads", str(args.threads)]
        plan.append((name, argv + (["--quiet"] if argv[0] != "sweep" else [])))
    if args.list:
        for name, argv in plan:
            print("%-40s mrjam %s" % (name, " ".join(argv)))
        return 0
    os.makedirs(args.out, exist_ok=True)
    state = os.path.join(args.out, "results.json")
    results = json.load(open(state)) if os.path.exists(state) else {}
    checker = Checker(SCHEMA_DIR)
    env = dict(os.environ)
    for name, argv in plan:
        if results.get(name, {}).get("pass"):
            continue
        folder = os.path.join(args.out, os.path.splitext(name)[0])
        rc, seconds = run_one(args.mrjam, name, argv, folder, env, args.timeout)
        valid, failures = validate(checker, folder)
        if rc != 0:
            failures.insert(0, "exit %s (see %s)" % (rc, os.path.relpath(os.path.join(folder, "log.txt"), args.out)))
        if valid == 0:
            failures.append("no report written")
        results[name] = {"argv": argv, "seconds": seconds, "exit": rc, "valid": valid, "failures": failures,
                         "pass": not failures}
        print("%-40s %7.0f s  exit %-7s %d report(s) valid  %s" % (name, seconds, rc, valid,
                                                                   "pass" if not failures else "FAIL " + failures[0]),
              flush=True)
        with open(state + ".tmp", "w") as f:
            json.dump(results, f, indent=1)
        os.replace(state + ".tmp", state)
        write_summary(args.out, results, order)
    failed = [n for n, _ in plan if not results.get(n, {}).get("pass")]
    print("%d example(s), %d failed%s" % (len(plan), len(failed), ": " + ", ".join(failed) if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
