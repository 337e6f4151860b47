#!/usr/bin/env python3
"""Frictional Hertz contact of a cylinder against Cattaneo-Mindlin.

Usage: cattaneo_mindlin_study.py SIGNORINI_BINARY [WORK_DIRECTORY]
       [--poisson 0.3,0.4,0.45,0.49] [--steps 4] [--tangential 0.002]

Runs prm/hertz-friction.prm (a cylinder of radius 1 pressed on a rigid plane
with Coulomb friction mu = 0.3 by moving its top edge down, then sideways)
for each Poisson ratio, and compares with Hertz and Cattaneo-Mindlin:
- a: the half-width of the contact zone (each edge midway between the last
  node in contact and the first one out), against Hertz's
  sqrt(4 P R / (pi E*)), E* = E / (1 - nu^2), P the normal load;
- c: the half-width of the stick zone (the same rule), against
  Cattaneo-Mindlin's a sqrt(1 - Q / (mu P)) (with the computed a), Q the
  tangential load; e: the offset of the stick zone's centre from the
  contact zone's, in units of a (0 for Cattaneo-Mindlin).
Cattaneo-Mindlin ignores the coupling of normal and tangential tractions,
which a rigid foundation has unless nu = 1/2 (Dundurs' beta =
(1 - 2 nu) / (2 (1 - nu)) vanishes); the table shows the trend with nu.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
MU = 0.3


def zone_half_width(rows, inside):
    """Half-width and centre of the nodes where inside(row) holds (a
    contiguous zone, edges midway to the neighbouring nodes)."""
    xs = [float(r["x"]) for r in rows]
    flags = [inside(r) for r in rows]
    indices = [i for i, f in enumerate(flags) if f]
    if not indices:
        return 0., 0.
    first, last = indices[0], indices[-1]
    if any(not f for f in flags[first:last + 1]):
        sys.exit("the zone is not contiguous")
    left = xs[first] if first == 0 else 0.5 * (xs[first - 1] + xs[first])
    right = xs[last] if last + 1 == len(xs) else \
        0.5 * (xs[last] + xs[last + 1])
    return 0.5 * (right - left), 0.5 * (right + left)


def study(binary, work, nu, steps, tangential):
    directory = os.path.join(work, f"nu-{nu}")
    os.makedirs(directory, exist_ok=True)
    prm = os.path.join(directory, "run.prm")
    with open(prm, "w") as f:
        f.write(f"include {os.path.join(SOURCE, 'prm', 'hertz-friction.prm')}\n"
                f"set Output directory = {directory}\n"
                "subsection Mesh\n  set File name = "
                f"{os.path.join(SOURCE, 'prm', 'hertz-cylinder.geo')}\nend\n"
                f"subsection Material\n  set Poisson ratio = {nu}\nend\n"
                f"subsection Contact\n  set Load steps = {steps}\nend\n"
                "subsection Boundary conditions\n  subsection Dirichlet 1\n"
                f"    set Function constants = delta=0.012, d={tangential}\n"
                "  end\nend\n"
                "subsection Output\n  set Write vtu = false\n"
                "  set Print timing = false\nend\n")
    result = subprocess.run([binary, prm], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{binary} {prm} failed:\n{result.stdout}{result.stderr}")
    statistics = list(csv.DictReader(
        open(os.path.join(directory, "statistics.csv"))))[-1]
    rows = [r for r in csv.DictReader(
        open(os.path.join(directory, "contact-00.csv")))
        if r["multiplier_node"] == "1"]
    rows.sort(key=lambda r: float(r["x"]))
    P = abs(float(statistics["contact_force"]))
    Q = abs(float(statistics["tangential_force"]))
    e_star = 1. / (1. - nu * nu)
    a_hertz = math.sqrt(4. * P / (math.pi * e_star))
    a, centre = zone_half_width(rows, lambda r: r["active"] == "1")
    c, stick_centre = zone_half_width(
        rows, lambda r: r["friction_status"] == "stick")
    c_mindlin = a * math.sqrt(max(1. - Q / (MU * P), 0.))
    return {"nu": nu, "beta": (1 - 2 * nu) / (2 * (1 - nu)), "P": P,
            "Q/(mu P)": Q / (MU * P), "a": a, "a Hertz": a_hertz,
            "c/a": c / a, "c/a CM": c_mindlin / a,
            "e/a": (stick_centre - centre) / a,
            "h/a": min(abs(float(r["x"]) - float(s["x"])) for r, s in
                       zip(rows, rows[1:])) / a}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("work", nargs="?", default="cattaneo-mindlin")
    parser.add_argument("--poisson", default="0.3,0.4,0.45,0.49")
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--tangential", type=float, default=0.002)
    args = parser.parse_args()
    results = [study(os.path.abspath(args.binary), os.path.abspath(args.work),
                     float(nu), args.steps, args.tangential)
               for nu in args.poisson.split(",")]
    keys = list(results[0].keys())
    print(" | ".join(f"{k:>9}" for k in keys))
    for r in results:
        print(" | ".join(f"{r[k]:9.4g}" for k in keys))


if __name__ == "__main__":
    main()
