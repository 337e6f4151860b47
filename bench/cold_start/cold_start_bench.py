#!/usr/bin/env python3
"""Cold start of the active set method: from scratch versus the nested start.

On the paper's block refined L times (one mesh, Number of cycles = 1, so no
previous mesh to start from) it runs the Release executable in separate
processes and prints, per mesh and condition:

- floor: one linear elasticity solve on the same mesh (no contact);
- scratch: the active set method from scratch (Contact/Nested start = false:
  the first step is the unconstrained problem);
- nested: the default, Contact/Nested start = true (the input block with
  fewer refinements solved first, from the finest one with at most
  "Nested start cells" cells, each started from the one before).

For each: active-set iterations on the mesh (for nested also the coarser
meshes' iterations together), CG iterations, seconds (linear solver setup +
contact solve, the nested start's setup, assembly and solves included), the
ratio to the floor of the same run, and the peak resident memory of the
process. Times are medians of --repeat runs, interleaved so that the machine's
load affects every variant alike.

Usage: bench/cold_start/cold_start_bench.py [--levels 3 4 5 6 7] [--repeat 3]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import measure_variants, single_mesh  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[3, 4, 5, 6, 7])
    runner.add_build_argument(parser)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    print("| DoFs | condition | floor s | scratch: its, CG, s, x floor, MiB "
          "| nested: its (coarser), CG, s, x floor, MiB |")
    print("|---:|---|---:|---|---|")
    for level in args.levels:
        mesh = single_mesh(level)
        variants = {"floor": dict(mesh, **{"Contact/Boundary ids": ""})}
        for condition in ("integral", "pointwise"):
            for start in ("scratch", "nested"):
                variants[(condition, start)] = dict(mesh, **{
                    "Contact/Condition": condition,
                    "Contact/Nested start":
                        "true" if start == "nested" else "false"})
        results = measure_variants(exe, variants, args.repeat)
        floor_row, floor, _ = results["floor"]
        for condition in ("integral", "pointwise"):
            cells = []
            for start in ("scratch", "nested"):
                row, t, mib = results[(condition, start)]
                if row["converged"] != "1":
                    sys.exit(f"level {level} {condition} {start}: not converged")
                its = row["iterations"]
                if start == "nested":
                    its += f" ({row['nested_iterations']})"
                cells.append(f"{its}, {row['cg_iterations']}, {t:.3g}, "
                             f"{t / floor:.2g}, {mib:.0f}")
            print(f"| {floor_row['dofs']} | {condition} | {floor:.3g} | "
                  + " | ".join(cells) + " |", flush=True)

if __name__ == "__main__":
    sys.exit(main())
