#!/usr/bin/env python3
"""Frank-Wolfe, the paper's solver, against the floor on the block.

On the block refined L times (one mesh) it runs the Release executable in
separate processes, per mesh and condition:

- floor: one linear elasticity solve (Linear solver/Type = automatic);
- FW direct: Frank-Wolfe with its default columns, one sparse direct
  factorisation and a back-substitution per column of the dual operator
  (up to Contact/Frank-Wolfe/Direct columns limit DoFs);
- FW AMG: the same with one AMG-CG solve per column (Direct columns limit =
  0), capped at --amg-columns columns on meshes above 10^5 DoFs.

For each: Frank-Wolfe steps, columns formed (linear solves), seconds (linear
solver setup + contact solve), ratio to the floor of the same run, the KKT
residual reached (Tolerance 1e-12 by default) and the peak resident memory.
Times are medians of --repeat runs (levels above --repeat-up-to: one run).

Usage: bench/frank_wolfe/frank_wolfe_bench.py [--levels 4 5 6] [--repeat 3]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import measure_variants, single_mesh  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[4, 5, 6])
    runner.add_build_argument(parser)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--repeat-up-to", type=int, default=5)
    parser.add_argument("--amg-columns", type=int, default=60)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    print("| DoFs | condition | floor s | FW direct: steps, columns, s, x floor,"
          " residual, MiB | FW AMG: steps, columns, s, x floor, residual, MiB |")
    print("|---:|---|---:|---|---|")
    for level in args.levels:
        mesh = single_mesh(level)
        variants = {"floor": dict(mesh, **{"Contact/Boundary ids": ""})}
        for condition in ("integral", "pointwise"):
            fw = dict(mesh, **{"Contact/Condition": condition,
                               "Contact/Solver": "Frank-Wolfe"})
            variants[(condition, "direct")] = fw
            amg = dict(fw, **{"Contact/Frank-Wolfe/Direct columns limit": "0"})
            if level > 5:
                amg["Contact/Frank-Wolfe/Maximum columns"] = str(args.amg_columns)
            variants[(condition, "amg")] = amg
        repeat = args.repeat if level <= args.repeat_up_to else 1
        results = measure_variants(exe, variants, repeat)
        floor_row, floor, _ = results["floor"]
        for condition in ("integral", "pointwise"):
            cells = []
            for variant in ("direct", "amg"):
                row, t, mib = results[(condition, variant)]
                capped = "" if row["converged"] == "1" else " (capped)"
                cells.append(f"{row['iterations']}, {row['linear_solves']}"
                             f"{capped}, {t:.3g}, {t / floor:.2g}, "
                             f"{float(row['kkt_residual']):.1e}, {mib:.0f}")
            print(f"| {floor_row['dofs']} | {condition} | {floor:.3g} | "
                  + " | ".join(cells) + " |", flush=True)

if __name__ == "__main__":
    sys.exit(main())
