"""Run the application on prm/block-adaptive.prm with entries added, for the
benchmark scripts: the block's statistics and the wall time of the run."""
import csv
import os
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run_block(build, directory, additions):
    """Append `additions` (parameter file text) and `Output directory =
    directory` to prm/block-adaptive.prm, run it, and return (rows of
    statistics.csv, wall seconds of the whole program)."""
    with open(os.path.join(ROOT, "prm", "block-adaptive.prm")) as f:
        text = f.read()
    text += f"\nset Output directory = {directory}\n" + additions
    prm = directory + ".prm"
    with open(prm, "w") as f:
        f.write(text)
    start = time.perf_counter()
    subprocess.run([os.path.join(build, "signorini"), prm], check=True,
                   stdout=subprocess.DEVNULL)
    seconds = time.perf_counter() - start
    with open(os.path.join(directory, "statistics.csv")) as f:
        return list(csv.DictReader(f)), seconds
