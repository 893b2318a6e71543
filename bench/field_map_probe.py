#!/usr/bin/env python3
"""|B| and (By, Bz) of a field map (`mrjam magnetics --field-map`) in the plane x = 0, at the
nearest node to each (y, z): where a map's field sits against its value on the axis.

    python3 bench/field_map_probe.py OUT/40x/field.map [--y-mm -1.2,-0.8,...] [--z-mm -1,-0.5,...]

Standard library only; the format is lib/engine/magnetic/external_field.hpp's (x fastest, then y, z).
"""
import argparse


def read_map(path):
    with open(path) as f:
        if f.readline().split() != ["mrjam-fieldmap", "1"]:
            raise SystemExit(f"{path}: not an mrjam-fieldmap 1 file")
        n = [int(v) for v in f.readline().split()]
        origin = [float(v) for v in f.readline().split()]
        spacing = [float(v) for v in f.readline().split()]
        values = [tuple(float(v) for v in line.split()) for line in f if line.strip()]
    if len(values) != n[0] * n[1] * n[2]:
        raise SystemExit(f"{path}: {len(values)} nodes, header says {n[0] * n[1] * n[2]}")
    return n, origin, spacing, values


def node(n, origin, spacing, axis, coordinate):
    i = round((coordinate - origin[axis]) / spacing[axis])
    return min(max(i, 0), n[axis] - 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("map")
    ap.add_argument("--y-mm", default="-1.2,-0.8,-0.4,0,0.4,0.8,1.2")
    ap.add_argument("--z-mm", default="-1.0,-0.5,-0.1,0,0.1,0.3")
    a = ap.parse_args()
    n, origin, spacing, values = read_map(a.map)
    ys = [float(v) * 1e-3 for v in a.y_mm.split(",")]
    zs = [float(v) * 1e-3 for v in a.z_mm.split(",")]
    i = node(n, origin, spacing, 0, 0.0)
    print("mT: |B| (By, Bz) at x = 0; columns y = " + ", ".join(f"{y * 1e3:g}" for y in ys) + " mm")
    for z in zs:
        k = node(n, origin, spacing, 2, z)
        cells = []
        for y in ys:
            j = node(n, origin, spacing, 1, y)
            bx, by, bz = values[(k * n[1] + j) * n[0] + i]
            cells.append(f"{1e3 * (bx * bx + by * by + bz * bz) ** 0.5:4.0f}({1e3 * by:+4.0f},{1e3 * bz:+4.0f})")
        print(f"z = {z * 1e3:+.1f} mm: " + " ".join(cells))


if __name__ == "__main__":
    main()
