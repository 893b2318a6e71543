#!/usr/bin/env python3
"""How fast the applied field draws iron grains towards its maximum, from a field map.

The experiment's valve was closed by hand with the fluid at rest before the supply pressure went
on (Table 3.2's protocol), a period of seconds; the model magnetises for a fraction of a
millisecond. This prints, along the valve's axis, the applied field, the force on one grain (a
linear, highly permeable sphere: F = 2 pi a^3 grad(B^2) / mu0), its Stokes speed in the carrier,
the magnetic body force on the suspension (chi_eff grad(B^2) / (2 mu0), chi_eff = 3 phi / (1 - phi),
Maxwell Garnett for mu_r >> 1) and the Darcy speed at which the carrier can get out of the way of
the grains' collective drift (Kozeny-Carman permeability at the feed fraction), and the magnetic
pressure scale mu0 chi_eff H^2 / 2 at the throat and at the map's ends.

    python3 bench/magnetophoresis.py [FIELDMAP] [--diameter 44e-6] [--fraction 0.345] [--viscosity 0.16]
"""
import argparse
import math
import os

MU0 = 4e-7 * math.pi


def read_fieldmap(path):
    with open(path) as f:
        if not f.readline().startswith("mrjam-fieldmap"):
            raise SystemExit(f"{path}: not an mrjam field map")
        nx, ny, nz = map(int, f.readline().split())
        origin = list(map(float, f.readline().split()))
        step = list(map(float, f.readline().split()))
        values = [list(map(float, line.split())) for line in f if line.strip()]
    if len(values) != nx * ny * nz:
        raise SystemExit(f"{path}: {len(values)} vectors, expected {nx * ny * nz}")
    return (nx, ny, nz), origin, step, values


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("fieldmap", nargs="?", default=os.path.join(here, "..", "examples", "fields",
                                                                "curved_on_applied.fieldmap"))
    ap.add_argument("--diameter", type=float, default=44e-6, help="grain diameter, m")
    ap.add_argument("--fraction", type=float, default=0.345, help="iron volume fraction")
    ap.add_argument("--viscosity", type=float, default=0.16, help="carrier viscosity, Pa s")
    a = ap.parse_args()
    (nx, ny, nz), o, h, B = read_fieldmap(a.fieldmap)
    ix, iy = round(-o[0] / h[0]), round(-o[1] / h[1])  # the grid line nearest the axis

    def b2(k):  # |B|^2 on the axis line at z index k (x fastest, then y, then z)
        v = B[(k * ny + iy) * nx + ix]
        return v[0] ** 2 + v[1] ** 2 + v[2] ** 2

    r, d, phi, mu = a.diameter / 2, a.diameter, a.fraction, a.viscosity
    chi = 3 * phi / (1 - phi)
    k_perm = d * d * (1 - phi) ** 3 / (180 * phi * phi)
    stokes = 3 * math.pi * mu * d
    print(f"# {a.fieldmap}: axis line x = {o[0] + ix * h[0]:.2e} m, y = {o[1] + iy * h[1]:.2e} m")
    print(f"# grain {d * 1e6:g} um, fraction {phi}, carrier {mu} Pa s: chi_eff {chi:.2f}, "
          f"Kozeny-Carman permeability {k_perm:.2e} m2")
    print("z_mm  B_mT   F_grain_N   v_grain_mm_s  body_force_N_m3  v_darcy_mm_s")
    for k in range(0, nz, 2):
        lo, hi = max(k - 1, 0), min(k + 1, nz - 1)
        g = (b2(hi) - b2(lo)) / ((hi - lo) * h[2])
        f = 2 * math.pi * r ** 3 * g / MU0
        body = chi * g / (2 * MU0)
        print(f"{(o[2] + k * h[2]) * 1e3:5.1f} {math.sqrt(b2(k)) * 1e3:6.1f} {f:10.2e} {f / stokes * 1e3:9.3f}"
              f" {body:14.2e} {k_perm * body / mu * 1e3:11.4f}")
    mid = min(range(nz), key=lambda k: abs(o[2] + k * h[2]))
    for label, k in [("throat (z = 0)", mid), ("map's upstream end", 0), ("map's downstream end", nz - 1)]:
        print(f"# magnetic pressure scale mu0 chi_eff H^2 / 2 at the {label}: {chi * b2(k) / (2 * MU0):.0f} Pa")


if __name__ == "__main__":
    main()
