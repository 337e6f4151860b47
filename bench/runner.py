"""What every benchmark script does, in one place: find the executable, write
a parameter file from a base file plus additions, run it (wall time, peak
memory), read statistics.csv, take medians over repeats.

A study imports it from the folder above its own:
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    import runner
"""
import csv
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)


# --- the executable ---

def add_build_argument(parser):
    """--build: the build directory (default: the source's build/)."""
    parser.add_argument("--build", default=os.path.join(ROOT, "build"),
                        help="build directory holding signorini (relative "
                             "to the working directory, else to the source)")


def executable(build):
    """signorini in @p build: relative to the working directory if that
    exists, else to the source directory (the scripts took either)."""
    if not os.path.isabs(build) and not os.path.isdir(build):
        build = os.path.join(ROOT, build)
    return os.path.join(build, "signorini")


def example(name):
    """The shipped example prm/@p name."""
    return os.path.join(ROOT, "prm", name)


# --- parameter files ---

def entries(overrides):
    """Parameter file text setting @p overrides (parameter path -> value,
    e.g. "Contact/Solver" -> "Frank-Wolfe")."""
    text = ""
    for path, value in overrides.items():
        parts = path.split("/")
        text += "".join(f"subsection {p}\n" for p in parts[:-1])
        text += f"set {parts[-1]} = {value}\n"
        text += "end\n" * (len(parts) - 1)
    return text


def write_case(example_name, overrides, workdir):
    """prm/@p example_name with its output in @p workdir/out and the
    @p overrides (parameter path -> value) appended, as @p workdir/case.prm;
    returns the paths of the file and of the (emptied) output directory."""
    out = os.path.join(workdir, "out")
    prm = os.path.join(workdir, "case.prm")
    with open(example(example_name)) as base, open(prm, "w") as f:
        f.write(base.read())
        f.write(f"\nset Output directory = {out}\n")
        f.write(entries(overrides))
    shutil.rmtree(out, ignore_errors=True)  # (no stale results)
    return prm, out


# --- runs ---

def read_statistics(directory):
    """The rows of @p directory/statistics.csv (one per cycle)."""
    with open(os.path.join(directory, "statistics.csv")) as f:
        return list(csv.DictReader(f))


def run_logged(command):
    """Run @p command; return (its screen output, exit code, peak resident
    MiB: under mpirun that of the largest rank it waited for)."""
    with tempfile.TemporaryFile(mode="w+") as log:
        process = subprocess.Popen(command, stdout=log,
                                   stderr=subprocess.STDOUT, text=True)
        _, status, usage = os.wait4(process.pid, 0)
        log.seek(0)
        output = log.read()
    return output, os.waitstatus_to_exitcode(status), usage.ru_maxrss / 1024.


def on_ranks(command, ranks):
    """@p command under mpirun on @p ranks (oversubscribed, as root too),
    or itself for one rank."""
    if ranks <= 1:
        return list(command)
    return ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
            str(ranks)] + list(command)


def phase_tables(output):
    """The tables a run prints with `Output/Print timing`: (phase -> (calls,
    wall seconds), phase -> (peak MiB at its end, raised by MiB or None);
    the second has "whole run" too)."""
    times, memory = {}, {}
    for line in output.splitlines():
        timed = re.match(r"\|\s*([a-z ]+?)\s*\|\s*(\d+)\s*\|\s*([0-9.e+-]+)s",
                         line)
        if timed:
            times[timed.group(1)] = (int(timed.group(2)),
                                     float(timed.group(3)))
        measured = re.match(r"\|\s*([a-z ]+?)\s*\|\s*([0-9.]+)\s*\|"
                            r"\s*([0-9.]*)\s*\|$", line)
        if measured:
            raised = measured.group(3)
            memory[measured.group(1)] = (float(measured.group(2)),
                                         float(raised) if raised else None)
    return times, memory


def run_timed(command, **kwargs):
    """Run @p command (its screen output discarded, a failure an exception);
    return the wall seconds of the whole program."""
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, **kwargs)
    return time.perf_counter() - start


def run_case(exe, overrides, workdir, example_name="block.prm"):
    """Run prm/@p example_name (block.prm) with overrides; return (last
    statistics row, peak MiB)."""
    overrides = dict(overrides)
    overrides.setdefault("Output/Write vtu", "false")
    overrides.setdefault("Output/Print timing", "false")
    prm, out = write_case(example_name, overrides, workdir)
    with tempfile.TemporaryFile() as errors:
        process = subprocess.Popen([exe, prm], stdout=subprocess.DEVNULL,
                                   stderr=errors)
        _, status, usage = os.wait4(process.pid, 0)
        # (exit code 2: a computation that did not converge, e.g. a capped
        # Frank-Wolfe, whose statistics are written and say so)
        code = os.waitstatus_to_exitcode(status)
        if code not in (0, 2) or not os.path.exists(
                os.path.join(out, "statistics.csv")):
            errors.seek(0)
            sys.exit(f"{prm} {overrides} failed (exit code {code}):\n"
                     + errors.read().decode(errors="replace"))
    return read_statistics(out)[-1], usage.ru_maxrss / 1024.0


def run_block(build, directory, additions):
    """Append `additions` (parameter file text) and `Output directory =
    directory` to prm/block-adaptive.prm, run it, and return (rows of
    statistics.csv, wall seconds of the whole program)."""
    with open(example("block-adaptive.prm")) as f:
        text = f.read()
    text += f"\nset Output directory = {directory}\n" + additions
    prm = directory + ".prm"
    with open(prm, "w") as f:
        f.write(text)
    seconds = run_timed([executable(build), prm])
    return read_statistics(directory), seconds


# --- measurements ---

def seconds(row):
    """The contact solve's time in a statistics row: setup + solve."""
    return float(row["setup_seconds"]) + float(row["solve_seconds"])


def single_mesh(level):
    """Overrides for the block refined @p level times, one computation, no
    estimate."""
    return {"Mesh/Initial refinements": str(level), "Number of cycles": "1",
            "Error estimator/Enable": "false"}


def median(values):
    return statistics.median(values)


def measure_variants(exe, variants, repeat, example_name="block.prm"):
    """Run every variant (name -> overrides of prm/@p example_name) @p repeat
    times, interleaved so that the machine's load affects all alike; return,
    per name, the last statistics row, the median seconds and the peak
    MiB."""
    times = {key: [] for key in variants}
    rows, memory = {}, {key: 0. for key in variants}
    with tempfile.TemporaryDirectory() as work:
        for _ in range(repeat):
            for key, overrides in variants.items():
                row, mib = run_case(exe, overrides, work, example_name)
                rows[key] = row
                times[key].append(seconds(row))
                memory[key] = max(memory[key], mib)
    return {key: (rows[key], median(times[key]), memory[key])
            for key in variants}
