#!/usr/bin/env python3
"""Run a parameter file serially and on 2 MPI ranks and compare the results.

Usage: serial_parallel.py SIGNORINI_BINARY PRM WORK_DIRECTORY [RANKS]

The partition must not change the computation: mesh sizes, contact node
counts and active sets exactly; energies, forces, errors and nodal contact
values to the solver tolerance. Exits non-zero with the differences listed.
"""
import csv
import os
import shutil
import subprocess
import sys

EXACT = ["cycle", "cells", "dofs", "nodes", "green_cells", "contact_nodes",
         "active_nodes", "contact_cells", "converged", "iterations",
         "stick_nodes", "slip_nodes", "tresca_solves"]
CLOSE = ["energy", "contact_force", "e", "eps", "eps_contact", "eps_ex",
         "effectivity", "prager_synge_ratio", "min_angle", "predicted_cells",
         "contraction_at_solution"]
TOLERANCE = 1e-7  # relative; the CG tolerance is 1e-10


def run(binary, prm, directory, ranks, extra=""):
    """Run PRM (plus the parameter text EXTRA) on RANKS ranks into DIRECTORY."""
    os.makedirs(directory, exist_ok=True)
    wrapper = os.path.join(directory, "run.prm")
    with open(wrapper, "w") as f:
        f.write(f"include {os.path.abspath(prm)}\n")
        f.write(extra)
        f.write(f"set Output directory = {os.path.abspath(directory)}\n")
    command = [binary, wrapper]
    if ranks > 1:
        command = ["mpirun", "-np", str(ranks)] + command
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{result.stdout}\n{result.stderr}")


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def close(a, b, scale):
    return abs(float(a) - float(b)) <= TOLERANCE * max(scale, 1e-300)


def compare(serial, parallel):
    """The differences between the runs in the directories SERIAL and PARALLEL."""
    problems = []
    rows_1 = read(os.path.join(serial, "statistics.csv"))
    rows_2 = read(os.path.join(parallel, "statistics.csv"))
    if len(rows_1) != len(rows_2):
        problems.append(f"{len(rows_1)} cycles serially, {len(rows_2)} in parallel")
    for r1, r2 in zip(rows_1, rows_2):
        for key in EXACT:
            if key in r1 and r1[key] != r2.get(key):
                problems.append(f"cycle {r1['cycle']}: {key} {r1[key]} vs {r2.get(key)}")
        for key in CLOSE:
            if key in r1 and r1[key] != "" and not close(r1[key], r2[key], abs(float(r1[key]))):
                problems.append(f"cycle {r1['cycle']}: {key} {r1[key]} vs {r2[key]}")
    for r1 in rows_1:
        name = f"contact-{int(r1['cycle']):02d}.csv"
        nodes_1 = read(os.path.join(serial, name))
        nodes_2 = read(os.path.join(parallel, name))
        if len(nodes_1) != len(nodes_2):
            problems.append(f"{name}: {len(nodes_1)} vs {len(nodes_2)} nodes")
            continue
        for key in ["normal_displacement", "Lambda", "nodal_force"]:
            scale = max(abs(float(n[key])) for n in nodes_1)
            for n1, n2 in zip(nodes_1, nodes_2):
                if not close(n1[key], n2[key], scale):
                    problems.append(f"{name} x={n1['x']}: {key} {n1[key]} vs {n2[key]}")
        active_1 = [n["active"] for n in nodes_1]
        active_2 = [n["active"] for n in nodes_2]
        if active_1 != active_2:
            problems.append(f"{name}: active sets differ")
    return problems


def main():
    binary, prm, work = sys.argv[1:4]
    ranks = int(sys.argv[4]) if len(sys.argv) > 4 else 2
    shutil.rmtree(work, ignore_errors=True)
    serial = os.path.join(work, "serial")
    parallel = os.path.join(work, f"np{ranks}")
    run(binary, prm, serial, 1)
    run(binary, prm, parallel, ranks)
    problems = compare(serial, parallel)
    rows_1 = read(os.path.join(serial, "statistics.csv"))
    print(f"{os.path.basename(prm)}: {len(rows_1)} cycles, cells "
          f"{[r['cells'] for r in rows_1]}, active nodes "
          f"{[r['active_nodes'] for r in rows_1]}, eps "
          f"{[r.get('eps', '-') for r in rows_1]}: "
          + (f"identical on 1 and {ranks} ranks" if not problems else "DIFFERENT"))
    for p in problems:
        print("  " + p)
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
