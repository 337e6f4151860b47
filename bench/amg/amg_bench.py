#!/usr/bin/env python3
"""The linear floor: one AMG-CG elasticity solve (no contact) on the block
refined uniformly, with the former AMG settings (near null space of the
aggregates: the translations; aggregation threshold 0.02, two smoother
sweeps, V-cycles) and the current defaults of Linear solver/AMG (all rigid
motions, threshold 0, one sweep, W-cycles); and the cold active set method
(integral condition) with both on the meshes of --contact-levels. Prints,
per mesh and setting, CG iterations, seconds (preconditioner setup + solve;
median of --repeat runs), seconds per million DoFs, and the ratio former /
current measured in the same run.

Usage: /usr/bin/python3 bench/amg/amg_bench.py [--levels 5 6 7]
       [--contact-levels 5 6] [--repeat 3] [--build build]
"""
import argparse
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import run_case, seconds  # noqa: E402

SETTINGS = {
    "former": {"Linear solver/AMG/Null space": "translations",
               "Linear solver/AMG/Aggregation threshold": "0.02",
               "Linear solver/AMG/Smoother sweeps": "2",
               "Linear solver/AMG/W-cycle": "false"},
    "current": {},  # the defaults
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[5, 6, 7])
    parser.add_argument("--contact-levels", type=int, nargs="*",
                        default=[5, 6])
    parser.add_argument("--repeat", type=int, default=3)
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    print("| DoFs | case | AMG settings | CG iterations | seconds (median) | "
          "s per M DoFs | former / current |")
    print("|---|---|---|---|---|---|---|")
    for level in sorted(set(args.levels) | set(args.contact_levels)):
        cases = []
        if level in args.levels:
            cases.append(("floor", {"Contact/Boundary ids": ""}))
        if level in args.contact_levels:
            # (from scratch: the nested start would mostly solve coarser
            # meshes)
            cases.append(("active set, cold", {"Contact/Nested start": "false"}))
        for case, contact in cases:
            times = {}
            for setting, amg in SETTINGS.items():
                overrides = {"Mesh/Initial refinements": str(level),
                             "Number of cycles": "1",
                             "Error estimator/Enable": "false",
                             "Linear solver/Type": "AMG-CG",
                             **amg, **contact}
                runs = []
                with tempfile.TemporaryDirectory() as work:
                    for _ in range(args.repeat):
                        runs.append(run_case(exe, overrides, work)[0])
                times[setting] = statistics.median(seconds(r) for r in runs)
                row = runs[-1]
                dofs = int(row["dofs"])
                ratio = (f"{times['former'] / times[setting]:.2f}"
                         if setting == "current" else "")
                print(f"| {dofs} | {case} | {setting} | "
                      f"{row['cg_iterations']} | {times[setting]:.3g} | "
                      f"{times[setting] / dofs * 1e6:.3g} | {ratio} |",
                      flush=True)


if __name__ == "__main__":
    main()
