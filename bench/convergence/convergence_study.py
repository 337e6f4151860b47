#!/usr/bin/env python3
"""The paper's Figure 3 for our block, and the same study on the manufactured
solution: eps (estimate) and the exact error under uniform refinement, for
the four stress reconstructions side by side:

  EE enh+JM      element equilibration, enhanced traction densities,
                 Johnson-Mercier exactly equilibrated element fields (the
                 default; a guaranteed upper bound)
  EE enh+disp    element equilibration, enhanced traction densities,
                 element stress from the displacement
  EET LS+disp    the paper's classical EET: least-squares traction
                 densities, element stress from the displacement
  star patch     star-patch reconstruction

Studies:
  block integral / block pointwise   prm/block.prm with both contact
      conditions; eps_ex is the exact error against a reference two levels
      finer than the finest mesh, plotted against the number of elements in
      contact (elements with an edge on the contact zone GC), as in the paper;
  manufactured   prm/manufactured.prm (pure elasticity, exact solution
      known): effectivity = e / energy_error (both absolute; the program's
      eps and relative_energy_error are normalised differently).

Writes a CSV (default bench/convergence/convergence-study.csv) and, if
matplotlib is available, a plot (default doc/convergence-study.png): left,
eps of every reconstruction and eps_ex against the elements in contact
(block); right, the effectivity of every reconstruction and study against
the cells.
Prints markdown tables (one per study: rows = meshes; eps_ex, and per
reconstruction eps and effectivity; the effectivity spread max - min and
the fitted log-log slopes) and, with --tables, writes them to a file.

Usage: bench/convergence/convergence_study.py [--meshes 5] [--build build]
           [--csv bench/convergence/convergence-study.csv]
           [--png doc/convergence-study.png]
           [--tables FILE] [--reconstructions all|LIST]
           [--studies all|LIST] [--jobs 1]
"""
import argparse
import concurrent.futures
import csv
import math
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import ROOT  # noqa: E402

# name -> entries of subsection Error estimator
RECONSTRUCTIONS = {
    "EE enh+JM": """  set Stress reconstruction = element equilibration
  subsection Element equilibration
    set Traction densities = enhanced
    set Element stress     = equilibrated
  end
""",
    "EE enh+disp": """  set Stress reconstruction = element equilibration
  subsection Element equilibration
    set Traction densities = enhanced
    set Element stress     = displacement
  end
""",
    "EET LS+disp": """  set Stress reconstruction = element equilibration
  subsection Element equilibration
    set Traction densities = least squares
    set Element stress     = displacement
  end
""",
    "star patch": """  set Stress reconstruction = star patch
""",
}
DEFAULT_RECONSTRUCTION = "EE enh+JM"

# name -> (parameter file, contact condition or None, reference?)
STUDIES = {
    "block integral": ("block.prm", "integral", True),
    "block pointwise": ("block.prm", "pointwise", True),
    "manufactured": ("manufactured.prm", None, False),
}

KEEP = ("cells", "dofs", "contact_cells", "active_nodes", "e", "eps",
        "eps_contact", "estimate_seconds", "equilibrium_defect")


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(xs)
    mx, my = sum(lx) / n, sum(ly) / n
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / \
        sum((a - mx) ** 2 for a in lx)


def run_one(build, meshes, study, reconstruction):
    """Run one (study, reconstruction); return (rows, wall seconds)."""
    prm_name, condition, reference = STUDIES[study]
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(ROOT, "prm", prm_name)) as f:
            text = f.read()
        text += f"""
set Output directory = {work}/out
set Number of cycles = {meshes}
subsection Error estimator
{RECONSTRUCTIONS[reconstruction]}end
subsection Output
  set Write vtu = false
end
"""
        if condition is not None:
            text += f"""subsection Contact
  set Condition = {condition}
end
"""
        if reference:
            text += """subsection Reference solution
  set Extra refinements = 2
end
"""
        prm = os.path.join(work, "study.prm")
        with open(prm, "w") as f:
            f.write(text)
        seconds = runner.run_timed([runner.executable(build), prm])
        rows = []
        with open(os.path.join(work, "out", "statistics.csv")) as f:
            for r in csv.DictReader(f):
                row = {"study": study, "reconstruction": reconstruction,
                       "condition": condition or "-"}
                row.update({k: r[k] for k in KEEP})
                if reference:
                    row["eps_ex"] = r["eps_ex"]
                    row["energy_error"] = ""
                    row["effectivity"] = r["effectivity"]
                    row["prager_synge_ratio"] = r["prager_synge_ratio"]
                else:
                    row["eps_ex"] = ""
                    row["energy_error"] = r["energy_error"]
                    row["effectivity"] = repr(float(r["e"]) /
                                              float(r["energy_error"]))
                    row["prager_synge_ratio"] = ""
                row["run_seconds"] = f"{seconds:.2f}"
                rows.append(row)
    return rows, seconds


def select(rows, study, reconstruction):
    return [r for r in rows if r["study"] == study
            and r["reconstruction"] == reconstruction]


def markdown_table(rows, study, reconstructions):
    """One study: rows = meshes, eps_ex (or energy_error) and per
    reconstruction eps (or e) and effectivity; then the slopes and the
    effectivity spreads."""
    manufactured = not STUDIES[study][2]
    per = {rc: select(rows, study, rc) for rc in reconstructions}
    base = per[reconstructions[0]]
    if manufactured:
        x_key, x_name = "cells", "cells"
        ex_key, ex_name, est_key, est_name = \
            "energy_error", "energy_error", "e", "e"
        fmt = "{:.4g}"
    else:
        x_key, x_name = "contact_cells", "elements in contact"
        ex_key, ex_name, est_key, est_name = "eps_ex", "eps_ex %", "eps", \
            "eps %"
        fmt = "{:.3f}"

    def value(r, key):
        v = float(r[key])
        return fmt.format(100 * v if key in ("eps", "eps_ex") else v)

    head = ["cells", "contact"] if not manufactured else ["cells"]
    head += [ex_name]
    for rc in reconstructions:
        head += [f"{rc}: {est_name}", f"{rc}: eff"]
    lines = [f"### {study} (uniform refinement"
             + ("" if manufactured else
                ", reference 2 levels finer than the finest")
             + "; effectivity = "
             + ("e / energy_error" if manufactured else "eps / eps_ex")
             + ")", "",
             "| " + " | ".join(head) + " |",
             "|" + "|".join("---:" for _ in head) + "|"]
    for i, b in enumerate(base):
        cells = [b["cells"]] + ([] if manufactured else [b["contact_cells"]])
        cells.append(value(b, ex_key))
        for rc in reconstructions:
            r = per[rc][i]
            assert r["cells"] == b["cells"]
            if not manufactured:
                # the reference and exact error do not depend on the estimator
                assert abs(float(r["eps_ex"]) / float(b["eps_ex"]) - 1) \
                    < 1e-6, (study, rc, i)
            cells += [value(r, est_key), f"{float(r['effectivity']):.3f}"]
        lines.append("| " + " | ".join(cells) + " |")
    # slopes against x (contact cells for the block, cells for manufactured)
    xs = [float(b[x_key]) for b in base]
    sl = ["slope vs " + x_name] + ([""] if not manufactured else [])
    sl.append(f"{slope(xs, [float(b[ex_key]) for b in base]):.2f}")
    for rc in reconstructions:
        sl += [f"{slope(xs, [float(r[est_key]) for r in per[rc]]):.2f}", ""]
    lines.append("| " + " | ".join(sl) + " |")
    sp = ["eff spread (max-min)"] + ([""] if not manufactured else []) + [""]
    for rc in reconstructions:
        eff = [float(r["effectivity"]) for r in per[rc]]
        sp += ["", f"{max(eff) - min(eff):.3f}"]
    lines.append("| " + " | ".join(sp) + " |")
    mn = ["eff min / max"] + ([""] if not manufactured else []) + [""]
    for rc in reconstructions:
        eff = [float(r["effectivity"]) for r in per[rc]]
        mn += ["", f"{min(eff):.3f} / {max(eff):.3f}"]
    lines.append("| " + " | ".join(mn) + " |")
    tm = ["run wall s"] + ([""] if not manufactured else []) + [""]
    for rc in reconstructions:
        tm += [per[rc][0]["run_seconds"],
               f"est {sum(float(r['estimate_seconds']) for r in per[rc]):.1f}"]
    lines.append("| " + " | ".join(tm) + " |")
    return "\n".join(lines) + "\n"


def parse_list(value, known, what):
    if value == "all":
        return list(known)
    names = [v.strip() for v in value.split(",") if v.strip()]
    for n in names:
        if n not in known:
            raise SystemExit(f"unknown {what} '{n}'; known: "
                             + ", ".join(known))
    return names


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", type=int, default=5)
    runner.add_build_argument(parser)
    parser.add_argument("--csv", default=os.path.join(
        ROOT, "bench", "convergence", "convergence-study.csv"))
    parser.add_argument("--png", default=os.path.join(
        ROOT, "doc", "convergence-study.png"))
    parser.add_argument("--tables", default=None,
                        help="also write the markdown tables to this file")
    parser.add_argument("--reconstructions", default="all",
                        help="comma-separated subset of: "
                        + ", ".join(RECONSTRUCTIONS))
    parser.add_argument("--studies", default="all",
                        help="comma-separated subset of: "
                        + ", ".join(STUDIES))
    parser.add_argument("--jobs", type=int, default=1,
                        help="runs at a time (timings are per run)")
    args = parser.parse_args()
    reconstructions = parse_list(args.reconstructions, RECONSTRUCTIONS,
                                 "reconstruction")
    studies = parse_list(args.studies, STUDIES, "study")

    tasks = [(s, rc) for s in studies for rc in reconstructions]
    results = {}
    start = time.perf_counter()
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        futures = {ex.submit(run_one, args.build, args.meshes, s, rc): (s, rc)
                   for s, rc in tasks}
        for fut in concurrent.futures.as_completed(futures):
            s, rc = futures[fut]
            results[(s, rc)], seconds = fut.result()
            print(f"ran {s:15s} {rc:12s} {seconds:8.1f} s", flush=True)
    print(f"total wall time {time.perf_counter() - start:.1f} s")
    rows = [r for t in tasks for r in results[t]]

    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {args.csv}")

    tables = "\n".join(markdown_table(rows, s, reconstructions)
                       for s in studies)
    print()
    print(tables)
    if args.tables:
        os.makedirs(os.path.dirname(os.path.abspath(args.tables)),
                    exist_ok=True)
        with open(args.tables, "w") as f:
            f.write(f"Uniform refinement, {args.meshes} meshes; "
                    f"build {os.path.abspath(args.build)}\n\n" + tables)
        print(f"wrote {args.tables}")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no plot")
        return
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.5))
    colours = dict(zip(RECONSTRUCTIONS,
                       ("tab:blue", "tab:orange", "tab:green", "tab:red")))
    markers = {"block integral": "o", "block pointwise": "s",
               "manufactured": "^"}
    lines = {"block integral": "-", "block pointwise": "-.",
             "manufactured": ":"}
    for s in studies:
        if not STUDIES[s][2]:
            continue
        for rc in reconstructions:
            rs = select(rows, s, rc)
            n = [float(r["contact_cells"]) for r in rs]
            eps = [float(r["eps"]) for r in rs]
            ax.loglog(n, [100 * e for e in eps], lines[s] + markers[s],
                      color=colours[rc], fillstyle="none",
                      label=f"{s}: eps, {rc}, slope {slope(n, eps):.2f}")
        rs = select(rows, s, reconstructions[0])
        n = [float(r["contact_cells"]) for r in rs]
        ex = [float(r["eps_ex"]) for r in rs]
        ax.loglog(n, [100 * e for e in ex], "--" + markers[s], color="k",
                  label=f"{s}: eps_ex (exact), slope {slope(n, ex):.2f}")
    ax.set_xlabel("elements in contact (edge on GC)")
    ax.set_ylabel("relative error (%)")
    ax.set_title("Block: estimated and exact error, uniform refinement")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6)
    for s in studies:
        for rc in reconstructions:
            rs = select(rows, s, rc)
            bx.semilogx([float(r["cells"]) for r in rs],
                        [float(r["effectivity"]) for r in rs],
                        lines[s] + markers[s], color=colours[rc],
                        fillstyle="none", label=f"{s}, {rc}")
    bx.axhline(1.0, color="k", lw=0.8)
    bx.set_xlabel("cells")
    bx.set_ylabel("effectivity (block: eps / eps_ex; "
                  "manufactured: e / energy error)")
    bx.set_title("Effectivity, uniform refinement")
    bx.grid(True, which="both", alpha=0.3)
    bx.legend(fontsize=6)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
    fig.savefig(args.png, dpi=120)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
