#!/usr/bin/env python3
"""Strong scaling of the pipeline on 1 and 2 MPI ranks.

Runs the paper's block refined --level times (level 7: 1.58 million DoFs),
integral condition, active set solver, one computation with the error
estimate, on 1 rank and on 2 ranks (`mpirun -np 2`), one thread per rank
(DEAL_II_NUM_THREADS=1 and OPENBLAS_NUM_THREADS=1, so that the figures
measure the distribution over ranks, not deal.II's or OpenBLAS's threads:
Epetra's vector operations call the BLAS, whose threads would give the
one-rank run the second core). Prints the wall time of each phase (rank 0's
TimerOutput sections; the phases end in collective operations) as medians
over --repeat runs, the speed-up and the parallel efficiency
speed-up / ranks, and checks that both runs found the same result.

Usage: bench/scaling/scaling_bench.py [--level 7] [--repeat 3] [--ranks 2]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT  # noqa: E402
PHASES = ["setup", "assembly", "linear solver setup", "contact solve",
          "error estimate"]


def run(exe, level, ranks, work):
    prm = os.path.join(work, "case.prm")
    with open(prm, "w") as f:
        f.write(f"""include {os.path.join(ROOT, "prm", "block.prm")}
set Output directory = {work}/out
set Number of cycles = 1
subsection Mesh
  set Initial refinements = {level}
end
subsection Output
  set Write vtu = false
  set Print timing = true
end
""")
    command = [exe, prm]
    if ranks > 1:
        command = ["mpirun", "-np", str(ranks)] + command
    env = dict(os.environ, DEAL_II_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    out = subprocess.run(command, check=True, capture_output=True, text=True,
                         env=env).stdout
    times = {}
    for phase in PHASES:
        match = re.search(r"\|\s*" + re.escape(phase) + r"\s*\|\s*\d+\s*\|\s*([0-9.e+-]+)s",
                          out)
        times[phase] = float(match.group(1)) if match else 0.
    row = runner.read_statistics(os.path.join(work, "out"))[-1]
    return times, row


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", type=int, default=7)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--ranks", type=int, default=2)
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    results = {}
    with tempfile.TemporaryDirectory() as work:
        for ranks in (1, args.ranks):
            samples = [run(exe, args.level, ranks, work) for _ in range(args.repeat)]
            results[ranks] = ({p: statistics.median(s[0][p] for s in samples)
                               for p in PHASES}, samples[-1][1])
    serial, parallel = results[1], results[args.ranks]
    print(f"block, level {args.level}: {serial[1]['dofs']} DoFs, "
          f"{serial[1]['cells']} cells; medians of {args.repeat} runs, "
          "1 thread per rank")
    print(f"| phase | 1 rank (s) | {args.ranks} ranks (s) | speed-up | efficiency |")
    print("|---|---|---|---|---|")
    for phase in PHASES + ["total"]:
        if phase == "total":
            t1 = sum(serial[0].values())
            tn = sum(parallel[0].values())
        else:
            t1, tn = serial[0][phase], parallel[0][phase]
        speedup = t1 / tn if tn > 0 else float("nan")
        print(f"| {phase} | {t1:.3g} | {tn:.3g} | {speedup:.2f} | "
              f"{100 * speedup / args.ranks:.0f} % |")
    same = all(serial[1][k] == parallel[1][k]
               for k in ("cells", "dofs", "active_nodes"))
    for key in ("energy", "eps"):
        a, b = float(serial[1][key]), float(parallel[1][key])
        same &= abs(a - b) <= 1e-7 * abs(a)
    print(f"same result on 1 and {args.ranks} ranks (cells, active nodes, "
          f"energy, eps): {'yes' if same else 'NO'}; CG iterations "
          f"{serial[1]['cg_iterations']} vs {parallel[1]['cg_iterations']}")


main()
