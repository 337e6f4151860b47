#!/usr/bin/env python3
"""The 3D block at a million DoFs: the contact solve against one linear solve.

Runs prm/block-3d.prm (the paper's block extruded, tetrahedra, u_z = 0 on the
faces z = 0, 1) in separate processes on one mesh (--subdivisions, refined
--level times; the defaults give 2.36M tetrahedra, 1.24M DoFs), one
computation without the estimator, on each of --ranks MPI ranks: the floor
(one AMG-CG elasticity solve, no contact) and the contact solve (integral
condition, active set method with its nested start). Prints per case the
active set iterations, the CG iterations of all its linear solves, the
seconds of setup + solve (median of --repeat runs), the ratio contact / floor
measured in the same run of the script, the stage times of the program's own
timer (assembly, setup, make grid: the cost around the solves), and the peak
resident memory of one rank.

Usage: /usr/bin/python3 bench/block_3d/block_3d_bench.py [--level 4]
       [--subdivisions 4 3 2] [--ranks 1 2] [--repeat 1] [--build build]
"""
import argparse
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import run_logged, write_case  # noqa: E402


def run(exe, ranks, overrides, work):
    """Run block-3d.prm with @p overrides on @p ranks; return (statistics
    row, stage seconds, peak MiB of the largest rank)."""
    prm, out = write_case("block-3d.prm", overrides, work)
    command = runner.on_ranks([exe, prm], ranks)
    output, code, peak = run_logged(command)
    if code != 0:
        sys.exit(f"{command} failed:\n{output}")
    times, _ = runner.phase_tables(output)
    stages = {phase: seconds for phase, (_, seconds) in times.items()}
    row = runner.read_statistics(out)[-1]
    return row, stages, peak


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", type=int, default=4)
    parser.add_argument("--subdivisions", type=int, nargs=3, default=[4, 3, 2])
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeat", type=int, default=1)
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    mesh = {"Mesh/Initial refinements": str(args.level),
            "Mesh/Block subdivisions": ", ".join(map(str, args.subdivisions)),
            "Number of cycles": "1",
            "Linear solver/Type": "AMG-CG",
            "Output/Write vtu": "false",
            "Output/Print timing": "true"}
    cases = {"floor": dict(mesh, **{"Contact/Boundary ids": ""}),
             "contact": dict(mesh)}
    print("| ranks | case | DoFs | active set iterations | CG iterations "
          "(all solves) | seconds (median) | contact / floor | assembly s | "
          "setup s | make grid s | peak MiB per rank |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for ranks in args.ranks:
        seconds, rows, stages, peaks = {}, {}, {}, {}
        with tempfile.TemporaryDirectory() as work:
            for case, overrides in cases.items():
                times = []
                for _ in range(args.repeat):
                    row, stage, peak = run(exe, ranks, overrides, work)
                    peaks[case] = max(peaks.get(case, 0.), peak)
                    times.append(float(row["setup_seconds"]) +
                                 float(row["solve_seconds"]))
                    rows[case], stages[case] = row, stage
                seconds[case] = statistics.median(times)
        for case in cases:
            row, stage = rows[case], stages[case]
            ratio = (f"{seconds['contact'] / seconds['floor']:.2f}"
                     if case == "contact" else "")
            print(f"| {ranks} | {case} | {row['dofs']} | "
                  f"{row.get('iterations', '')} | {row['cg_iterations']} | "
                  f"{seconds[case]:.3g} | {ratio} | "
                  f"{stage.get('assembly', 0.):.3g} | "
                  f"{stage.get('setup', 0.):.3g} | "
                  f"{stage.get('make grid', 0.):.3g} | "
                  f"{peaks[case]:.0f} |", flush=True)


if __name__ == "__main__":
    main()
