#!/usr/bin/env python3
"""A body held by the contact alone: the block on a roller (tests/runs/roller.prm).

Usage: floating_body.py SIGNORINI_BINARY SOURCE_DIR WORK_DIRECTORY

The left edge is a roller (u_x = 0 only), so the vertical translation is
stopped by the foundation alone. For both conditions and both solvers, on 1
and 3 MPI ranks, every cycle must
- converge, with the solution checks at round-off (below 1e-10);
- carry a contact force equal to the applied vertical load: with no vertical
  support, the foundation balances the pressure p = 0.1 on the top left half
  (length 1/2), i.e. -0.05 (compressive);
- give the same energy with both solvers (the same discrete problem);
and the 3-rank run must reproduce the serial one (tests/runs/serial_parallel.py).
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from serial_parallel import compare, read, run  # noqa: E402

APPLIED_VERTICAL_LOAD = -0.1 * 0.5
CHECKS = ["feasibility", "multiplier_sign", "complementarity", "residual",
          "resultant"]


def main():
    binary, source, work = sys.argv[1:4]
    prm = os.path.join(source, "tests", "runs", "roller.prm")
    shutil.rmtree(work, ignore_errors=True)
    problems = []
    energies = {}
    for condition in ["integral", "pointwise"]:
        for solver in ["active set", "Frank-Wolfe"]:
            extra = ("subsection Contact\n"
                     f"  set Condition = {condition}\n"
                     f"  set Solver = {solver}\n"
                     "end\n")
            case = f"{condition}, {solver}"
            name = f"{condition}-{solver.replace(' ', '_')}"
            serial = os.path.join(work, name, "serial")
            parallel = os.path.join(work, name, "np3")
            run(binary, prm, serial, 1, extra)
            run(binary, prm, parallel, 3, extra)
            rows = read(os.path.join(serial, "statistics.csv"))
            for row in rows:
                where = f"{case}, cycle {row['cycle']}"
                if row["converged"] != "1":
                    problems.append(f"{where}: not converged")
                force = float(row["contact_force"])
                if abs(force - APPLIED_VERTICAL_LOAD) > 1e-10:
                    problems.append(f"{where}: contact force {force}")
                for check in CHECKS:
                    if not float(row[check]) <= 1e-10:
                        problems.append(f"{where}: {check} {row[check]}")
                energies.setdefault((condition, row["cycle"]), []).append(
                    (solver, float(row["energy"])))
            problems += [f"{case}, 1 vs 3 ranks: {p}"
                         for p in compare(serial, parallel)]
            print(f"{case}: cycles {[r['cells'] for r in rows]} cells, "
                  f"contact force {[r['contact_force'] for r in rows]}, "
                  f"energy {[r['energy'] for r in rows]}, "
                  f"eps {[r.get('eps', '-') for r in rows]}")
    for (condition, cycle), values in energies.items():
        (_, e1), (_, e2) = values
        if abs(e1 - e2) > 1e-9 * abs(e1):
            problems.append(f"{condition}, cycle {cycle}: energies {values}")
    for p in problems:
        print("  " + p)
    print("FAILED" if problems else
          "both conditions and both solvers: contact force = applied load, "
          "checks at round-off, identical on 1 and 3 ranks")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
