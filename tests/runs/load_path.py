#!/usr/bin/env python3
"""The quasi-static load path (Contact/Load steps) against exact solutions.

Usage: load_path.py SIGNORINI_BINARY SOURCE_DIR WORK_DIRECTORY

Every step of every run must converge with its checks at round-off, and
- proportional slip: the strip of tests/runs/friction_strip.prm (full
  slip, Coulomb) in 4 equal steps. Every step is the affine solution times
  t (all nodes slide, the same way), so the last one is the exact solution
  (relative energy-norm error below 1e-7), every node has slid by the
  exact slip in all (accumulated_slip, 1e-9), and the energy of step k is
  (k/4)^2 times the last one (2e-9: the digits of the CSV files);
- the same on the 3D strip sliding obliquely (3 steps);
- unloading: the strip sheared to full slip at t = 1/2, then the shear
  removed at t = 1 (Load factor = 1, data written in t). The bottom is
  where the shear left it, and so is the stress-free solution without
  shear: every node sticks, with no tangential force, and that affine
  solution is exact (with either Friction solver), the accumulated slip
  that of the first step. The static problem of the same final data (one step,
  from the unloaded state) is another one (relative error above 0.1): the
  answer depends on the path;
- the Coulomb block (mu = 0.3) in 5 equal steps keeps its stick and slip
  sets along the path, so the path is linear and its end is the static
  solution (energy 2e-9, the same sets), on 1 and 2 ranks alike;
- frictionless, the block in 3 steps: with a zero gap the problem is
  positively homogeneous, so step k is t times the static solution (energy
  t^2, the same active set).
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from serial_parallel import compare, read, run  # noqa: E402

# the energies of statistics.csv have 10 digits
TOLERANCE = 2e-9

CHECKS = ["feasibility", "multiplier_sign", "complementarity", "residual",
          "resultant", "friction_bound", "stick", "slip"]

UNLOADING = """
subsection Boundary conditions
  subsection Dirichlet 1
    set Function constants  = p=0.1, nu=0.3, tau=0.03, g=0.01
    set Function expression = 2*(1+nu)*tau*(2-2*t)*y + g; -(1-nu*nu)*p*y
  end
  subsection Traction 1
    set Function constants  = p=0.1, tau=0.03
    set Function expression = tau*(2-2*t); -p
  end
  subsection Traction 2
    set Function constants  = tau=0.03
    set Function expression = 0; tau*(2-2*t)
  end
end
subsection Exact solution
  set Function expression = nu*(1+nu)*p*x + g; -(1-nu*nu)*p*y
end
subsection Contact
  set Load steps  = {steps}
  set Load factor = 1
end
"""


def steps(n):
    return f"subsection Contact\n  set Load steps = {n}\nend\n"


def main():
    binary, source, work = sys.argv[1:4]
    runs = os.path.join(source, "tests", "runs")
    strip = os.path.join(runs, "friction_strip.prm")
    strip_3d = os.path.join(runs, "friction_strip_3d.prm")
    block = os.path.join(source, "tests", "inputs", "block.prm")
    shutil.rmtree(work, ignore_errors=True)
    problems = []

    def computed(name, prm, extra, ranks=1):
        """The statistics and load-step rows of a run, checked."""
        directory = os.path.join(work, name)
        run(binary, prm, directory, ranks, extra)
        rows = read(os.path.join(directory, "statistics.csv"))
        path = os.path.join(directory, "load-steps.csv")
        step_rows = read(path) if os.path.exists(path) else []
        for row in rows + step_rows:
            where = f"{name}, cycle {row['cycle']}" + \
                (f", step {row['step']}" if "step" in row else "")
            if row["converged"] != "1":
                problems.append(f"{where}: not converged")
            for check in CHECKS:
                if check in row and not float(row[check]) <= 1e-10:
                    problems.append(f"{where}: {check} {row[check]}")
        return rows, step_rows

    def expect(condition, text):
        if not condition:
            problems.append(text)

    def exact(name, rows, limit=1e-7):
        for row in rows:
            error = float(row["relative_energy_error"])
            expect(error < limit, f"{name}, cycle {row['cycle']}: relative "
                   f"energy error {error}")

    def scaled_energies(name, rows, step_rows):
        """Step k of N has (k/N)^2 times the energy of the last step."""
        for row in rows:
            cycle = [s for s in step_rows if s["cycle"] == row["cycle"]]
            final = float(row["energy"])
            for s in cycle:
                t = int(s["step"]) / len(cycle)
                expect(abs(float(s["energy"]) - t * t * final)
                       <= TOLERANCE * abs(final),
                       f"{name}, cycle {row['cycle']}, t = {t}: energy "
                       f"{s['energy']}, expected {t * t * final}")
                expect(s["active_nodes"] == row["active_nodes"],
                       f"{name}, cycle {row['cycle']}, t = {t}: "
                       f"{s['active_nodes']} active nodes, "
                       f"{row['active_nodes']} at the end")

    # proportional full slip, 2D and 3D
    for name, prm, n in [("slip", strip, 4), ("slip-3d", strip_3d, 3)]:
        rows, step_rows = computed(name, prm, steps(n))
        exact(name, rows)
        scaled_energies(name, rows, step_rows)
        expect(len(step_rows) == n * len(rows),
               f"{name}: {len(step_rows)} step rows")
        for s in step_rows:
            expect(s["slip_nodes"] == s["contact_nodes"],
                   f"{name}, cycle {s['cycle']}, step {s['step']}: "
                   f"{s['slip_nodes']} of {s['contact_nodes']} slide")
        print(f"{name}: {n} steps, relative energy error "
              f"{[r['relative_energy_error'] for r in rows]}")

    def accumulated_slip(name):
        """Every node of the strip in contact has slid by the exact slip
        exx x + g in all (contact-00.csv: the end of the path)."""
        for n in read(os.path.join(work, name, "contact-00.csv")):
            if n["multiplier_node"] != "1":
                continue
            x = float(n["x"])
            exact_slip = 0.3 * 1.3 * 0.1 * x + 0.01
            expect(abs(float(n["accumulated_slip_x"]) - exact_slip) <= 1e-9,
                   f"{name}, x = {x}: accumulated slip "
                   f"{n['accumulated_slip_x']}, exact {exact_slip}")

    accumulated_slip("slip")

    # unloading: all stick, exact (by both friction solvers), having slid
    # in the first step only; the static problem differs
    fixed_point = "subsection Contact\n  set Friction solver = fixed point\nend\n"
    for name, extra in [("unloading", ""),
                        ("unloading-fixed-point", fixed_point)]:
        rows, step_rows = computed(name, strip,
                                   UNLOADING.format(steps=2) + extra)
        exact(name, rows)
        for s in step_rows:
            status = "slip_nodes" if s["step"] == "1" else "stick_nodes"
            expect(s[status] == s["contact_nodes"],
                   f"{name}, cycle {s['cycle']}, step {s['step']}: "
                   f"{s[status]} of {s['contact_nodes']} {status}")
        for r in rows:
            expect(float(r["tangential_force"]) <= 1e-12,
                   f"{name}, cycle {r['cycle']}: tangential force "
                   f"{r['tangential_force']}")
        accumulated_slip(name)
    static, _ = computed("unloading-static", strip,
                         UNLOADING.format(steps=1))
    for r in static:
        expect(float(r["relative_energy_error"]) > 0.1,
               f"unloading in one step, cycle {r['cycle']}: relative error "
               f"{r['relative_energy_error']} (the path should matter)")
    print(f"unloading: stick {[s['stick_nodes'] for s in step_rows]}, "
          f"relative energy error {[r['relative_energy_error'] for r in rows]}"
          f"; in one step {[r['relative_energy_error'] for r in static]}")

    # the Coulomb block: sets unchanged along the path, its end is static
    coulomb = ("set Number of cycles = 3\n"
               "subsection Error estimator\n  set Enable = false\nend\n"
               "subsection Linear solver\n"
               "  set Relative tolerance = 1e-13\nend\n"
               "subsection Contact\n  set Condition = pointwise\n"
               "  set Friction = Coulomb\n"
               "  set Friction coefficient = 0.3\nend\n")
    one_step, _ = computed("block-static", block, coulomb)
    path, step_rows = computed("block-steps", block, coulomb + steps(5))
    computed("block-steps-np2", block, coulomb + steps(5), 2)
    problems.extend(f"block in 5 steps, 1 vs 2 ranks: {p}" for p in
                    compare(os.path.join(work, "block-steps"),
                            os.path.join(work, "block-steps-np2")))
    for a, b in zip(one_step, path):
        expect(abs(float(a["energy"]) - float(b["energy"]))
               <= TOLERANCE * abs(float(a["energy"])),
               f"block, cycle {a['cycle']}: energy {b['energy']} in 5 "
               f"steps, {a['energy']} in one")
        for key in ["stick_nodes", "slip_nodes", "active_nodes"]:
            expect(a[key] == b[key], f"block, cycle {a['cycle']}: {key} "
                   f"{b[key]} in 5 steps, {a[key]} in one")
    for s in step_rows:
        end = path[int(s["cycle"])]
        for key in ["stick_nodes", "slip_nodes"]:
            expect(s[key] == end[key], f"block, cycle {s['cycle']}, step "
                   f"{s['step']}: {key} {s[key]}, {end[key]} at the end")
    print(f"Coulomb block: energies {[r['energy'] for r in path]} in 5 "
          f"steps, {[r['energy'] for r in one_step]} in one")

    # frictionless: homogeneous in the load
    rows, step_rows = computed("frictionless", block,
                               "set Number of cycles = 2\n" + steps(3))
    scaled_energies("frictionless", rows, step_rows)

    for p in problems:
        print("  " + p)
    print("FAILED" if problems else "load path: exact proportional slip "
          "(2D, 3D) and unloading, path dependence, Coulomb block and "
          "frictionless block against their static solutions")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
