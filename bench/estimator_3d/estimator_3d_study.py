#!/usr/bin/env python3
"""The error in constitutive relation on tetrahedra, for each reconstruction
(--reconstructions; by default the element equilibration with enhanced
densities, the default, and the star patch): its effectivity on

- the unit cube meshed by Gmsh (sizes --sizes) with the manufactured
  solution u = (x(1-x) y(1-y) z(1-z), 0, 0), zero on the boundary, against
  the exact energy error;
- the paper's block extruded (prm/block-3d.prm, Block subdivisions 4, 3, 4,
  --block-cycles uniform meshes) against a reference two levels finer than
  the finest.

Prints tetrahedra, e or eps, the exact error, the effectivity and the
estimate's seconds (Release, worker threads).

Usage: bench/estimator_3d/estimator_3d_study.py [--sizes 0.25 0.125 0.0625]
       [--block-cycles 2] [--build build]
       [--reconstructions "element equilibration" "star patch"]
"""
import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import runner  # noqa: E402
from runner import write_case  # noqa: E402

LAMBDA, MU = 0.5769230769230769, 0.3846153846153846
SOLUTION = "x*(1-x)*y*(1-y)*z*(1-z); 0; 0"
# f = -div sigma(u) for u = (g, 0, 0)
BODY_FORCE = (
    f"-(({LAMBDA}+2*{MU})*(-2*y*(1-y)*z*(1-z))"
    f" + {MU}*(-2*x*(1-x)*z*(1-z) - 2*x*(1-x)*y*(1-y)));"
    f" -({LAMBDA}+{MU})*(1-2*x)*(1-2*y)*z*(1-z);"
    f" -({LAMBDA}+{MU})*(1-2*x)*y*(1-y)*(1-2*z)")


def cube_case(size, workdir, reconstruction):
    """The manufactured case on the Gmsh cube of mesh size @p size."""
    geo = os.path.join(workdir, f"cube-{size}.geo")
    with open(geo, "w") as f:
        f.write('SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 1, 1, 1};\n'
                "Physical Surface(1) = {1, 2, 3, 4, 5, 6};\n"
                "Physical Volume(1) = {1};\n"
                f"Mesh.MeshSizeMin = {size};\nMesh.MeshSizeMax = {size};\n")
    prm = os.path.join(workdir, "cube.prm")
    out = os.path.join(workdir, "out-cube")
    with open(prm, "w") as f:
        f.write(f"""set Dimension = 3
set Output directory = {out}
set Number of cycles = 1
subsection Mesh
  set Source = file
  set File name = {geo}
end
subsection Boundary conditions
  subsection Dirichlet 1
    set Boundary ids = 1
    set Function expression = {SOLUTION}
  end
  subsection Body force
    set Function expression = {BODY_FORCE}
  end
end
subsection Contact
  set Boundary ids =
end
subsection Exact solution
  set Enable = true
  set Function expression = {SOLUTION}
end
subsection Error estimator
  set Enable = true
  set Stress reconstruction = {reconstruction}
end
subsection Output
  set Print timing = false
  set Write vtu = false
end
""")
    return prm, out


def rows(exe, prm, out):
    runner.run_timed([exe, prm])
    return runner.read_statistics(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=float, nargs="+",
                        default=[0.25, 0.125, 0.0625])
    parser.add_argument("--block-cycles", type=int, default=2)
    runner.add_build_argument(parser)
    parser.add_argument("--reconstructions", nargs="+",
                        default=["element equilibration", "star patch"])
    args = parser.parse_args()
    exe = runner.executable(args.build)
    with tempfile.TemporaryDirectory() as workdir:
        print("| reconstruction | case | tetrahedra | e | exact energy error "
              "| effectivity | estimate s |")
        print("|---|---|---:|---:|---:|---:|---:|")
        for reconstruction in args.reconstructions:
            for size in args.sizes:
                r = rows(exe, *cube_case(size, workdir, reconstruction))[-1]
                print(f"| {reconstruction} | cube, h = {size} | {r['cells']} "
                      f"| {float(r['e']):.4g} "
                      f"| {float(r['energy_error']):.4g} "
                      f"| {float(r['e']) / float(r['energy_error']):.3f} "
                      f"| {float(r['estimate_seconds']):.2f} |", flush=True)
        print("\n| reconstruction | case | tetrahedra | eps % | eps_ex % "
              "| effectivity | estimate s |")
        print("|---|---|---:|---:|---:|---:|---:|")
        for reconstruction in args.reconstructions:
            prm, out = write_case(
                "block-3d.prm",
                {"Number of cycles": args.block_cycles,
                 "Mesh/Initial refinements": 0,
                 "Error estimator/Enable": "true",
                 "Error estimator/Stress reconstruction": reconstruction,
                 "Reference solution/Extra refinements": 2,
                 "Output/Write vtu": "false", "Output/Print timing": "false"},
                workdir)
            for r in rows(exe, prm, out):
                print(f"| {reconstruction} | 3D block | {r['cells']} "
                      f"| {100 * float(r['eps']):.3f} "
                      f"| {100 * float(r['eps_ex']):.3f} "
                      f"| {float(r['effectivity']):.3f} "
                      f"| {float(r['estimate_seconds']):.2f} |", flush=True)

if __name__ == "__main__":
    main()
