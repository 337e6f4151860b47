#!/usr/bin/env python3
"""The cost of friction: the contact solve with Coulomb friction against the
frictionless one on the same mesh.

prm/block.prm (2D) and prm/block-3d.prm (3D), refined --levels times, one
computation, --condition (pointwise by default), active set method,
estimator off (--million3d adds the 3D block of 16 x 12 x 8 bricks refined
twice, 1.24M DoFs, issue 36's 1M-DoF case: about 6 GB and 5 minutes per
run); each
without friction and with Coulomb mu = 0.3. Prints per mesh: DoFs, the
active-set iterations, the CG iterations, the seconds of the contact solve
(linear solver setup + solve) and the ratio frictional / frictionless.
Medians of --repeat runs, interleaved. --uniqueness-check false skips the
contraction at the solution (Contact/Uniqueness check, 2 or more solves).

Usage: bench/friction/friction_bench.py [--repeat 3] [--levels2d 4 5]
                                        [--levels3d 0 1] [--build build]
                                        [--uniqueness-check true|false]
                                        [--condition pointwise|integral]
                                        [--million3d]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import measure_variants, single_mesh  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    runner.add_build_argument(parser)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--levels2d", type=int, nargs="*", default=[4, 5])
    parser.add_argument("--levels3d", type=int, nargs="*", default=[0, 1])
    parser.add_argument("--uniqueness-check", choices=["true", "false"],
                        default="true")
    parser.add_argument("--condition", choices=["pointwise", "integral"],
                        default="pointwise")
    parser.add_argument("--million3d", action="store_true")
    args = parser.parse_args()
    exe = runner.executable(args.build)
    print("| mesh | DoFs | frictionless: iterations, CG, s | Coulomb 0.3: "
          "iterations, CG, s, stick/slip | ratio |")
    print("|---|---:|---|---|---:|")
    cases = [("block.prm", "2D block", level) for level in args.levels2d] + \
        [("block-3d.prm", "3D block", level) for level in args.levels3d]
    if args.million3d:
        cases.append(("block-3d.prm", "3D block 16 x 12 x 8", 2))
    for example, name, level in cases:
        base = dict(single_mesh(level))
        if "16 x 12 x 8" in name:
            base["Mesh/Block subdivisions"] = "16, 12, 8"
        base["Contact/Condition"] = args.condition
        friction = dict(base)
        friction["Contact/Friction"] = "Coulomb"
        friction["Contact/Friction coefficient"] = "0.3"
        friction["Contact/Uniqueness check"] = args.uniqueness_check
        results = measure_variants(exe, {"none": base, "Coulomb": friction},
                                   args.repeat, example)
        (row_0, t_0, _), (row_1, t_1, _) = results["none"], results["Coulomb"]
        print(f"| {name}, level {level} | {row_0['dofs']} | "
              f"{row_0['iterations']}, {row_0['cg_iterations']}, {t_0:.3g} | "
              f"{row_1['iterations']}, {row_1['cg_iterations']}, {t_1:.3g}, "
              f"{row_1['stick_nodes']}/{row_1['slip_nodes']} | "
              f"{t_1 / t_0:.2f} |", flush=True)


if __name__ == "__main__":
    main()
