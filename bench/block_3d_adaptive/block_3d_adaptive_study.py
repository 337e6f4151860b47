#!/usr/bin/env python3
"""The adaptive computation of the extruded block (prm/block-3d-adaptive.prm:
optimal sizes for a target error, realised by remeshing with Gmsh, the
star-patch estimate) with its choices varied one at a time: the initial mesh
(Initial refinements), the Singular rate and the Error density smoothing.

Prints, per variant, the tetrahedra and eps of each computation, the N*
predicted for it, and whether the target was reached (eps <= eps_0 (1 +
tolerance), tolerance 0.025). Each variant is a whole run (1 to 5 minutes in
Release on 2 cores).

Usage: bench/block_3d_adaptive/block_3d_adaptive_study.py [--build build]
       [--target 0.05]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT  # noqa: E402

# (initial refinements, singular rate, error density smoothing)
VARIANTS = [(0, 1, 0), (0, 0.75, 0), (0, 1, 2), (0, 0.75, 2),
            (1, 0.75, 2), (1, 0.6, 0), (1, 0.6, 2), (1, 0.5, 2)]


def with_entry(text, name, value):
    """@p text with the entry @p name set to @p value (it must occur once)."""
    pattern = re.compile(r"^(\s*set " + re.escape(name) + r"\s*=).*$",
                         re.MULTILINE)
    assert len(pattern.findall(text)) == 1, name
    return pattern.sub(lambda m: f"{m.group(1)} {value}", text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    runner.add_build_argument(parser)
    parser.add_argument("--target", type=float, default=0.05)
    args = parser.parse_args()
    with open(os.path.join(ROOT, "prm", "block-3d-adaptive.prm")) as f:
        example = f.read()
    print("| initial refinements | Singular rate | Error density smoothing "
          "| tetrahedra (eps) per computation | N* predicted | target |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for refinements, rate, smoothing in VARIANTS:
            out = os.path.join(work, "out")
            text = with_entry(example, "Output directory", out)
            text = with_entry(text, "Initial refinements", refinements)
            text = with_entry(text, "Singular rate", rate)
            text = with_entry(text, "Error density smoothing", smoothing)
            text = with_entry(text, "Target error", args.target)
            prm = os.path.join(work, "case.prm")
            with open(prm, "w") as f:
                f.write(text)
            run = subprocess.run([runner.executable(args.build), prm],
                                 capture_output=True, text=True, check=True)
            rows = runner.read_statistics(out)
            meshes = ", ".join(
                f"{int(r['cells']):,} ({100 * float(r['eps']):.2f} %)"
                for r in rows)
            predicted = ", ".join(f"{float(r['predicted_cells']):,.0f}"
                                  for r in rows[1:])
            reached = ("not reached" if "not reached" in run.stdout
                       else "reached")
            print(f"| {refinements} | {rate} | {smoothing} | {meshes} "
                  f"| {predicted} | {reached} |", flush=True)


if __name__ == "__main__":
    main()
