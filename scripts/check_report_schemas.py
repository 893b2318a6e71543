#!/usr/bin/env python3
"""Validate mrjam JSON reports against the schemas in schemas/ (JSON Schema draft-07).

    python3 scripts/check_report_schemas.py REPORT.json [REPORT.json ...]
    find out -name '*.json' | xargs python3 scripts/check_report_schemas.py

The schema is chosen by the report's "mode": run, jam, design, shear, shear-calibrate,
shear-converge, magnetics, and "asteroid <kind>" (one schema for every kind). Each failure is
printed with its JSON path. A JSON file that is not a report (a scene or sweep file also carries
"mode", but no "status", "mrjam_version" or "results") is skipped with a note; --strict counts it
as a failure. Exit status: 0 all valid, 1 a report failed (or, with --strict, a file was not a
report), 2 bad usage or a schema that could not be read.
"""
import argparse
import json
import os
import sys

try:
    import jsonschema
    from jsonschema import Draft7Validator
except ImportError:  # pragma: no cover
    sys.stderr.write("error: the Python package jsonschema is needed (Debian: apt-get install python3-jsonschema)\n")
    sys.exit(2)

SCHEMA_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "schemas")

# keys that only a report has (a scene or sweep file has "mode" but none of them)
REPORT_KEYS = ("status", "mrjam_version", "results")
MESSAGE_LIMIT = 300


def schema_key(mode, modes):
    """The schema's mode for a report's "mode" ("asteroid <kind>" share one), or None."""
    if not isinstance(mode, str):
        return None
    if mode == "asteroid" or mode.startswith("asteroid "):
        mode = "asteroid"
    return mode if mode in modes else None


def json_path(parts):
    out = "$"
    for p in parts:
        out += "[%d]" % p if isinstance(p, int) else (".%s" % p if str(p).isidentifier() else "[%s]" % json.dumps(p))
    return out


def short(text):
    text = " ".join(str(text).split())
    return text if len(text) <= MESSAGE_LIMIT else text[:MESSAGE_LIMIT] + "..."


def leaf_errors(error):
    """The innermost errors of an anyOf/oneOf/if-then failure, which say what is actually wrong."""
    if not error.context:
        return [error]
    leaves = []
    for sub in error.context:
        leaves.extend(leaf_errors(sub))
    return leaves


class Checker:
    def __init__(self, schema_dir):
        self.schema_dir = schema_dir
        self.validators = {}
        # schemas/report_<mode>.schema.json, one per mode
        self.modes = sorted(name[len("report_"):-len(".schema.json")] for name in os.listdir(schema_dir)
                            if name.startswith("report_") and name.endswith(".schema.json"))

    def validator(self, key):
        if key not in self.validators:
            path = os.path.join(self.schema_dir, "report_%s.schema.json" % key)
            with open(path) as f:
                schema = json.load(f)
            Draft7Validator.check_schema(schema)
            self.validators[key] = (path, Draft7Validator(schema))
        return self.validators[key]

    def check(self, path):
        """Returns ("ok" | "fail" | "skip", schema key or None, list of message lines)."""
        try:
            with open(path) as f:
                report = json.load(f)
        except (OSError, ValueError) as e:
            return "fail", None, ["cannot read JSON: %s" % short(e)]
        if not isinstance(report, dict) or "mode" not in report:
            return "skip", None, ["not a report (no top-level \"mode\")"]
        if not any(k in report for k in REPORT_KEYS):
            return "skip", None, ["not a report (\"mode\" %s but none of %s: a scene or sweep file?)"
                                  % (json.dumps(report["mode"]), ", ".join(REPORT_KEYS))]
        key = schema_key(report["mode"], self.modes)
        if key is None:
            return "fail", None, ["$.mode: unknown mode %s (known: %s, asteroid <kind>)"
                                  % (json.dumps(report["mode"]), ", ".join(k for k in self.modes if k != "asteroid"))]
        _, validator = self.validator(key)
        lines = []
        errors = sorted(validator.iter_errors(report), key=lambda e: list(map(str, e.absolute_path)))
        for error in errors:
            leaves = leaf_errors(error)
            if len(leaves) == 1 and leaves[0] is error:
                lines.append("%s: %s" % (json_path(error.absolute_path), short(error.message)))
                continue
            lines.append("%s: %s (%s)" % (json_path(error.absolute_path), short(error.message), error.validator))
            seen = set()
            for leaf in leaves:
                line = "    %s: %s" % (json_path(leaf.absolute_path), short(leaf.message))
                if line not in seen:
                    seen.add(line)
                    lines.append(line)
        return ("fail" if lines else "ok"), key, lines


def main(argv=None):
    parser = argparse.ArgumentParser(description="Validate mrjam JSON reports against schemas/report_<mode>.schema.json")
    parser.add_argument("reports", nargs="+", help="report files (JSON)")
    parser.add_argument("--schemas", default=SCHEMA_DIR, help="directory of the schemas (default: the repo's schemas/)")
    parser.add_argument("--strict", action="store_true", help="a JSON file that is not a report is a failure")
    parser.add_argument("--quiet", action="store_true", help="print failures and the summary only")
    args = parser.parse_args(argv)

    try:
        checker = Checker(args.schemas)
    except OSError as e:
        sys.stderr.write("error: --schemas: cannot list %s (%s)\n" % (args.schemas, e.strerror))
        return 2
    counts = {}  # schema key -> [ok, failed]
    failed = skipped = 0
    for path in args.reports:
        try:
            status, key, lines = checker.check(path)
        except (OSError, ValueError, jsonschema.SchemaError) as e:
            sys.stderr.write("error: a schema could not be used: %s\n" % short(e))
            return 2
        if key is not None:
            counts.setdefault(key, [0, 0])[status != "ok"] += 1
        if status == "ok":
            if not args.quiet:
                print("ok    %s (%s)" % (path, key))
        elif status == "skip":
            skipped += 1
            if args.strict:
                failed += 1
                print("FAIL  %s: %s" % (path, lines[0]))
            elif not args.quiet:
                print("skip  %s: %s" % (path, lines[0]))
        else:
            failed += 1
            print("FAIL  %s%s" % (path, " (%s)" % key if key else ""))
            for line in lines:
                print("      " + line)
    summary = ", ".join("%s %d ok%s" % (k, ok, " %d failed" % bad if bad else "") for k, (ok, bad) in sorted(counts.items()))
    print("checked %d file(s): %s%s; %d failure(s)" % (len(args.reports), summary or "no reports",
                                                       "; %d skipped (not reports)" % skipped if skipped else "",
                                                       failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
