#!/usr/bin/env python3
"""The paper's Figure 3 for our block: eps (estimate) and eps_ex (exact error
against a reference two levels finer than the finest mesh) under uniform
refinement, for both contact conditions and both stress reconstructions
(star patch, the default, and the paper's element equilibration), against
the number of elements in contact (elements with an edge on the contact
zone GC).

Writes doc/convergence-study.csv and, if matplotlib is available,
doc/convergence-study.png, and prints the fitted log-log slopes.

Usage: bench/convergence_study.py [--meshes 5] [--build build]
"""
import argparse
import csv
import math
import os
import subprocess
import tempfile

RECONSTRUCTIONS = ("star patch", "element equilibration")
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(xs)
    mx, my = sum(lx) / n, sum(ly) / n
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / \
        sum((a - mx) ** 2 for a in lx)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", type=int, default=5)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = parser.parse_args()
    rows = []
    for condition, reconstruction in [(c, r) for c in ("integral", "pointwise")
                                      for r in RECONSTRUCTIONS]:
        with tempfile.TemporaryDirectory() as work:
            prm = os.path.join(work, "study.prm")
            with open(os.path.join(ROOT, "prm", "block.prm")) as f:
                text = f.read()
            text += f"""
set Output directory = {work}/out
set Number of cycles = {args.meshes}
subsection Contact
  set Condition = {condition}
end
subsection Error estimator
  set Stress reconstruction = {reconstruction}
end
subsection Reference solution
  set Extra refinements = 2
end
subsection Output
  set Write vtu = false
end
"""
            with open(prm, "w") as f:
                f.write(text)
            subprocess.run([os.path.join(args.build, "signorini"), prm],
                           check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(work, "out", "statistics.csv")) as f:
                for r in csv.DictReader(f):
                    rows.append({"reconstruction": reconstruction})
                    rows[-1].update({k: r[k] for k in (
                        "condition", "cells", "dofs", "contact_cells",
                        "active_nodes", "eps", "eps_ex", "effectivity",
                        "eps_contact", "prager_synge_ratio")})
    out_csv = os.path.join(ROOT, "doc", "convergence-study.csv")
    with open(out_csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {out_csv}")

    fits = {}
    for condition in ("integral", "pointwise"):
        for reconstruction in RECONSTRUCTIONS:
            rs = [r for r in rows if r["condition"] == condition
                  and r["reconstruction"] == reconstruction]
            n = [float(r["contact_cells"]) for r in rs]
            for key in ("eps", "eps_ex"):
                fits[(condition, reconstruction, key)] = slope(
                    n, [float(r[key]) for r in rs])
                print(f"{condition:9s} {reconstruction:21s} {key:6s} slope "
                      f"{fits[(condition, reconstruction, key)]:.2f}")
            print(f"{condition:9s} {reconstruction:21s} effectivity " +
                  ", ".join(f"{float(r['effectivity']):.2f}" for r in rs))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no plot")
        return
    fig, ax = plt.subplots(figsize=(6.5, 5))
    styles = {"integral": "o", "pointwise": "s"}
    for condition in ("integral", "pointwise"):
        for reconstruction, line in zip(RECONSTRUCTIONS, ("-", "-.")):
            rs = [r for r in rows if r["condition"] == condition
                  and r["reconstruction"] == reconstruction]
            n = [float(r["contact_cells"]) for r in rs]
            ax.loglog(n, [100 * float(r["eps"]) for r in rs],
                      line + styles[condition], fillstyle="none",
                      label=f"{condition}: eps, {reconstruction}, slope "
                      f"{fits[(condition, reconstruction, 'eps')]:.2f}")
        ax.loglog(n, [100 * float(r["eps_ex"]) for r in rs],
                  "--" + styles[condition],
                  label=f"{condition}: eps_ex (exact), slope "
                  f"{fits[(condition, RECONSTRUCTIONS[0], 'eps_ex')]:.2f}")
    ax.set_xlabel("elements in contact (edge on GC)")
    ax.set_ylabel("relative error (%)")
    ax.set_title("Block: estimated and exact error, uniform refinement")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    out_png = os.path.join(ROOT, "doc", "convergence-study.png")
    fig.savefig(out_png, dpi=120)
    print(f"wrote {out_png}")


if __name__ == "__main__":
    main()
