#!/usr/bin/env python3
"""The installed package, used as a downstream program uses it.

Installs the build tree into a fresh prefix (cmake --install), configures
examples/contact_in_your_program against it with find_package(signorini)
alone, builds and runs it, and compares what it prints -- its own mesh,
assembly and constraints, signorini's contact solver and estimator -- with
the installed signorini executable on the same problem
(tests/inputs/block.prm, two refinements): the same mesh, the same energy
and contact force to the linear solver's tolerance, the same eps.

Usage: installed_package.py BUILD_DIR SOURCE_DIR BUILD_TYPE WORK_DIR
"""
import csv
import os
import shutil
import subprocess
import sys

build, source, build_type, work = sys.argv[1:5]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
prefix = os.path.join(work, "prefix")
signorini = os.path.join(prefix, "bin", "signorini")


def run(command, **kwargs):
    print("$", " ".join(command), flush=True)
    return subprocess.run(command, check=True, **kwargs)


run(["cmake", "--install", build, "--prefix", prefix],
    stdout=subprocess.DEVNULL)
example = os.path.join(work, "example")
run(["cmake", "-S", os.path.join(source, "examples", "contact_in_your_program"),
     "-B", example, f"-DCMAKE_PREFIX_PATH={prefix}",
     f"-DCMAKE_BUILD_TYPE={build_type}"], stdout=subprocess.DEVNULL)
run(["cmake", "--build", example], stdout=subprocess.DEVNULL)
output = run([os.path.join(example, "contact_in_your_program")],
             cwd=example, capture_output=True, text=True).stdout
print(output)
program = {}
for line in output.splitlines():
    key, _, value = line.rpartition(" ")
    program[key] = value

prm = os.path.join(work, "block.prm")
with open(os.path.join(source, "tests", "inputs", "block.prm")) as f:
    text = f.read()
with open(prm, "w") as f:
    f.write(text + f"""
set Output directory = {work}/application
set Number of cycles = 1
subsection Mesh
  set Initial refinements = 2
end
subsection Output
  set Write vtu = false
end
""")
run([signorini, prm], stdout=subprocess.DEVNULL)
with open(os.path.join(work, "application", "statistics.csv")) as f:
    application = list(csv.DictReader(f))[-1]

failures = 0
for key, column, tolerance in [("cells", "cells", 0.),
                               ("dofs", "dofs", 0.),
                               ("energy", "energy", 1e-8),
                               ("contact_force", "contact_force", 1e-8),
                               ("eps", "eps", 1e-8)]:
    mine, theirs = float(program[key]), float(application[column])
    difference = abs(mine - theirs) / max(abs(theirs), 1e-300)
    ok = difference <= tolerance
    failures += 0 if ok else 1
    print(f"{key}: program {mine:.10g}, signorini {theirs:.10g}, relative "
          f"difference {difference:.1e} {'ok' if ok else 'FAILED'}")
sys.exit(1 if failures else 0)
