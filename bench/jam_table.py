#!/usr/bin/env python3
"""The jam predictor's measured table (docs/notes/jam_measurements.md, "Where it stands") from finished reports.

One row per `mrjam jam` report, and one per later seed of a `--seeds N` report: case, tier,
seed, grains, outcome, time to arrest, grains passed before it, the grain flux over the last
0.5 ms of field (for a flow the field did not stop), the hold, wall time and grain-steps per
second. Reports written before `flux_share_with_field` existed get the flux from their flux
history, by the same count-at-time rule as the C++ (lib/jam/throat_flux.cpp).

    python3 bench/jam_table.py out/jam_tiers/*.report.json
"""
import json
import sys

from jam_steady_check import passed_at  # the count-at-time rule, shared with the steady-flow check


def last_flux_share(res, span=0.5e-3):
    """Grain flux over the last `span` of the field period, as a share of the no-field flux."""
    rows = res.get("flux_history", {}).get("rows", [])
    base = res.get("no_field_flux_grains_per_s") or 0
    on = res.get("field_switched_on_s")
    if not rows or not base or on is None:
        return None
    end = on + res["time_to_arrest_s"] if res.get("jammed") else rows[-1][0]
    if end - span < on:
        span = end - on
    if span <= 0:
        return None
    return (passed_at(rows, end) - passed_at(rows, end - span)) / span / base


def case_name(inputs):
    field = inputs.get("field", {})
    where = f"{field.get('flux_density', 0) * 1e3:.0f} mT" if field.get("type") == "uniform" else "map"
    psd = inputs.get("grains", {}).get("psd", "44um")
    valve = inputs.get("valve", {})
    # The resolved scene gives the diameter; the constriction's name is its ratio to 44 um.
    name = valve.get("constriction") or f"{valve.get('constriction_diameter', 0) / 44e-6:.0f}x"
    model = inputs.get("model", {})
    supply = ", batch" if model.get("supply") == "batch" else ""
    # The frictionless slab is the default; a frictional one is a different valve model.
    faces = ""
    if model.get("slab_faces") == "frictional":
        faces = f", {model.get('slab_thickness_diameters', 0):g}-diameter slab, frictional faces"
    youngs = inputs.get("material", {}).get("youngs_modulus", 1e9)
    stiffness = f", E {youngs / 1e9:g} GPa" if youngs != 1e9 else ""  # the examples' 1 GPa goes unsaid
    cutoff = model.get("magnetic_cutoff_diameters")
    cutoff = f", dipole cutoff {cutoff:g} d" if cutoff else ""  # given in the scene; else the tier's
    interval = model.get("magnetic_update_interval", 1)
    hold = f", magnetic forces held {interval} steps" if interval > 1 else ""
    return f"{psd} {name}, {where}{faces}{supply}{stiffness}{cutoff}{hold}"


def grains_words(res):
    """The grains modelled; for a finite batch (model/supply), the batch and what was left."""
    batch = res.get("batch")
    if isinstance(batch, dict):
        return f"{batch['grains_at_start']:,} ({batch['grains_left']:,} left)"
    return f"{res.get('grains', 0):,}"


def hold_words(hold):
    if not isinstance(hold, dict):
        return "-"
    share = f"{hold.get('flux_share', 0) * 100:.1f} %"
    if hold.get("gave_way_after_s") is not None:
        return f"gave way after {hold['gave_way_after_s'] * 1e3:.2f} ms ({share})"
    if hold.get("held"):
        return f"held ({share})"
    # Reports older than the give-way time cannot tell a break from a creep.
    return f"crept ({share})" if "gave_way_after_s" in hold else f"not held ({share})"


def row(r):
    res = r.get("results", {})
    share = None if res.get("jammed") else last_flux_share(res)
    arrest = res.get("time_to_arrest_s")
    perf = r.get("performance", {})
    return [
        case_name(r.get("inputs_jam", {})),
        r.get("fidelity", {}).get("jam_tier") or r.get("fidelity", {}).get("tier", "?"),
        str(r.get("seed", "?")),
        grains_words(res),
        res.get("outcome", r.get("status", "?")),
        f"{arrest * 1e3:.2f} ms" if arrest is not None else "-",
        str(res.get("grains_passed_before_arrest")) if arrest is not None else "-",
        f"{share * 100:.0f} %" if share is not None else "-",
        hold_words(res.get("hold")),
        f"{r.get('wall_time_s', 0):,.0f} s",
        f"{perf.get('grain_steps_per_s', 0):.2g}",
    ]


def seed_rows(r):
    """The later seeds of a `--seeds N` report, from their summary records (`seeds`): no grain
    count, history or wall time of their own, and the flux over the last arrest window only."""
    first = row(r)
    window = r.get("inputs_jam", {}).get("protocol", {}).get("arrest_window", 0)
    rows = []
    for rec in r.get("seeds", [])[1:]:
        arrest = rec.get("time_to_arrest_s")
        share = rec.get("flux_share_last_window")
        flux = f"{share * 100:.0f} % (last {window * 1e3:g} ms)" if share is not None and arrest is None else "-"
        rows.append(first[:2] + [str(rec.get("seed", "?")), "-", rec.get("outcome", rec.get("status", "?")),
                                 f"{arrest * 1e3:.2f} ms" if arrest is not None else "-", "-", flux,
                                 hold_words(rec.get("hold")), "-", "-"])
    return rows


def main(paths):
    if not paths:
        sys.exit(__doc__)
    head = ["case", "tier", "seed", "grains", "outcome", "time to arrest", "grains passed before",
            "flux, last 0.5 ms of field", "hold", "wall", "grain-steps/s"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for p in paths:
        try:
            report = json.load(open(p))
            if report.get("mode") != "jam":
                print(f"| {p}: not a `mrjam jam` report (a design's runs are under its directory) |" + " |" * (len(head) - 1))
                continue
            for cells in [row(report)] + seed_rows(report):
                print("| " + " | ".join(cells) + " |")
        except (OSError, ValueError, KeyError, TypeError) as e:
            print(f"| {p}: unreadable ({e}) |" + " |" * (len(head) - 1))


if __name__ == "__main__":
    main(sys.argv[1:])
