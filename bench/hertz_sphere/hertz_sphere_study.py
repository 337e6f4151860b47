#!/usr/bin/env python3
"""Hertz contact of a ball in 3D (prm/hertz-sphere.prm) on meshes graded
towards the contact point, the edge there h_contact = --sizes (the mesh
meshed by Gmsh from a copy of prm/hertz-sphere.geo with that size).

Prints per mesh and condition: tetrahedra, DoFs, the Hertz radius a and peak
pressure p0 from the computed load P = 4 |contact force|, the farthest node
in contact, and at the contact point and around it (nodes with r < 0.8 a)
the two discrete pressures against p(r) = p0 (1 - r^2/a^2)^(1/2): the nodal
pressure (nodal force over the node's area) and -Lambda (the integral
condition's multiplier: the mass matrix's inverse applied to the same
forces); 'scatter' is the standard deviation of the relative errors.

Usage: bench/hertz_sphere/hertz_sphere_study.py [--sizes 0.01 0.005 0.0033]
       [--build build]
"""
import argparse
import csv
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT, write_case  # noqa: E402


def analyse(table):
    """Hertz's a and p0 from the computed load, and the pressures."""
    rows = list(csv.DictReader(open(table)))
    e_star = 1. / (1. - 0.3 ** 2)
    load = 4. * abs(sum(float(r["nodal_force"]) for r in rows))
    a = (3. * load / (4. * e_star)) ** (1. / 3.)
    p0 = 3. * load / (2. * math.pi * a * a)
    result = {"a": a, "p0": p0, "farthest": 0.}
    nodal, multiplier = [], []
    for r in rows:
        if r["multiplier_node"] != "1":
            continue
        radius = math.hypot(float(r["x"]), float(r["y"]))
        if r["active"] == "1":
            result["farthest"] = max(result["farthest"], radius)
        if radius == 0.:
            result["centre nodal"] = float(r["nodal_pressure"]) / p0
            result["centre Lambda"] = -float(r["Lambda"]) / p0
        if radius < 0.8 * a:
            exact = p0 * math.sqrt(1. - radius ** 2 / a ** 2)
            nodal.append(float(r["nodal_pressure"]) / exact - 1.)
            multiplier.append(-float(r["Lambda"]) / exact - 1.)
    result["scatter nodal"] = statistics.pstdev(nodal)
    result["scatter Lambda"] = statistics.pstdev(multiplier)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=float, nargs="+",
                        default=[0.01, 0.005, 0.0033])
    parser.add_argument("--conditions", nargs="+",
                        default=["integral", "pointwise"])
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)
    geometry = open(os.path.join(ROOT, "prm", "hertz-sphere.geo")).read()
    print("| h_contact | condition | tetrahedra | DoFs | a | farthest node "
          "in contact | nodal pressure / p0 at r = 0 | -Lambda / p0 at r = 0 "
          "| scatter nodal pressure | scatter -Lambda | seconds |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as workdir:
        for size in args.sizes:
            geo = os.path.join(workdir, "hertz-sphere.geo")
            with open(geo, "w") as f:
                f.write(re.sub(r"h_contact = [0-9.e-]+;",
                               f"h_contact = {size};", geometry).replace(
                    '"hertz-sphere-geometry.geo"',
                    '"' + os.path.join(ROOT, "prm",
                                       "hertz-sphere-geometry.geo") + '"'))
            for condition in args.conditions:
                prm, out = write_case(
                    "hertz-sphere.prm",
                    {"Mesh/File name": geo, "Contact/Condition": condition,
                     "Output/Write vtu": "false",
                     "Output/Print timing": "false"}, workdir)
                start = time.time()
                log = subprocess.run([exe, prm], capture_output=True,
                                     text=True, check=True).stdout
                seconds = time.time() - start
                cells, dofs = re.search(r"Cycle 0: (\d+) cells, (\d+) DoFs",
                                        log).groups()
                r = analyse(os.path.join(out, "contact-00.csv"))
                print(f"| {size} | {condition} | {cells} | {dofs} "
                      f"| {r['a']:.4f} | {r['farthest']:.4f} "
                      f"| {r['centre nodal']:.4f} | {r['centre Lambda']:.4f} "
                      f"| {r['scatter nodal']:.4f} "
                      f"| {r['scatter Lambda']:.4f} | {seconds:.1f} |",
                      flush=True)


if __name__ == "__main__":
    main()
