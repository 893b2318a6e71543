#!/usr/bin/env python3
"""The measured tables of docs/shear.md, run and written from the current binary.

Every row is the bundled 00:100 example (examples/shear_trendler_00-100.json) at a tier, with a
seed and at most a few keys changed (CASES below). `--run` runs the rows whose report is missing
(one `mrjam shear` at a time, one thread each, into OUT/NAME/report.json, with OUT/NAME/run.json
saying which commit built the binary, `--commit`, by default the checkout's HEAD, and when); `--write` rewrites each table of docs/shear.md between its
markers, `<!-- tables.py: TABLE -->` and `<!-- tables.py: end -->`, from those reports, with the
commit and date of the runs. A table is only written when every row of it has a report from
the same commit, so a table never mixes binaries.

    python3 bench/shear/tables.py --run [--only 'quick_*'] [--mrjam build/mrjam] [--out out/bench_shear]
    python3 bench/shear/tables.py --write
    python3 bench/shear/tables.py --list

The whole set is about an hour and a half of one core on this 2-core machine (the paper tier, the
volume reading and the longer magnetic ranges are the long rows).
"""
import argparse
import copy
import datetime
import fnmatch
import json
import pathlib
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "shear_trendler_00-100.json"
DOC = ROOT / "docs" / "shear.md"

# name: (table, tier, changes as {JSON pointer: value}, what the change is)
CASES = {
    "quick_seed1": ("tiers", "quick", {}, "as bundled"),
    "quick_seed2": ("tiers", "quick", {"/seed": 2}, "seed 2"),
    "quick_seed3": ("tiers", "quick", {"/seed": 3}, "seed 3"),
    "standard_seed1": ("tiers", "standard", {}, "as bundled"),
    "standard_seed2": ("tiers", "standard", {"/seed": 2}, "seed 2"),
    "paper_seed1": ("tiers", "paper", {}, "as bundled"),
    "quick_saturation": ("sensitivity", "quick", {"/magnetic/saturation": "material"}, "saturating grains (M_s 1.7e6 A/m)"),
    "quick_no_rolling": ("sensitivity", "quick", {"/contact/rolling": "none"}, "no rolling resistance"),
    "quick_monodisperse": ("sensitivity", "quick", {"/size": {"distribution": "single", "diameter": "6.7 um"}},
                           "monodisperse 6.7 um"),
    "quick_volume_reading": ("sensitivity", "quick", {"/size/parts/0/size/basis": "volume"},
                             "volume reading of the size table"),
    "quick_density10": ("sensitivity", "quick", {"/scaling": {"density": 10}}, "density x 10"),
    "quick_long_first_rate": ("sensitivity", "quick", {"/ladder/strain_first": 1.5}, "first rate 1.5 strain"),
    "quick_lees_edwards": ("sensitivity", "quick", {"/cell/boundaries": "lees_edwards"}, "Lees-Edwards boundaries"),
    "quick_lees_edwards_seed2": ("sensitivity", "quick", {"/cell/boundaries": "lees_edwards", "/seed": 2},
                                 "Lees-Edwards boundaries, seed 2"),
    "quick_range_16um": ("sensitivity", "quick", {"/magnetic/cutoff": {"beyond_contact": "16 um"}},
                         "magnetic range 16 um beyond contact"),
    "quick_range_24um": ("sensitivity", "quick", {"/magnetic/cutoff": {"beyond_contact": "24 um"}},
                         "magnetic range 24 um beyond contact"),
}


def set_pointer(doc, pointer, value):
    """Sets doc at a JSON pointer, creating objects on the way (a list is indexed by number)."""
    parts = pointer.lstrip("/").split("/")
    node = doc
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node.setdefault(p, {})
    if isinstance(node, list):
        node[int(parts[-1])] = value
    else:
        node[parts[-1]] = value


def commit():
    try:
        return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def run_case(name, mrjam, out, built_from):
    table, tier, changes, _ = CASES[name]
    folder = out / name
    folder.mkdir(parents=True, exist_ok=True)
    scene = json.loads(EXAMPLE.read_text())
    for pointer, value in changes.items():
        set_pointer(scene, pointer, copy.deepcopy(value))
    scene.setdefault("output", {})["directory"] = str(folder / "run")
    (folder / "scene.json").write_text(json.dumps(scene, indent=1))
    cmd = [str(mrjam), "shear", str(folder / "scene.json"), "--report", str(folder / "report.json"),
           "--fidelity", tier, "--threads", "1", "--quiet"]
    started = time.time()
    with open(folder / "log.txt", "w") as log:
        code = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode
    info = {"command": " ".join(cmd), "exit": code, "wall_s": round(time.time() - started, 1), "commit": built_from,
            "date": datetime.date.today().isoformat()}
    (folder / "run.json").write_text(json.dumps(info, indent=1))
    print(f"{name}: exit {code}, {info['wall_s']} s", flush=True)
    return code == 0


def first_rate_drift(rate):
    """The first rate's drift across its window (kPa) and whether it was flagged; None before the key existed."""
    if "drift_in_window_Pa" not in rate:
        return None
    flag = " (drifting)" if rate.get("drifting_in_window") else ""
    return f"{rate['drift_in_window_Pa'] / 1e3:+.1f} ± {rate['drift_error_Pa'] / 1e3:.1f}{flag}"


def core_us(rep):
    """Core-us per grain-step of the study's cells; '-' for a report of before the key."""
    value = rep.get("performance", {}).get("core_us_per_grain_step")
    return f"{value:.3f}" if isinstance(value, (int, float)) else "-"


def row(name, out):
    rep = json.loads((out / name / "report.json").read_text())
    info = json.loads((out / name / "run.json").read_text())
    res = rep["results"]
    curve = res["flow_curve"]
    fits = res["fits"]
    b = fits["bingham"]
    exp = res.get("experiment", {}).get("yield_stress_Pa")
    high = [q["stress_Pa"] for q in curve if q["rate_1_s"] >= 200]
    hb = fits.get("herschel_bulkley", {})
    casson = fits.get("casson", {})

    def kpa(x):
        return f"{x / 1e3:.1f}" if isinstance(x, (int, float)) else "-"

    cells = [
        name, CASES[name][3], rep["fidelity"]["tier"], str(rep.get("seed", "")),
        f"{res['cell'].get('gap_m', 0) * 1e6 + 2 * res['cell'].get('raft_thickness_m', 0) * 1e6:.0f}",
        str(res["cell"]["grains"]), f"{res['cell']['timestep_s'] * 1e9:.2f}",
        f"{curve[0]['strain']:.2f} / {curve[-1]['strain']:.2f}" if curve else "-",
        f"{kpa(b.get('yield_stress_Pa'))} ± {kpa(b.get('yield_stress_error_Pa'))}",
        f"{(b['yield_stress_Pa'] / exp - 1) * 100:+.1f} %" if exp and b.get("ok") else "-",
        kpa(statistics.mean(high)) if high else "-",
        " / ".join(kpa(q["stress_Pa"]) for q in curve),
        first_rate_drift(curve[0]) or "-",
        f"{kpa(casson.get('yield_stress_Pa'))} / {kpa(hb.get('yield_stress_Pa'))}",
        f"{rep['wall_time_s']:.0f}",
        core_us(rep),
    ]
    return "| " + " | ".join(cells) + " |", info


HEADER = ("| run | change | tier | seed | cell (um) | grains | dt (ns) | strain first / last rate | "
          "Bingham yield (kPa) | vs experiment | mean stress >= 200 1/s (kPa) | stress per rate (kPa) | "
          "first rate's drift across its window (kPa) | Casson / HB yield (kPa) | wall (s) | core-us per grain-step |")


def render(table, out):
    names = [n for n, c in CASES.items() if c[0] == table]
    missing = [n for n in names if not (out / n / "report.json").exists()]
    if missing:
        return None, f"no report for {', '.join(missing)}"
    rows, infos = zip(*(row(n, out) for n in names))
    commits = {i["commit"] for i in infos}
    if len(commits) > 1:
        return None, f"rows from different commits ({', '.join(sorted(commits))}); rerun them"
    dates = sorted({i["date"] for i in infos})
    lines = [f"Generated by `python3 bench/shear/tables.py --write` from runs of commit {commits.pop()} "
             f"({', '.join(dates)}; `--run` runs them: one thread each, rates 1164, 582, 291 and 100 1/s, "
             "Bingham over the first three).", "", HEADER, "|" + "---|" * (HEADER.count("|") - 1)]
    return "\n".join(lines + list(rows)), None


def write(out):
    text = DOC.read_text()
    for table in sorted({c[0] for c in CASES.values()}):
        start, end = f"<!-- tables.py: {table} -->", "<!-- tables.py: end -->"
        if start not in text:
            sys.exit(f"{DOC}: no marker {start}")
        body, why = render(table, out)
        if body is None:
            print(f"{table}: not written: {why}")
            continue
        i = text.index(start) + len(start)
        j = text.index(end, i)
        text = text[:i] + "\n" + body + "\n" + text[j:]
        print(f"{table}: written")
    DOC.write_text(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--run", action="store_true", help="run the rows without a report")
    ap.add_argument("--write", action="store_true", help="rewrite the tables (in docs/shear.md) between their markers")
    ap.add_argument("--list", action="store_true", help="print the rows and stop")
    ap.add_argument("--only", nargs="*", default=["*"], help="glob(s) on the row names")
    ap.add_argument("--mrjam", default=str(ROOT / "build" / "mrjam"))
    ap.add_argument("--out", default=str(ROOT / "out" / "bench_shear"))
    ap.add_argument("--commit", help="the commit the binary was built from (default: the checkout's HEAD)")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    chosen = [n for n in CASES if any(fnmatch.fnmatch(n, g) for g in args.only)]
    if args.list or not (args.run or args.write):
        for n in chosen:
            print(f"{n:24s} {CASES[n][0]:12s} {CASES[n][1]:9s} {CASES[n][3]}")
        return
    if args.run:
        for n in chosen:
            if not (out / n / "report.json").exists():
                run_case(n, args.mrjam, out, args.commit or commit())
    if args.write:
        write(out)


if __name__ == "__main__":
    main()
