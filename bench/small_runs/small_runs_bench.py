#!/usr/bin/env python3
"""Small runs: the whole process, and the linear solver they should use.

For small 2D and 3D cases (estimator off, outputs as the examples write
them) it runs the Release executable in separate processes and prints, per
case and linear solver (the default, then each choice forced), the median
wall time of the whole process and of its contact solve (setup + solve, from
statistics.csv), with the active set iterations. A first line gives the
start-up alone: `signorini --help`. The 3D Gmsh cubes are meshed from
tests/meshes/cube.geo by Gmsh at the given sizes (the clamped face x = 0,
contact on z = 0 against a flat foundation, a pressure on z = 1).

Usage: bench/small_runs/small_runs_bench.py [--repeat 5] [--quick]
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT  # noqa: E402

SOLVERS = {
    "default": {},
    "KLU": {"Linear solver/Type": "direct",
            "Linear solver/Direct solver package": "Amesos_Klu"},
    "MUMPS": {"Linear solver/Type": "direct",
              "Linear solver/Direct solver package": "Amesos_Mumps"},
    "AMG-CG": {"Linear solver/Type": "AMG-CG"},
}

CUBE = """set Dimension = 3
set Number of cycles = 1
subsection Mesh
  set Source    = file
  set File name = {mesh}
end
subsection Boundary conditions
  subsection Dirichlet 1
    set Boundary ids        = 1
    set Components          = x, y, z
    set Function expression = 0; 0; 0
  end
  subsection Traction 1
    set Boundary ids        = 3
    set Function expression = 0; 0; -0.1
  end
end
subsection Contact
  set Boundary ids = 2
  set Direction    = 0, 0, -1
  subsection Gap
    set Function expression = 0
  end
end
"""


def cases(work, quick):
    """(name, parameter file text without output directory) of each case."""
    found = []
    for level in ([2, 3] if quick else [2, 3, 4]):
        with open(runner.example("block.prm")) as f:
            found.append((f"2D block, level {level}", f.read() +
                          runner.entries({"Number of cycles": "1",
                                          "Mesh/Initial refinements":
                                          str(level)})))
    for size in ([0.1] if quick else [0.1, 0.07, 0.05]):
        mesh = os.path.join(work, f"cube-{size}.msh")
        subprocess.run(["gmsh", "-3", "-clmax", str(size), "-format",
                        "msh41", os.path.join(ROOT, "tests", "meshes",
                                              "cube.geo"), "-o", mesh],
                       check=True, stdout=subprocess.DEVNULL)
        found.append((f"3D Gmsh cube, size {size}", CUBE.format(mesh=mesh)))
    for level in ([0] if quick else [0, 1]):
        with open(runner.example("block-3d.prm")) as f:
            found.append((f"3D block, level {level}", f.read() +
                          runner.entries({"Number of cycles": "1",
                                          "Mesh/Initial refinements":
                                          str(level)})))
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--quick", action="store_true",
                        help="the smallest cases only")
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    help_seconds = [runner.run_timed([exe, "--help"])
                    for _ in range(args.repeat)]
    print(f"start-up (signorini --help): {runner.median(help_seconds):.3f} s"
          f" (median of {args.repeat})\n")
    print("| case | cells | DoFs | solver | method | active set iterations "
          "| contact solve (s) | whole process (s) |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for name, text in cases(work, args.quick):
            times = {key: [] for key in SOLVERS}
            solves = {key: [] for key in SOLVERS}
            rows = {}
            # (interleaved, so that the machine's load affects all alike)
            for _ in range(args.repeat):
                for key, overrides in SOLVERS.items():
                    out = os.path.join(work, "out")
                    prm = os.path.join(work, "case.prm")
                    with open(prm, "w") as f:
                        f.write(text + runner.entries(overrides) +
                                runner.entries({"Error estimator/Enable":
                                                "false"}) +
                                f"set Output directory = {out}\n")
                    times[key].append(runner.run_timed([exe, prm]))
                    rows[key] = runner.read_statistics(out)[-1]
                    solves[key].append(runner.seconds(rows[key]))
            for key in SOLVERS:
                row = rows[key]
                print(f"| {name} | {row['cells']} | {row['dofs']} | {key} | "
                      f"{row['linear_solver']} | {row['iterations']} | "
                      f"{runner.median(solves[key]):.3f} | "
                      f"{runner.median(times[key]):.3f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
