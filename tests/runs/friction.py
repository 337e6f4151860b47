#!/usr/bin/env python3
"""Friction (Contact/Friction) against exact and independent solutions.

Usage: friction.py SIGNORINI_BINARY SOURCE_DIR WORK_DIRECTORY [CONDITION]

CONDITION (Contact/Condition, pointwise by default) is that of every run
below, the integral one's friction law acting on the nodal values of the
tangential traction and the weighted slips. With it the exact Tresca full
slip is approached at the rate h (relative energy error below 1e-2,
halved by each refinement) instead of reproduced: the held corner node
carries no multiplier, and the nodal values next to it, which exceed the
exact traction to make up its share, are cut by the bound. For the
suite's time the pointwise run checks the solver in full and the estimate
on 1 rank without adaptation, the integral run the estimate in full and
the blocks' solves on 1 and 2 ranks (2D) and 1 (3D), without the fixed
point on 3 ranks and on the 3D block.

On the strip of tests/runs/friction_strip.prm (and the 3D block of
friction_strip_3d.prm, sliding obliquely) (pressure p = 0.1 and shear
tau on top, plane strain, nu = 0.3, the left side carrying the exact
displacement), every cycle must converge with the friction checks at
round-off and
- full slip (Coulomb mu = 0.3 or Tresca s = 0.03, tau = mu p): every node in
  contact slides, and the exact affine solution is reproduced (relative
  energy-norm error below 1e-7: the error's own round-off is about 5e-9);
- full stick (tau = 0.02 < mu p, the lateral stress -nu p / (1 - nu) that
  keeps the bottom from stretching): every node sticks, same accuracy;
- bonded (tau = 0.06 > mu p with mu = 1e6): the solution of the strip glued
  to the foundation, computed without friction (Dirichlet data on the
  bottom): same energy (1e-10), same exact solution.
On the paper's block (prm/block.prm, the chosen condition) mu = 0 gives the
frictionless energies, contact forces and active sets (1e-12), and the
Coulomb block (mu = 0.3) has sticking and sliding nodes and gives the same
results on 1, 2 and 3 ranks (tests/runs/serial_parallel.py); so does the 3D
block (prm/block-3d.prm, one cycle) on 1 and 2. The second route (Friction
solver = fixed point: the fixed point on the Tresca threshold mu y) gives
the exact full-slip solutions in 2D and 3D, and on both blocks the same
stick and slip sets, energies and forces as the semismooth Newton method
(2e-9, the digits of statistics.csv), with a contraction in (0, 1), and
the same results on 1 and 3 ranks (2D block). The contraction of the fixed
point at the solution (Contact/Uniqueness check) is in (0, 1) on the
full-slip strip, proportional to mu there (mu = 0.3 and 1, tau = mu p; on
the unrefined strip with as many steps as sliding nodes, where the estimate
is exact; the default 2 steps' estimate, rougher, decides alike; at mu =
2.2 the default takes at least 6 steps and gives the rate of 50 steps
within 5 %), and the same from both routes (2D and 3D strips). The error estimate with
friction: mu = 0 gives the frictionless estimate, the Coulomb block a
bound with effectivity in [1, 1.3] against a reference two levels finer (1
and 2 ranks alike), also at mu = 1000 where every node in contact sticks
([1, 1.5] with the pointwise condition), and prm/block-adaptive.prm with
mu = 0.3 reaches 2 % in at most three computations.
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from serial_parallel import compare, read, run  # noqa: E402

CHECKS = ["feasibility", "multiplier_sign", "complementarity", "residual",
          "resultant", "friction_bound", "stick", "slip"]

STICK = """
subsection Boundary conditions
  subsection Dirichlet 1
    set Function constants  = p=0.1, nu=0.3, tau={tau}
    set Function expression = 2*(1+nu)*tau*y; -p*(1+nu)*(1-2*nu)/(1-nu)*y
  end
  subsection Traction 1
    set Function constants  = p=0.1, tau={tau}
  end
  subsection Traction 2
    set Function constants  = p=0.1, nu=0.3, tau={tau}
    set Function expression = -nu*p/(1-nu); tau
  end
end
subsection Exact solution
  set Function constants  = p=0.1, nu=0.3, tau={tau}
  set Function expression = 2*(1+nu)*tau*y; -p*(1+nu)*(1-2*nu)/(1-nu)*y
end
"""

SLIP = """
subsection Boundary conditions
  subsection Dirichlet 1
    set Function constants  = p=0.1, nu=0.3, tau={tau}, g=0.01
  end
  subsection Traction 1
    set Function constants  = p=0.1, tau={tau}
  end
  subsection Traction 2
    set Function constants  = tau={tau}
  end
end
subsection Exact solution
  set Function constants  = p=0.1, nu=0.3, tau={tau}, g=0.01
end
subsection Contact
  set Friction coefficient = {mu}
end
"""

TRESCA = """
subsection Contact
  set Friction = Tresca
  subsection Friction threshold
    set Function expression = 0.03
  end
end
"""


def contact(lines):
    return "subsection Contact\n" + lines + "end\n"


def estimate(binary, source, block, base, rows_of, on_one_and_two_ranks,
             problems, full, condition):
    """The error in constitutive relation with friction: mu = 0 gives the
    frictionless estimate (1e-12), the Coulomb (mu = 0.3) and Tresca blocks
    a bound of the error against a reference two levels finer (effectivity
    in [1, 1.3], ||U_ref - U^|| <= e), the same on 2 ranks, and the adapted
    Coulomb block reaches eps = 2 % in at most three computations. At mu =
    1000 (every node in contact sticks) the bound stays sharp: effectivity
    in [1, 1.3] with the integral condition, [1, 1.5] with the pointwise one
    (whose R^_n = M^-1 f reaches into the separated part; both were 2.3 to
    3.8 before U^ took less slip there). Without FULL (the suite's time): on
    1 rank, and not adapted."""
    estimator = ("subsection Error estimator\n  set Enable = true\nend\n"
                 "set Number of cycles = 2\n")
    none = rows_of("estimate-none", block, base + estimator)
    zero = rows_of("estimate-mu0", block, base + estimator + contact(
        "  set Friction = Coulomb\n  set Friction coefficient = 0\n"))
    for a, b in zip(none, zero):
        for key in ["eps", "e", "eps_contact"]:
            x, y = float(a[key]), float(b[key])
            if not abs(x - y) <= 1e-12 * abs(x):
                problems.append(f"estimate, mu = 0, cycle {a['cycle']}: "
                                f"{key} {y}, frictionless {x}")
    # a gap not linear along GC on a load path: the contact term, of the
    # foundation interpolated between the nodes, is >= 0 (with g itself it
    # came out negative: -0.10 % of e^2 on the second mesh)
    wavy = rows_of("estimate-wavy-gap", block, base + estimator + contact(
        "  set Friction = Coulomb\n  set Friction coefficient = 1\n"
        "  set Load steps = 3\n  subsection Gap\n"
        "    set Function expression = 0.002*sin(10*x)+0.002\n  end\n"))
    for row in wavy:
        if not float(row["eps_contact"]) >= 0.:
            problems.append(f"estimate, wavy gap, cycle {row['cycle']}: "
                            f"contact share {row['eps_contact']}")
    reference = ("subsection Reference solution\n"
                 "  set Extra refinements = 2\nend\n")
    coulomb = on_one_and_two_ranks(
        "estimate-coulomb", block, base + estimator + reference + contact(
            "  set Friction = Coulomb\n  set Friction coefficient = 0.3\n"),
        (2,) if full else ())
    # (Tresca: the classical law, on every row of GC in contact or not;
    # every node sticks at this threshold)
    tresca = rows_of("estimate-tresca", block, base + estimator + reference
                     + contact("  set Friction = Tresca\n"
                               "  subsection Friction threshold\n"
                               "    set Function expression = 0.05\n"
                               "  end\n"))
    sticking = rows_of("estimate-mu1000", block, base + estimator + reference
                       + contact("  set Friction = Coulomb\n"
                                 "  set Friction coefficient = 1000\n"))
    for name, rows, largest in [
            ("Coulomb", coulomb, 1.3), ("Tresca", tresca, 1.3),
            ("Coulomb mu = 1000", sticking,
             1.3 if condition == "integral" else 1.5)]:
        for row in rows:
            where = f"estimate, {name} block, cycle {row['cycle']}"
            effectivity = float(row["effectivity"])
            if not (1. <= effectivity <= largest
                    and float(row["prager_synge_ratio"]) <= 1.
                    and float(row["eps_contact"]) > 0.):
                problems.append(f"{where}: effectivity {effectivity}, "
                                f"Prager-Synge ratio "
                                f"{row['prager_synge_ratio']}, contact "
                                f"share {row['eps_contact']}")
        print(f"estimate, {name} block: eps {[r['eps'] for r in rows]}, "
              f"effectivity {[r['effectivity'] for r in rows]}")
    if not full:
        return
    adaptive = os.path.join(source, "prm", "block-adaptive.prm")
    adapted = rows_of("estimate-adaptive", adaptive, contact(
        "  set Friction = Coulomb\n  set Friction coefficient = 0.3\n"),
        tolerance=1e-8)  # (the example's linear solver tolerance, 1e-10)
    if not any(float(r["eps"]) <= 0.02 for r in adapted[:3]):
        problems.append(f"adapted Coulomb block: eps "
                        f"{[r['eps'] for r in adapted]}")
    print(f"adapted Coulomb block: cells {[r['cells'] for r in adapted]}, "
          f"N* {[r['predicted_cells'] for r in adapted]}, eps "
          f"{[r['eps'] for r in adapted]}")


# no contact: the bottom (GC) glued by Dirichlet data
GLUED = """
subsection Contact
  set Boundary ids =
  set Friction     = none
end
subsection Boundary conditions
  subsection Dirichlet 2
    set Boundary ids        = 2
    set Components          = x, y
    set Function expression = 0; 0
  end
end
"""

def held_by_top(top, expression, extra=""):
    """The block held and moved by the Dirichlet data EXPRESSION on the ids
    TOP only (no clamp, no loads), estimator off, with EXTRA."""
    return ("subsection Boundary conditions\n"
            "  subsection Dirichlet 1\n"
            f"    set Boundary ids        = {top}\n"
            f"    set Function expression = {expression}\n"
            "  end\n"
            "  subsection Traction 1\n    set Boundary ids =\n  end\n"
            "  subsection Traction 2\n    set Boundary ids =\n  end\n"
            "end\n"
            "subsection Error estimator\n  set Enable = false\nend\n" +
            extra)


# pressed, then sheared, by the whole top (CG to 1e-13: at 1e-10 the
# semismooth Newton route may stop where its slip forces no longer shrink,
# below 1e-8 of the problem's forces, and its total tangential force was
# 2.0e-9 from the fixed point's; at 1e-13 both give the same 10 digits)
SHEARED_COULOMB = held_by_top(
    "3, 5", "0.1*max(2*t-1,0); -0.01*min(2*t,1)",
    "set Number of cycles = 1\n"
    "subsection Linear solver\n  set Relative tolerance = 1e-13\nend\n"
    "subsection Mesh\n  set Initial refinements = 1\nend\n"
    "subsection Contact\n"
    "  set Friction             = Coulomb\n"
    "  set Friction coefficient = 0.3\n"
    "  set Load steps           = 2\n"
    "  set Load factor          = 1\n"
    "end\n")


def sheared_by_top(v):
    """Moved by the top's left half to (0.1, V)."""
    return held_by_top("3", f"0.1; {v}",
                       "set Number of cycles = 2\n"
                       "subsection Linear solver\n"
                       "  set Relative tolerance = 1e-13\nend\n")


def sheared(binary, block, rows_of, on_one_and_two_ranks, work, problems):
    """Tresca on the block held and moved by its top only, (0.1, v): the
    classical convex problem, whose friction acts on all of GC in contact
    or not, converges where the law at the nodes in contact only had no
    solution (v = -0.01: a separated node sliding with the body
    penetrated, and pressed, it stuck and was pulled). At threshold 1 every
    node of GC sticks, the separated ones too (no slip in the contact
    table); at 0.05 some slide (the same on 2 ranks); pressed down to v = -0.1, where every node
    is in contact and sticks, the energy is that of the block glued to the
    foundation by Dirichlet data."""
    def tresca(threshold):
        return contact("  set Friction = Tresca\n"
                       "  subsection Friction threshold\n"
                       f"    set Function expression = {threshold}\n"
                       "  end\n")
    held = rows_of("sheared-tresca-1", block,
                   sheared_by_top(-0.01) + tresca(1))
    for row in held:
        if not (row["stick_nodes"] == row["contact_nodes"]
                and int(row["active_nodes"]) < int(row["contact_nodes"])):
            problems.append(f"sheared, threshold 1, cycle {row['cycle']}: "
                            f"{row['stick_nodes']} of {row['contact_nodes']} "
                            f"nodes stick, {row['active_nodes']} in contact")
        table = read(os.path.join(work, "sheared-tresca-1",
                                  f"contact-{int(row['cycle']):02d}.csv"))
        moved = [n for n in table if abs(float(n["slip_x"])) > 1e-12]
        if moved:
            problems.append(f"sheared, threshold 1, cycle {row['cycle']}: "
                            f"{len(moved)} nodes slip")
    sliding = on_one_and_two_ranks("sheared-tresca-0.05", block,
                                   sheared_by_top(-0.01) + tresca(0.05))
    if not all(int(r["slip_nodes"]) > 0 for r in sliding):
        problems.append(f"sheared, threshold 0.05: slip nodes "
                        f"{[r['slip_nodes'] for r in sliding]}")
    pressed = rows_of("sheared-pressed", block,
                      sheared_by_top(-0.1) + tresca(1))
    glued = os.path.join(work, "sheared-glued")
    run(binary, block, glued, 1, sheared_by_top(-0.1) + GLUED)
    for a, b in zip(pressed, read(os.path.join(glued, "statistics.csv"))):
        e1, e2 = float(a["energy"]), float(b["energy"])
        if not (a["stick_nodes"] == a["active_nodes"] == a["contact_nodes"]
                and abs(e1 - e2) <= 1e-10 * abs(e2)):
            problems.append(f"sheared, pressed, cycle {a['cycle']}: energy "
                            f"{e1} against the glued block's {e2}, "
                            f"{a['stick_nodes']} stick, {a['active_nodes']} "
                            f"in contact of {a['contact_nodes']}")
    print(f"sheared block, Tresca: threshold 1 "
          f"{[r['stick_nodes'] for r in held]} stick of "
          f"{[r['contact_nodes'] for r in held]} "
          f"({[r['active_nodes'] for r in held]} in contact), threshold 0.05 "
          f"{[r['slip_nodes'] for r in sliding]} slip; pressed: energies "
          f"{[r['energy'] for r in pressed]}")


def main():
    binary, source, work = sys.argv[1:4]
    condition = sys.argv[4] if len(sys.argv) > 4 else "pointwise"
    chosen = contact(f"  set Condition = {condition}\n")
    strip = os.path.join(source, "tests", "runs", "friction_strip.prm")
    block = os.path.join(source, "tests", "inputs", "block.prm")
    if not os.path.exists(block):
        block = os.path.join(source, "prm", "block.prm")
    shutil.rmtree(work, ignore_errors=True)
    problems = []

    def rows_of(name, prm, extra, ranks=1, tolerance=1e-10):
        directory = os.path.join(work, name)
        run(binary, prm, directory, ranks, extra + chosen)
        rows = read(os.path.join(directory, "statistics.csv"))
        for row in rows:
            where = f"{name}, cycle {row['cycle']}"
            if row["converged"] != "1":
                problems.append(f"{where}: not converged")
            for check in CHECKS:
                if check in row and not float(row[check]) <= tolerance:
                    problems.append(f"{where}: {check} {row[check]}")
        return rows

    def exact(name, rows, status, first_order=False):
        """Every node STATUS and the exact solution reproduced; with
        FIRST_ORDER, approached at the rate h instead (below 1e-2, halved
        by each refinement)."""
        for row in rows:
            where = f"{name}, cycle {row['cycle']}"
            error = float(row["relative_energy_error"])
            if not error < (1e-2 if first_order else 1e-7):
                problems.append(f"{where}: relative energy error {error}")
            if row[status] != row["contact_nodes"]:
                problems.append(f"{where}: {row[status]} of "
                                f"{row['contact_nodes']} nodes {status}")
        errors = [float(r["relative_energy_error"]) for r in rows]
        if first_order and not all(1.8 < a / b < 2.2
                                   for a, b in zip(errors, errors[1:])):
            problems.append(f"{name}: relative energy errors {errors}, not "
                            f"halved by each refinement")
        print(f"{name}: {[r[status] for r in rows]} {status}, relative "
              f"energy error {[r['relative_energy_error'] for r in rows]}")

    exact("slip, Coulomb", rows_of("slip-coulomb", strip, ""), "slip_nodes")
    # the contact table: every node with a multiplier slides by the exact
    # slip exx x + g, under the force -tau times its length
    nodes = read(os.path.join(work, "slip-coulomb", "contact-00.csv"))
    for n in nodes:
        if n["multiplier_node"] != "1":
            continue
        x = float(n["x"])
        length = (0.5 if x in (0., 1.) else 1.) / 16
        exact_slip = 0.3 * 1.3 * 0.1 * x + 0.01
        if n["friction_status"] != "slip" or \
                abs(float(n["slip_x"]) - exact_slip) > 1e-9 or \
                abs(float(n["tangential_force_x"]) + 0.03 * length) > 1e-12:
            problems.append(f"slip, contact-00.csv at x = {x}: "
                            f"{n['friction_status']}, slip {n['slip_x']} "
                            f"(exact {exact_slip}), force "
                            f"{n['tangential_force_x']}")
    # the contraction of the fixed point on the Tresca threshold at the
    # solution: in (0, 1), and, the sets and slip directions being those
    # of every mu (full slip under tau = mu p), proportional to mu; on the
    # unrefined strip with 4 steps (4 sliding nodes: Arnoldi spans them,
    # the rate is exact); in the default steps a rough estimate, which
    # must decide alike
    coarse = ("set Number of cycles = 1\nsubsection Mesh\n"
              "  set Block subdivisions = 2, 3\n"
              "  set Initial refinements = 0\nend\n")
    spanning = "subsection Contact\n  set Uniqueness check steps = 4\nend\n"
    rates = []
    for tau, mu in [(0.03, 0.3), (0.1, 1)]:
        rows = rows_of(f"slip-coarse-mu{mu}", strip,
                       coarse + SLIP.format(tau=tau, mu=mu) + spanning,
                       tolerance=1e-8)
        exact(f"slip, Coulomb, unrefined, mu = {mu}", rows, "slip_nodes")
        rates.append(float(rows[0]["contraction_at_solution"]))
        if rows[0]["contraction_steps"] != "4":
            problems.append(f"slip, unrefined, mu = {mu}: "
                            f"{rows[0]['contraction_steps']} Arnoldi steps")
    if not (0. < rates[0] < 1. and
            abs(rates[1] / rates[0] - 1. / 0.3) < 1e-6 / 0.3):
        problems.append(f"slip, unrefined: contraction at the solution "
                        f"{rates[0]} (mu = 0.3), {rates[1]} (mu = 1)")
    row = rows_of("slip-coarse-default-steps", strip,
                  coarse + SLIP.format(tau=0.03, mu=0.3), tolerance=1e-8)[0]
    rough = float(row["contraction_at_solution"])
    if not (0. < rough < 1. and 2 <= int(row["contraction_steps"]) <= 4):
        problems.append(f"slip, unrefined: contraction at the solution "
                        f"{rough} in {row['contraction_steps']} (default) "
                        f"steps, {rates[0]} exact")
    print(f"slip, unrefined: contraction at the solution {rates} "
          f"(mu = 0.3, 1), {rough} (mu = 0.3, default steps)")
    # a rate above 1/2 takes at least 6 steps, where the first Ritz values
    # may hold still away from it (2 steps gave 0.886 for 0.734 with the
    # integral condition): the full-slip strip at mu = 2.2, one cycle, at
    # the default and with 50 steps (the integral condition's friction
    # checks end near 5e-7 there, within Contact/Check tolerance)
    near = []
    for steps in ["", "subsection Contact\n"
                      "  set Uniqueness check steps = 50\nend\n"]:
        row = rows_of(f"slip-mu2.2-{len(near)}", strip,
                      "set Number of cycles = 1\n" +
                      SLIP.format(tau=0.22, mu=2.2) + steps,
                      tolerance=1e-6)[0]
        near.append((float(row["contraction_at_solution"]),
                     int(row["contraction_steps"])))
    if not (near[0][1] >= 6 and
            abs(near[0][0] - near[1][0]) <= 0.05 * near[1][0]):
        problems.append(f"slip, mu = 2.2: contraction at the solution "
                        f"(rate, steps) {near[0]} at the default, {near[1]} "
                        f"with 50 steps")
    print(f"slip, mu = 2.2: contraction at the solution (rate, steps) "
          f"{near[0]} at the default, {near[1]} with 50 steps")
    strip_3d = os.path.join(source, "tests", "runs", "friction_strip_3d.prm")
    exact("3D slip, Coulomb", rows_of("slip-3d-coulomb", strip_3d, ""),
          "slip_nodes")
    # (the integral condition's Tresca law bounds the nodal values of the
    # traction, of which the held corner has none: next to it they exceed
    # the exact traction, and the bound there makes the discrete solution
    # differ from the affine one by O(h); Coulomb's bound, mu times the
    # normal values, follows them)
    inexact = (condition == "integral")
    exact("3D slip, Tresca", rows_of("slip-3d-tresca", strip_3d, TRESCA),
          "slip_nodes", inexact)
    exact("slip, Tresca", rows_of("slip-tresca", strip, TRESCA), "slip_nodes",
          inexact)
    stick = STICK.format(tau=0.02)
    exact("stick, Coulomb", rows_of("stick-coulomb", strip, stick),
          "stick_nodes")
    exact("stick, Tresca", rows_of("stick-tresca", strip, stick + TRESCA),
          "stick_nodes")

    # bonded: mu = 1e6 against the strip glued by Dirichlet data
    bonded = STICK.format(tau=0.06)
    glued = bonded + GLUED
    large = rows_of("bonded-mu", strip,
                    bonded + contact("  set Friction coefficient = 1e6\n"))
    exact("bonded, mu = 1e6", large, "stick_nodes")
    reference = read(os.path.join(work, "bonded-glued", "statistics.csv")) \
        if run(binary, strip, os.path.join(work, "bonded-glued"), 1, glued) \
        is None else []
    for a, b in zip(large, reference):
        e1, e2 = float(a["energy"]), float(b["energy"])
        if abs(e1 - e2) > 1e-10 * abs(e2):
            problems.append(f"bonded, cycle {a['cycle']}: energy {e1} "
                            f"against the glued strip's {e2}")
    print(f"bonded: energies {[r['energy'] for r in large]}, glued "
          f"{[r['energy'] for r in reference]}")

    # mu = 0 is frictionless
    pointwise = ("set Number of cycles = 3\n"
                 "subsection Error estimator\n  set Enable = false\nend\n"
                 "subsection Linear solver\n"
                 "  set Relative tolerance = 1e-13\nend\n"
                 + chosen)
    none = rows_of("block-none", block, pointwise)
    zero = rows_of("block-mu0", block, pointwise + contact(
        "  set Friction = Coulomb\n  set Friction coefficient = 0\n"))
    for a, b in zip(none, zero):
        for key in ["energy", "contact_force"]:
            x, y = float(a[key]), float(b[key])
            if abs(x - y) > 1e-12 * abs(x):
                problems.append(f"mu = 0, cycle {a['cycle']}: {key} {y}, "
                                f"frictionless {x}")
        if a["active_nodes"] != b["active_nodes"]:
            problems.append(f"mu = 0, cycle {a['cycle']}: active nodes "
                            f"{b['active_nodes']}, frictionless "
                            f"{a['active_nodes']}")
        if abs(float(b["tangential_force"])) > \
                1e-12 * abs(float(b["contact_force"])):
            problems.append(f"mu = 0, cycle {a['cycle']}: tangential force "
                            f"{b['tangential_force']}")
    print(f"mu = 0: energies {[r['energy'] for r in zero]}, frictionless "
          f"{[r['energy'] for r in none]}")

    def on_one_and_two_ranks(name, prm, extra, ranks=(2,)):
        """The rows of PRM + EXTRA on 1 rank, checked against RANKS."""
        label = name.replace("-", " ")
        one = rows_of(name, prm, extra)
        for n in ranks:
            other = rows_of(f"{name}-np{n}", prm, extra, n)
            problems.extend(f"{label}, 1 vs {n} ranks: {p}" for p in
                            compare(os.path.join(work, name),
                                    os.path.join(work, f"{name}-np{n}")))
            for a, b in zip(one, other):
                for key in ["stick_nodes", "slip_nodes"]:
                    if a[key] != b[key]:
                        problems.append(f"{label}, cycle {a['cycle']}: {key} "
                                        f"{a[key]} on 1 rank, {b[key]} on "
                                        f"{n}")
        print(f"{label}: stick {[r['stick_nodes'] for r in one]}, slip "
              f"{[r['slip_nodes'] for r in one]}, energy "
              f"{[r['energy'] for r in one]}")
        return one

    sheared(binary, block, rows_of, on_one_and_two_ranks, work, problems)

    # the friction checks are relative to the forces carried, not to the
    # bounds: a Tresca threshold that is never reached (every node of the
    # right half sticks) may be 1e3 or 1e300 without changing them (relative
    # to 1e300 they were 1e-312, whatever the left half did)
    unreached = {}
    for big in ["1e3", "1e300"]:
        unreached[big] = rows_of(f"tresca-unreached-{big}", block, contact(
            "  set Friction = Tresca\n"
            "  subsection Friction threshold\n"
            f"    set Function expression = x>0.5?{big}:0\n"
            "  end\n") + "set Number of cycles = 1\n"
            "subsection Error estimator\n  set Enable = false\nend\n",
            tolerance=1e-8)  # (near 1e-10 with the integral condition)
    for key in ["friction_bound", "slip"]:
        x, y = (float(unreached[big][0][key]) for big in ["1e3", "1e300"])
        if not abs(x - y) <= 1e-6 * abs(x):
            problems.append(f"Tresca threshold 1e3 or 1e300 where not "
                            f"reached: {key} {x} against {y}")
    print(f"Tresca threshold not reached: friction_bound "
          f"{[r[0]['friction_bound'] for r in unreached.values()]}")

    # the Coulomb block in 2D and 3D on 1 and 2 ranks
    coulomb = pointwise + contact(
        "  set Friction = Coulomb\n  set Friction coefficient = 0.3\n")
    # (the integral condition's test checks its estimate in full and its
    # solver on fewer ranks and meshes, the pointwise one the reverse: the
    # suite's time)
    full = (condition == "pointwise")
    one = on_one_and_two_ranks("block-coulomb", block, coulomb,
                               (2, 3) if full else (2,))
    if not any(int(r["stick_nodes"]) > 0 and int(r["slip_nodes"]) > 0
               for r in one):
        problems.append("Coulomb block: no cycle with both sticking and "
                        "sliding nodes")
    block_3d = os.path.join(source, "prm", "block-3d.prm")
    one_3d = on_one_and_two_ranks("block-3d-coulomb", block_3d,
                         coulomb.replace("set Number of cycles = 3",
                                         "set Number of cycles = 1"),
                         (2,) if full else ())

    # the second route, the fixed point on the Tresca threshold: the same
    # solutions (exact on the strip; on the blocks the same sets and, to
    # the digits of statistics.csv, the same energies and forces)
    fixed_point = contact("  set Friction solver = fixed point\n")
    exact("slip, Coulomb, fixed point",
          rows_of("slip-fixed-point", strip, fixed_point), "slip_nodes")
    exact("3D slip, Coulomb, fixed point",
          rows_of("slip-3d-fixed-point", strip_3d, fixed_point),
          "slip_nodes")
    # (both routes judge uniqueness alike: the rate from solves to 1e-8)
    for newton, other in [("slip-coulomb", "slip-fixed-point"),
                          ("slip-3d-coulomb", "slip-3d-fixed-point")]:
        for a, b in zip(*(read(os.path.join(work, d, "statistics.csv"))
                          for d in (newton, other))):
            x, y = (float(r["contraction_at_solution"]) for r in (a, b))
            if not abs(x - y) <= 1e-4 * x:
                problems.append(f"{newton}, cycle {a['cycle']}: contraction "
                                f"at the solution {x}, {y} by the fixed point")
    # (on 1 and 3 ranks alike, its Tresca solves and iterations too)
    if full:
        on_one_and_two_ranks("block-coulomb-fixed-point", block,
                             coulomb + fixed_point, (3,))
    # the block pressed, then sheared, by its top (no clamp): the fixed
    # point's Tresca problems act on all of GC, with the bound 0 where the
    # previous iterate separated (with the law at the rows in contact only,
    # its second Tresca problem did not converge)
    # (the integral condition's friction checks end near 1e-9 there, within
    # Contact/Check tolerance)
    sheared_newton = rows_of("sheared-coulomb", block, SHEARED_COULOMB,
                             tolerance=1e-8)
    blocks = [("sheared block", block, SHEARED_COULOMB, sheared_newton),
              ("block", block, coulomb, one),
              ("3D block", block_3d,
               coulomb.replace("set Number of cycles = 3",
                               "set Number of cycles = 1"), one_3d)]
    for name, prm, extra, newton in blocks[:3 if full else 2]:
        # (its Tresca problems stop at 1e-12 of the largest force, not at
        # round-off, where the rank count decided: in 3D the slip
        # directions are then within 1e-8 of the bounds)
        other = rows_of(name.replace(" ", "-") + "-fixed-point", prm,
                        extra + fixed_point, tolerance=1e-8)
        for a, b in zip(newton, other):
            for key in ["energy", "contact_force", "tangential_force"]:
                x, y = float(a[key]), float(b[key])
                if abs(x - y) > 2e-9 * abs(x):
                    problems.append(f"{name}, cycle {a['cycle']}: {key} {y} "
                                    f"by the fixed point, {x} by Newton")
            for key in ["stick_nodes", "slip_nodes"]:
                if a[key] != b[key]:
                    problems.append(f"{name}, cycle {a['cycle']}: {key} "
                                    f"{b[key]} by the fixed point, {a[key]} "
                                    f"by Newton")
            # (on the sheared block the changes first grow, by 2.1 with the
            # integral condition: there only the rate at the solution)
            rate = ("contraction_at_solution" if name == "sheared block"
                    else "contraction")
            if not 0. < float(b[rate]) < 1.:
                problems.append(f"{name}, cycle {a['cycle']}: {rate} "
                                f"{b[rate]}")
        print(f"{name}, fixed point: energy {[r['energy'] for r in other]}, "
              f"Tresca solves {[r['tresca_solves'] for r in other]}, "
              f"contraction {[r['contraction'] for r in other]}")

    estimate(binary, source, block, pointwise, rows_of, on_one_and_two_ranks,
             problems, not full, condition)

    for p in problems:
        print("  " + p)
    print("FAILED" if problems else "friction: exact slip, stick and bonded "
          "solutions, mu = 0 frictionless, 1, 2 and 3 ranks identical, the "
          "fixed point on the Tresca threshold agrees")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
