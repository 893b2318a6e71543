#!/usr/bin/env python3
"""Grains per axial bin in each of a run's VTK snapshots (mrjam jam --snapshots DIR): how the
grains move along the tube, e.g. drawn towards the field's maximum while the valve is closed.

    python3 bench/axial_counts.py DIR [--from -3.9] [--to 3.9] [--bin 0.6]   (mm)
"""
import argparse
import glob
import os
import re
import struct


def read_snapshot(path):
    """(time in s, z of every grain in m) from a legacy binary VTK file written by mrjam."""
    data = open(path, "rb").read()
    start = data.index(b"POINTS ")
    end = data.index(b"\n", start)
    n = int(data[start:end].split()[1])
    xyz = struct.unpack(">%dd" % (3 * n), data[end + 1:end + 1 + 24 * n])
    time = float(re.search(rb"time ([0-9.eE+-]+)", data).group(1))
    return time, xyz[2::3]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("directory")
    ap.add_argument("--from", dest="lo", type=float, default=-3.9, help="mm")
    ap.add_argument("--to", dest="hi", type=float, default=3.9, help="mm")
    ap.add_argument("--bin", type=float, default=0.6, help="mm")
    a = ap.parse_args()
    files = glob.glob(os.path.join(a.directory, "*.vtk"))
    if not files:
        raise SystemExit(f"{a.directory}: no .vtk snapshots")
    bins = max(1, round((a.hi - a.lo) / a.bin))
    rows = sorted(read_snapshot(f) for f in files)
    print("t_ms  " + " ".join(f"{a.lo + k * a.bin:6.1f}" for k in range(bins)) + "   (bin starts, mm)")
    for time, z in rows:
        counts = [0] * bins
        for zz in z:
            k = int((zz * 1e3 - a.lo) // a.bin)
            if 0 <= k < bins:
                counts[k] += 1
        print(f"{time * 1e3:5.2f} " + " ".join(f"{c:6d}" for c in counts))


if __name__ == "__main__":
    main()
