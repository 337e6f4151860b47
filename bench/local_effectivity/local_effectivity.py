#!/usr/bin/env python3
"""Where the estimate is loose: the block on uniform meshes against a
reference solution, the shares of eps_ex^2 (exact) and eps^2 (estimate) and
the effectivity by region of the body, from the VTU cell fields eps_E,
eps_ex_E and local_effectivity that the program writes.

Runs prm/block.prm as it is (the default estimator, integral condition)
with a reference on the initial mesh, Extra refinements levels beyond the
finest computational mesh, and reads output/solution-CC.vtu. Regions, by the
centroid of a cell, each cell in the first that holds it:
  (a) corner      the clamped loaded corner (0, 1): centroid within r of it
  (b) contact     cells with a vertex on the contact zone GC (y = 0)
  (c) singular    within r of another singular point: the clamped end of GC
                  (0, 0), the ends of the loads (1/2, 1) and (1, 1/2), the
                  contact/separation point (the last active node of GC)
  (d) rest
Per region: cells, share of eps_ex^2 and of eps^2, the region's
effectivity sqrt(sum eps_E^2 / sum eps_ex_E^2) and the median of the local
effectivities eps_E / eps_ex_E of its cells.

Usage: bench/local_effectivity/local_effectivity.py [--build build]
       [--meshes 4] [--extra 2] [--radius 0.125]
"""
import argparse
import csv
import math
import os
import sys
import tempfile

import numpy

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT  # noqa: E402
import vtu  # noqa: E402

REGIONS = ("(a) clamped loaded corner", "(b) contact zone",
           "(c) other singular points", "(d) rest")


def run(build, work, meshes, extra):
    """Run the block with a reference; return the output directory."""
    with open(os.path.join(ROOT, "prm", "block.prm")) as f:
        text = f.read()
    out = os.path.join(work, "out")
    text += f"""
set Output directory = {out}
set Number of cycles = {meshes}
subsection Reference solution
  set Extra refinements = {extra}
  set Mesh              = initial mesh
end
subsection Output
  set Write vtu    = true
  set Print timing = false
end
"""
    prm = os.path.join(work, "local-effectivity.prm")
    with open(prm, "w") as f:
        f.write(text)
    runner.run_timed([runner.executable(build), prm])
    return out


def separation_point(filename):
    """x of the last active node of GC (contact-CC.csv)."""
    with open(filename) as f:
        rows = [r for r in csv.DictReader(f) if r["active"] == "1"]
    return max(float(r["x"]) for r in rows) if rows else 0.


def regions(points, triangles, radius, x_s):
    """The region index (0..3 for a..d) of every cell."""
    vertices = points[triangles]                       # (cells, 3, 2)
    centroid = vertices.mean(axis=1)

    def near(p):
        return numpy.hypot(centroid[:, 0] - p[0],
                           centroid[:, 1] - p[1]) < radius

    region = numpy.full(len(triangles), 3)
    singular = numpy.zeros(len(triangles), dtype=bool)
    for p in ((0., 0.), (0.5, 1.), (1., 0.5), (x_s, 0.)):
        singular |= near(p)
    region[singular] = 2
    region[(numpy.abs(vertices[:, :, 1]) < 1e-12).any(axis=1)] = 1
    region[near((0., 1.))] = 0
    return region


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    runner.add_build_argument(parser)
    parser.add_argument("--meshes", type=int, default=4)
    parser.add_argument("--extra", type=int, default=2)
    parser.add_argument("--radius", type=float, default=0.125,
                        help="r, 1/8 of the block's side by default")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        out = run(args.build, work, args.meshes, args.extra)
        statistics = runner.read_statistics(out)
        print(f"r = {args.radius:g}; reference {args.extra} levels beyond "
              "the finest mesh (initial mesh refined)")
        print("| cells | eps | eps_ex | effectivity | region | cells in it "
              "| share of eps_ex^2 | share of eps^2 | region effectivity "
              "| median local effectivity |")
        print("|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|")
        for cycle, row in enumerate(statistics):
            points, triangles, data = vtu.read(
                os.path.join(out, f"solution-{cycle:02d}.vtu"))
            first = triangles[:, 0]      # cell fields: constant per cell
            if "eps_ex_E" not in data:
                sys.exit(f"solution-{cycle:02d}.vtu has no eps_ex_E")
            eps_E = data["eps_E"][first].astype(float)
            eps_ex_E = data["eps_ex_E"][first].astype(float)
            local = data["local_effectivity"][first].astype(float)
            x_s = separation_point(
                os.path.join(out, f"contact-{cycle:02d}.csv"))
            region = regions(points, triangles, args.radius, x_s)
            ex2, est2 = (eps_ex_E ** 2).sum(), (eps_E ** 2).sum()
            # the fields against the statistics: sum eps_ex_E^2 = eps_ex^2
            assert math.isclose(math.sqrt(ex2), float(row["eps_ex"]),
                                rel_tol=1e-4), (ex2, row["eps_ex"])
            for k, name in enumerate(REGIONS):
                cells = region == k
                a, b = (eps_ex_E[cells] ** 2).sum(), (eps_E[cells] ** 2).sum()
                finite = local[cells][numpy.isfinite(local[cells])]
                head = (f"| {len(triangles)} | {100 * float(row['eps']):.2f} %"
                        f" | {100 * float(row['eps_ex']):.2f} % | "
                        f"{float(row['effectivity']):.2f}") if k == 0 \
                    else "| | | |"
                print(f"{head} | {name} | {cells.sum()} | "
                      f"{100 * a / ex2:.1f} % | {100 * b / est2:.1f} % | "
                      f"{math.sqrt(b / a) if a > 0 else float('nan'):.2f} | "
                      f"{numpy.median(finite) if len(finite) else 0.:.2f} |")


if __name__ == "__main__":
    main()
