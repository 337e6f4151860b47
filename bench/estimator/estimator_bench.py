#!/usr/bin/env python3
"""Cost of the error estimate against one linear solve on the same mesh.

For the paper's block refined L times (L = --min-level..--max-level) it runs
the Release executable in separate processes and prints, per mesh: DoFs, the
time of one linear elasticity solve (the contact zone removed; preconditioner
setup + solve at the default tolerance), and for both contact conditions the
time of the whole estimate (admissible fields, the extra solve of the
pointwise condition when some Lambda_i > 0, the stress reconstruction
chosen by --reconstruction, eps_E)
with its ratio to that solve. The contact solve of the measured mesh starts
from the active set of the once coarser mesh (two cycles); only the last
cycle is reported. Medians over --repeat repetitions, each of which runs the
linear solve and the two estimates back to back; the ratios are the medians
of the ratios within a repetition.

Usage: bench/estimator/estimator_bench.py [--min-level 4] [--max-level 7]
       [--repeat 3] [--reconstruction "star patch"]
"""
import argparse
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT  # noqa: E402


def run(exe, text, work):
    prm = os.path.join(work, "case.prm")
    with open(os.path.join(ROOT, "prm", "block.prm")) as base, \
            open(prm, "w") as f:
        f.write(base.read() + text + f"""
set Output directory = {work}/out
subsection Output
  set Write vtu = false
  set Print timing = false
end
""")
    runner.run_timed([exe, prm])
    return runner.read_statistics(os.path.join(work, "out"))[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--min-level", type=int, default=4)
    parser.add_argument("--max-level", type=int, default=7)
    parser.add_argument("--repeat", type=int, default=3)
    runner.add_build_argument(parser)
    parser.add_argument("--reconstruction", default="element equilibration",
                        choices=["star patch", "element equilibration"])
    args = parser.parse_args()
    exe = runner.executable(args.build)

    print(f"Stress reconstruction: {args.reconstruction}\n")
    print("| level | DoFs | linear solve (s) | integral: estimate (s) | ratio "
          "| pointwise: estimate (s) | ratio |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for level in range(args.min_level, args.max_level + 1):
            # (each repetition runs the linear solve and both estimates
            # back to back, and the ratios are taken within it: on a shared
            # machine the load drifts over the minutes a level takes)
            linear, estimates = [], {"integral": [], "pointwise": []}
            ratios = {"integral": [], "pointwise": []}
            for _ in range(args.repeat):
                row = run(exe, f"""
set Number of cycles = 1
subsection Mesh
  set Initial refinements = {level}
end
subsection Contact
  set Boundary ids =
end
subsection Error estimator
  set Enable = false
end
""", work)
                linear.append(float(row["setup_seconds"]) +
                              float(row["solve_seconds"]))
                dofs = row["dofs"]
                for condition in ("integral", "pointwise"):
                    row = run(exe, f"""
set Number of cycles = 2
subsection Mesh
  set Initial refinements = {level - 1}
end
subsection Contact
  set Condition = {condition}
end
subsection Error estimator
  set Stress reconstruction = {args.reconstruction}
end
""", work)
                    estimates[condition].append(float(row["estimate_seconds"]))
                    ratios[condition].append(estimates[condition][-1] /
                                             linear[-1])
            cells = [str(level), dofs, f"{statistics.median(linear):.3g}"]
            for condition in ("integral", "pointwise"):
                cells += [f"{statistics.median(estimates[condition]):.3g}",
                          f"{statistics.median(ratios[condition]):.2f}"]
            print("| " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
