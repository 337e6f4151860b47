#!/usr/bin/env python3
"""Time to the answer: the adaptive examples, wall time per stage, 1 and 2 ranks.

Runs the shipped examples prm/block-adaptive.prm (the block to 2 %, meshes by
remeshing) and prm/hertz-adaptive.prm (Hertz to 2 %, with a reference solution
on the final mesh refined twice) as a user does, with the Release executable,
on 1 and 2 MPI ranks, --repeat times each (interleaved), and prints per stage
(the program's own TimerOutput sections, summed over the cycles) the median
wall time on each rank count and their ratio, then the total (the timer's),
the process from launch to exit (MPI start included) and the total without
the reference solution and comparison (the answer itself: the mesh that
reaches the target and its error figure). The answer (cells and eps of
the last cycle) is printed too, and must be the same on both rank counts.

Usage: bench/time_to_answer/time_to_answer.py [--repeat 3] [--ranks 1 2]
       [--build build]
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT  # noqa: E402
CASES = ["block-adaptive.prm", "hertz-adaptive.prm"]
REFERENCE_STAGES = ("reference solution", "reference comparison")


def run(exe, prm_dir, name, ranks, out):
    """Run prm_dir/name with timing on; return ({stage: s}, total s, rows)."""
    prm = os.path.join(prm_dir, f"bench-{name}")
    with open(os.path.join(prm_dir, name)) as f, open(prm, "w") as g:
        g.write(f.read())
        g.write(f"\nset Output directory = {out}\n"
                "subsection Output\n  set Print timing = true\nend\n")
    command = [exe, prm]
    if ranks > 1:
        command = ["mpirun", "-np", str(ranks), "--oversubscribe"] + command
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1")
    start = time.monotonic()
    log = subprocess.run(command, capture_output=True, text=True, env=env)
    process_seconds = time.monotonic() - start
    if log.returncode != 0:
        sys.exit(f"{name} on {ranks} rank(s) failed:\n{log.stdout}{log.stderr}")
    stages, total = {}, None
    for line in log.stdout.splitlines():
        m = re.match(r"\| Total wallclock time elapsed since start\s*\|\s*"
                     r"([0-9.e+-]+)s", line)
        if m:
            total = float(m.group(1))
        m = re.match(r"\| (\w[\w /-]*?)\s*\|\s*(\d+) \|\s*([0-9.e+-]+)s \|", line)
        if m:
            stages[m.group(1)] = float(m.group(3))
    if total is None or not stages:
        sys.exit(f"{name}: no timing table in the screen log")
    rows = runner.read_statistics(out)
    stages["process (launch to exit, MPI start included)"] = process_seconds
    return stages, total, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    with tempfile.TemporaryDirectory() as work:
        prm_dir = os.path.join(work, "prm")
        shutil.copytree(os.path.join(ROOT, "prm"), prm_dir,
                        ignore=shutil.ignore_patterns("output*"))
        for name in CASES:
            samples = {r: [] for r in args.ranks}
            answers = {}
            for _ in range(args.repeat):
                for ranks in args.ranks:
                    out = os.path.join(work, f"out-{name}-{ranks}")
                    stages, total, rows = run(exe, prm_dir, name, ranks, out)
                    samples[ranks].append((stages, total))
                    answers[ranks] = [(int(r["cells"]), float(r["eps"]))
                                      for r in rows]
            print(f"\n{name}: cycles (cells, eps %) " + " | ".join(
                f"{r} rank(s): "
                + ", ".join(f"({c}, {100 * e:.4g})" for c, e in answers[r])
                for r in args.ranks))
            # (the rank counts agree to the solver tolerance, not bitwise)
            first = answers[args.ranks[0]]
            for r in args.ranks[1:]:
                if [c for c, _ in answers[r]] != [c for c, _ in first] or any(
                        abs(e - f) > 1e-6 * abs(f)
                        for (_, e), (_, f) in zip(answers[r], first)):
                    print(f"WARNING: {r} ranks disagree with "
                          f"{args.ranks[0]} on the answer")
            names = sorted({s for r in args.ranks for st, _ in samples[r]
                            for s in st if not s.startswith("process")})
            header = "| stage | " + " | ".join(f"{r} rank(s) s" for r in
                                               args.ranks)
            if len(args.ranks) > 1:
                header += f" | {args.ranks[0]} / {args.ranks[-1]}"
            print(header + " |")
            print("|---|" + "---:|" * (len(args.ranks) +
                                       (1 if len(args.ranks) > 1 else 0)))

            def line(label, values):
                text = f"| {label} | " + " | ".join(f"{v:.3g}" for v in values)
                if len(values) > 1 and values[-1] > 0:
                    text += f" | {values[0] / values[-1]:.2f}"
                print(text + " |")

            for stage in names:
                line(stage, [statistics.median(st.get(stage, 0.)
                                               for st, _ in samples[r])
                             for r in args.ranks])
            line("total", [statistics.median(t for _, t in samples[r])
                           for r in args.ranks])
            process = [s for s in samples[args.ranks[0]][0][0]
                       if s.startswith("process")][0]
            line(process, [statistics.median(st[process]
                                             for st, _ in samples[r])
                           for r in args.ranks])
            line("answer (total without the reference)",
                 [statistics.median(t - sum(st.get(s, 0.)
                                            for s in REFERENCE_STAGES)
                                    for st, t in samples[r])
                  for r in args.ranks])
            sys.stdout.flush()


if __name__ == "__main__":
    sys.exit(main())
