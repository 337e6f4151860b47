#!/usr/bin/env python3
"""Solver benchmark on the paper's block under uniform refinement.

For each mesh (block refined L times, L = 0..--max-level) it runs the Release
executable in separate processes and prints, per mesh: DoFs, the time of one
linear elasticity solve with the direct and the AMG-CG preconditioner (the
floor; setup + solve), the linear solver that 'automatic' picks, and for each
condition x solver the outer iterations, the contact solve time (preconditioner
setup + solve) and its ratio to the automatic floor, and the peak memory
(maximum resident set of the process). The active set method is timed from
scratch ('cold') and started from the active set of the previous, once coarser
mesh ('nested', as in a sequence of cycles; only the last cycle is timed).
Frank-Wolfe is capped on large meshes (Maximum columns); where it stops the
KKT residual reached is printed.

Usage: bench/contact/contact_bench.py [--max-level 7] [--build build]
       [--repeat 1]
"""
import argparse
import csv
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import run_case, seconds  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-level", type=int, default=7)
    runner.add_build_argument(parser)
    parser.add_argument("--repeat", type=int, default=1,
                        help="runs per measurement; the median is reported")
    parser.add_argument("--csv", default=None, help="also write the table here")
    args = parser.parse_args()
    exe = runner.executable(args.build)

    def measure(overrides):
        results = []
        with tempfile.TemporaryDirectory() as work:
            for _ in range(args.repeat):
                results.append(run_case(exe, overrides, work))
        row = results[-1][0]
        return row, statistics.median(seconds(r) for r, _ in results), \
            max(m for _, m in results)

    columns = ["level", "dofs", "contact_nodes", "floor_direct_s", "floor_amg_s",
               "automatic", "floor_s"]
    for condition in ("integral", "pointwise"):
        for variant in ("as_cold", "as_nested", "fw"):
            columns += [f"{condition}_{variant}_its", f"{condition}_{variant}_s",
                        f"{condition}_{variant}_ratio",
                        f"{condition}_{variant}_MiB"]
        columns += [f"{condition}_fw_residual"]
    table = []
    print(" | ".join(columns), flush=True)
    for level in range(args.max_level + 1):
        mesh = {"Mesh/Initial refinements": str(level), "Number of cycles": "1"}
        linear = dict(mesh, **{"Contact/Boundary ids": ""})
        entry = {"level": level}
        if level <= 5:
            row, t, _ = measure(dict(linear, **{"Linear solver/Type": "direct"}))
            entry["floor_direct_s"] = f"{t:.3g}"
        else:
            entry["floor_direct_s"] = "-"
        row, t, _ = measure(dict(linear, **{"Linear solver/Type": "AMG-CG"}))
        entry["floor_amg_s"] = f"{t:.3g}"
        row, floor, _ = measure(linear)
        entry.update(dofs=row["dofs"], automatic=row["linear_solver"],
                     floor_s=f"{floor:.3g}")
        for condition in ("integral", "pointwise"):
            contact = dict(mesh, **{"Contact/Condition": condition})
            variants = {
                "as_cold": dict(contact, **{
                    "Contact/Initial active set from previous cycle": "false",
                    "Contact/Nested start": "false"}),
                "as_nested": dict(contact, **{
                    "Mesh/Initial refinements": str(max(level - 1, 0)),
                    "Number of cycles": "2" if level > 0 else "1"}),
                "fw": dict(contact, **{
                    "Contact/Solver": "Frank-Wolfe",
                    "Contact/Frank-Wolfe/Maximum columns":
                        "100000" if level <= 5 else ("60" if level == 6 else "20")}),
            }
            for variant, overrides in variants.items():
                row, t, mib = measure(overrides)
                key = f"{condition}_{variant}"
                entry["contact_nodes"] = row["contact_nodes"]
                entry[key + "_its"] = row["iterations"] + \
                    ("" if row["converged"] == "1" else " (capped)")
                entry[key + "_s"] = f"{t:.3g}"
                entry[key + "_ratio"] = f"{t / floor:.2g}"
                entry[key + "_MiB"] = f"{mib:.0f}"
                if variant == "fw":
                    entry[key + "_residual"] = f"{float(row['kkt_residual']):.1e}"
        table.append(entry)
        print(" | ".join(str(entry.get(c, "")) for c in columns), flush=True)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=columns)
            writer.writeheader()
            writer.writerows(table)


if __name__ == "__main__":
    sys.exit(main())
