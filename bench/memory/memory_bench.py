#!/usr/bin/env python3
"""Peak memory of the linear floor and of the contact solve, per AMG hierarchy.

On the block refined --level times (1.58M DoFs at level 7), one computation
without the estimate, it runs the Release executable in separate processes
and prints, for each case (the floor: one AMG-CG elasticity solve without the
contact; the contact solve: the active set method with its nested start, both
conditions) and each hierarchy (Trilinos ML with smoothed aggregation, the
default; ML with plain aggregation; Linear solver/AMG/Low memory), the CG
iterations, the seconds of setup + solve (median of --repeat runs,
interleaved), and the peak resident memory of the process (the largest of the
runs), with the ratio to the 1.2 GiB target.

Usage: /usr/bin/python3 bench/memory/memory_bench.py [--level 7] [--repeat 3]
       [--build build]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import measure_variants, single_mesh  # noqa: E402

HIERARCHIES = {
    "ML, smoothed aggregation (default)": {},
    "ML, plain aggregation": {"Linear solver/AMG/Smoothed aggregation": "false"},
    "Low memory": {"Linear solver/AMG/Low memory": "true"},
}
TARGET_GIB = 1.2


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", type=int, default=7)
    parser.add_argument("--repeat", type=int, default=3)
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    mesh = dict(single_mesh(args.level), **{"Linear solver/Type": "AMG-CG"})
    cases = {
        "floor": {"Contact/Boundary ids": ""},
        "contact, integral, nested start": {"Contact/Condition": "integral"},
        "contact, pointwise, nested start": {"Contact/Condition": "pointwise"},
    }
    print("| case | hierarchy | DoFs | CG iterations | seconds (median) | "
          f"peak MiB | peak GiB | peak / {TARGET_GIB} GiB |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for case, overrides in cases.items():
        variants = {name: dict(mesh, **overrides, **hierarchy)
                    for name, hierarchy in HIERARCHIES.items()}
        results = measure_variants(exe, variants, args.repeat)
        for name, (row, seconds, mib) in results.items():
            gib = mib / 1024.
            print(f"| {case} | {name} | {row['dofs']} | "
                  f"{row['cg_iterations']} | {seconds:.3g} | {mib:.0f} | "
                  f"{gib:.3f} | {gib / TARGET_GIB:.2f} |", flush=True)


if __name__ == "__main__":
    main()
