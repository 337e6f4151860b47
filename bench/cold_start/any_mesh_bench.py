#!/usr/bin/env python3
"""Cold start on a mesh without coarser levels: a user's Gmsh mesh.

The block as a Gmsh mesh (tests/meshes/square.geo at h = 1/256 in 2D,
tests/meshes/block-3d.geo at h = 0.03 in 3D, meshed by the gmsh executable
into a temporary directory), one computation (Number of cycles = 1, so no
previous mesh to start from), both conditions, estimator off. Variants:

- floor: one elasticity solve on the same mesh (no contact boundary);
- gap 1: the contact problem with a gap of 1 (no contact becomes active);
- scratch: Contact/Nested start = false (the first step is the
  unconstrained problem);
- nested: the default; the mesh has no coarser levels, so its domain is
  meshed again by Gmsh at coarser sizes (CoarseDomainMesher) and solved
  first.

For each: active-set iterations on the mesh (for nested, in brackets, those
of the coarser meshes together), CG iterations, seconds (linear solver setup
and contact solve, the nested start's meshing, setup, assembly and solves
included), and the ratio to floor and to gap 1. Medians of --repeat runs,
interleaved.

Usage: bench/cold_start/any_mesh_bench.py [--repeat 3] [--dims 2 3]
                                         [--conditions integral pointwise]
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import measure_variants  # noqa: E402

MESHES = os.path.join(runner.ROOT, "tests", "meshes")


def gmsh_mesh(geometry, dim, size, directory):
    """The .msh of tests/meshes/@p geometry at maximal size @p size."""
    msh = os.path.join(directory, f"{os.path.splitext(geometry)[0]}.msh")
    subprocess.run(["gmsh", f"-{dim}", "-clmax", str(size), "-format",
                    "msh41", os.path.join(MESHES, geometry), "-o", msh],
                   check=True, stdout=subprocess.DEVNULL)
    return msh


def case(msh, condition):
    """Overrides of prm/block.prm or prm/block-3d.prm for the block on
    @p msh with @p condition, one computation, no estimate."""
    return {"Mesh/Source": "file", "Mesh/File name": msh,
            "Mesh/Initial refinements": "0", "Number of cycles": "1",
            "Error estimator/Enable": "false",
            "Contact/Condition": condition}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    runner.add_build_argument(parser)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--dims", type=int, nargs="+", default=[2, 3])
    parser.add_argument("--conditions", nargs="+",
                        default=["integral", "pointwise"])
    args = parser.parse_args()
    exe = runner.executable(args.build)

    print("| mesh | DoFs | condition | floor s | gap 1: its, s | "
          "scratch: its, CG, s, "
          "x floor, x gap 1 | nested: its (coarser), CG, s, x floor, "
          "x gap 1 |")
    print("|---|---:|---|---:|---|---|---|")
    with tempfile.TemporaryDirectory() as directory:
        for dim in args.dims:
            geometry, size = {2: ("square.geo", 1 / 256),
                              3: ("block-3d.geo", 0.03)}[dim]
            msh = gmsh_mesh(geometry, dim, size, directory)
            for condition in args.conditions:
                measure(exe, args.repeat, dim, geometry, size,
                        case(msh, condition), condition)


def measure(exe, repeat, dim, geometry, size, base, condition):
    """Run the four variants of @p base and print their table row."""
    variants = {
        "floor": dict(base, **{"Contact/Boundary ids": ""}),
        "gap 1": dict(base, **{"Contact/Gap/Function expression": "1",
                               "Contact/Nested start": "false"}),
        "scratch": dict(base, **{"Contact/Nested start": "false"}),
        "nested": dict(base)}
    results = measure_variants(exe, variants, repeat,
                               "block.prm" if dim == 2 else "block-3d.prm")
    floor_row, floor, _ = results["floor"]
    gap_row, gap, _ = results["gap 1"]
    cells = []
    for name in ("scratch", "nested"):
        row, t, _ = results[name]
        if row["converged"] != "1":
            sys.exit(f"{dim}D {condition} {name}: not converged")
        its = row["iterations"]
        if name == "nested":
            its += f" ({row['nested_iterations']})"
        cells.append(f"{its}, {row['cg_iterations']}, {t:.3g}, "
                     f"{t / floor:.2g}, {t / gap:.2g}")
    print(f"| {geometry} h = {size:.3g}, {floor_row['cells']} cells "
          f"| {floor_row['dofs']} | {condition} | {floor:.3g} | "
          f"{gap_row['iterations']}, {gap:.3g} | "
          + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
