#!/usr/bin/env python3
"""Where the 3D estimate's time and memory go, against the contact solve.

Runs prm/block-3d.prm (the paper's block extruded, Block subdivisions
4, 3, 4, refined --levels times: 1 gives 9 216 tetrahedra, 2 gives 73 728)
in separate processes, one computation each, with the error estimator at its
defaults and without it. Prints per mesh: tetrahedra, DoFs, the contact
solve's seconds, the estimate's seconds and their ratio (within one run),
the seconds of the estimate's steps (the program's "estimate steps" line),
the peak resident memory with and without the estimator and the difference
per tetrahedron, and eps. Medians over --repeat repetitions (each runs both
computations back to back); the machine is shared: read the ratios.

Usage: /usr/bin/python3 bench/estimator_3d_cost/estimator_3d_cost.py
       [--levels 1 2] [--repeat 3] [--build build]
"""
import argparse
import os
import re
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import run_logged, write_case  # noqa: E402


def run(exe, overrides, work):
    """Run block-3d.prm with @p overrides; return (statistics row, estimate
    steps {name: seconds}, peak MiB)."""
    prm, out = write_case("block-3d.prm", overrides, work)
    output, code, peak = run_logged([exe, prm])
    if code != 0:
        sys.exit(f"{exe} {prm} failed:\n{output}")
    steps = {}
    for line in output.splitlines():
        if "estimate steps" in line:
            for name, seconds in re.findall(
                    r"([a-z][a-z ()0-9]*?) ([0-9.e+-]+) s", line.split(":", 1)[1]):
                steps[re.sub(r" \(\d+ iterations\)", "", name.strip())] = (
                    float(seconds))
            match = re.search(r"enhancement \((\d+) iterations\)", line)
            if match:
                steps["iterations"] = float(match.group(1))
    row = runner.read_statistics(out)[-1]
    return row, steps, peak


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeat", type=int, default=3)
    runner.add_build_argument(parser)
    args = parser.parse_args()
    exe = runner.executable(args.build)

    step_names = ["mesh and strains", "classical densities", "element fields",
                  "enhancement", "element errors"]
    print("| tetrahedra | DoFs | contact solve s | estimate s | ratio | "
          + " | ".join(f"{name} s" for name in step_names)
          + " | enhancement iterations | peak MiB without | peak MiB with "
          "| estimate kB / tetrahedron | eps % |")
    print("|" + "---:|" * (10 + len(step_names)))
    for level in args.levels:
        base = {"Mesh/Initial refinements": str(level),
                "Number of cycles": "1",
                "Output/Write vtu": "false",
                "Output/Print timing": "true"}
        samples = {}
        with tempfile.TemporaryDirectory() as work:
            for _ in range(args.repeat):
                off, _, peak_off = run(
                    exe, dict(base, **{"Error estimator/Enable": "false"}),
                    work)
                on, steps, peak_on = run(
                    exe, dict(base, **{"Error estimator/Enable": "true"}),
                    work)
                cells = float(on["cells"])
                values = {"contact": float(on["solve_seconds"]),
                          "estimate": float(on["estimate_seconds"]),
                          "ratio": float(on["estimate_seconds"])
                          / float(on["solve_seconds"]),
                          "peak_off": peak_off, "peak_on": peak_on,
                          "per_cell": (peak_on - peak_off) * 1024. / cells,
                          "eps": 100. * float(on["eps"])}
                values.update(steps)
                for key, value in values.items():
                    samples.setdefault(key, []).append(value)
        median = {key: statistics.median(v) for key, v in samples.items()}
        print(f"| {int(float(on['cells']))} | {on['dofs']} "
              f"| {median['contact']:.2f} | {median['estimate']:.2f} "
              f"| {median['ratio']:.1f} | "
              + " | ".join(f"{median.get(name, 0.):.2f}" for name in step_names)
              + f" | {median.get('iterations', 0):.0f} "
              f"| {median['peak_off']:.0f} | {median['peak_on']:.0f} "
              f"| {median['per_cell']:.1f} | {median['eps']:.3f} |",
              flush=True)


if __name__ == "__main__":
    main()
