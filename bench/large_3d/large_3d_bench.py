#!/usr/bin/env python3
"""The largest 3D runs of a machine: time and memory of each phase.

Runs prm/block-3d.prm on one mesh (--subdivisions refined --level times; the
defaults, 7 x 5 x 3 refined 4 times, give 10.3M tetrahedra and 5.3M DoFs),
one computation, on --ranks MPI ranks (oversubscribed: memory per rank does
not care how many cores there are), with `Linear solver/AMG/Low memory`, the
contact solve by the active set method with its nested start, and with the
error estimate if --estimate. Prints, per phase of the program's own tables
(`Output/Print timing`), its calls, wall seconds, and on the largest rank the
peak resident memory at its end and how far the phase raised it, then the
whole run's peak, in kB (1000 bytes) per DoF and per tetrahedron. One run: a run of
this size takes minutes, and the memory does not vary.

Usage: /usr/bin/python3 bench/large_3d/large_3d_bench.py [--level 4]
       [--subdivisions 7 5 3] [--ranks 2] [--estimate] [--build build]
"""
import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import run_logged, write_case  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", type=int, default=4)
    parser.add_argument("--subdivisions", type=int, nargs=3,
                        default=[7, 5, 3])
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--estimate", action="store_true")
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    overrides = {
        "Mesh/Initial refinements": str(args.level),
        "Mesh/Block subdivisions": ", ".join(map(str, args.subdivisions)),
        "Number of cycles": "1",
        "Maximum cells": "1e9",
        "Linear solver/Type": "AMG-CG",
        "Linear solver/AMG/Low memory": "true",
        "Error estimator/Enable": "true" if args.estimate else "false",
        "Output/Write vtu": "false",
        "Output/Print timing": "true"}
    with tempfile.TemporaryDirectory() as work:
        prm, out = write_case("block-3d.prm", overrides, work)
        command = runner.on_ranks([exe, prm], args.ranks)
        output, code, _ = run_logged(command)
        if code != 0:
            sys.exit(f"{command} failed:\n{output}")
        row = runner.read_statistics(out)[-1]
    times, memory = runner.phase_tables(output)
    dofs, cells = int(row["dofs"]), int(row["cells"])
    print(f"{cells} tetrahedra, {dofs} DoFs, {args.ranks} ranks, estimate "
          f"{'on' if args.estimate else 'off'}; active set iterations "
          f"{row['iterations']}, CG iterations {row['cg_iterations']}")
    print("| phase | calls | wall s | peak MiB at its end (largest rank) | "
          "raised by MiB |")
    print("|---|---:|---:|---:|---:|")
    for phase, (calls, seconds) in times.items():
        peak, raised = memory.get(phase, (float("nan"), None))
        raised = "" if raised is None else f"{raised:.0f}"
        print(f"| {phase} | {calls} | {seconds:.3g} | {peak:.0f} | {raised} |")
    peak = memory["whole run"][0]
    print(f"whole run: peak {peak:.0f} MiB on the largest rank, "
          f"{peak * 1024 * 1.024 / dofs:.2f} kB per DoF, "
          f"{peak * 1024 * 1.024 / cells:.2f} kB per tetrahedron")


if __name__ == "__main__":
    main()
