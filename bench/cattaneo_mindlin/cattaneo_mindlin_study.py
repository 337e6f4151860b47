#!/usr/bin/env python3
"""Frictional Hertz contact of a cylinder or a ball against
Cattaneo-Mindlin.

Usage: cattaneo_mindlin_study.py SIGNORINI_BINARY [WORK_DIRECTORY]
       [--dimension 2] [--poisson 0.3,0.4,0.45,0.49] [--steps 4]
       [--tangential D] [--contact-size H]

Runs prm/hertz-friction.prm (a cylinder of radius 1 pressed on a rigid plane
with Coulomb friction mu = 0.3 by moving its top edge down, then sideways;
in 3D prm/hertz-friction-3d.prm, a ball) for each Poisson ratio, and
compares with Hertz and Cattaneo-Mindlin. In 2D:
- a: the half-width of the contact zone (each edge midway between the last
  node in contact and the first one out), against Hertz's
  sqrt(4 P R / (pi E*)), E* = E / (1 - nu^2), P the normal load;
- c: the half-width of the stick zone (the same rule), against
  Cattaneo-Mindlin's a sqrt(1 - Q / (mu P)) (with the computed a), Q the
  tangential load; e: the offset of the stick zone's centre from the
  contact zone's, in units of a (0 for Cattaneo-Mindlin).
In 3D the same with a the radius of the contact zone (the half disc of the
lumped areas of the nodes in contact), Hertz's (3 P R / (4 E*))^(1/3), c
that of the stick zone against a (1 - Q / (mu P))^(1/3), e from the
centroids, and h the mesh size h_contact.
Cattaneo-Mindlin ignores the coupling of normal and tangential tractions,
which a rigid foundation has unless nu = 1/2 (Dundurs' beta =
(1 - 2 nu) / (2 (1 - nu)) vanishes); the table shows the trend with nu.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
MU = 0.3


def zone_half_width(rows, inside):
    """Half-width and centre of the nodes where inside(row) holds (a
    contiguous zone, edges midway to the neighbouring nodes)."""
    xs = [float(r["x"]) for r in rows]
    flags = [inside(r) for r in rows]
    indices = [i for i, f in enumerate(flags) if f]
    if not indices:
        return 0., 0.
    first, last = indices[0], indices[-1]
    if any(not f for f in flags[first:last + 1]):
        sys.exit("the zone is not contiguous")
    left = xs[first] if first == 0 else 0.5 * (xs[first - 1] + xs[first])
    right = xs[last] if last + 1 == len(xs) else \
        0.5 * (xs[last] + xs[last + 1])
    return 0.5 * (right - left), 0.5 * (right + left)


def zone_radius(rows, inside):
    """3D: the radius of the half disc (y >= 0) covered by the nodes where
    inside(row) holds (the area of their lumped areas, nodal force over
    nodal pressure), and the x of its centroid."""
    area = moment = 0.
    for r in rows:
        if inside(r):
            a = -float(r["nodal_force"]) / float(r["nodal_pressure"])
            area += a
            moment += a * float(r["x"])
    if area == 0.:
        return 0., 0.
    return math.sqrt(2. * area / math.pi), moment / area


def study(binary, work, nu, steps=4, tangential=None, contact_size=None,
          dimension=2, ranks=1):
    """The row of the table for Poisson ratio NU (runs in WORK/nu-NU), on
    the geometry of the example, or with its h_contact = CONTACT_SIZE, on
    RANKS MPI ranks."""
    directory = os.path.join(work, f"{dimension}d-nu-{nu}" +
                             (f"-np{ranks}" if ranks > 1 else ""))
    os.makedirs(directory, exist_ok=True)
    name, size = ("hertz-cylinder.geo", 0.002) if dimension == 2 else \
        ("hertz-ball.geo", 0.01)
    geometry = os.path.join(SOURCE, "prm", name)
    if contact_size is not None:
        with open(geometry) as f:
            text = f.read().replace(f"h_contact = {size};",
                                    f"h_contact = {contact_size};")
        geometry = os.path.join(directory, name)
        with open(geometry, "w") as f:
            f.write(text)
    example = "hertz-friction.prm" if dimension == 2 else \
        "hertz-friction-3d.prm"
    delta, d = (0.012, 0.002) if dimension == 2 else (0.01, 0.0015)
    if tangential is not None:
        d = tangential
    prm = os.path.join(directory, "run.prm")
    with open(prm, "w") as f:
        f.write(f"include {os.path.join(SOURCE, 'prm', example)}\n"
                f"set Output directory = {directory}\n"
                f"subsection Mesh\n  set File name = {geometry}\nend\n"
                f"subsection Material\n  set Poisson ratio = {nu}\nend\n"
                f"subsection Contact\n  set Load steps = {steps}\nend\n"
                "subsection Boundary conditions\n"
                f"  subsection Dirichlet {dimension - 1}\n"
                f"    set Function constants = delta={delta}, d={d}\n"
                "  end\nend\n"
                "subsection Output\n  set Write vtu = false\n"
                "  set Print timing = false\nend\n")
    command = [binary, prm]
    if ranks > 1:
        command = ["mpirun", "-np", str(ranks)] + command
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    try:
        result = subprocess.run(command, capture_output=True, text=True,
                                env=env, timeout=900)
    except subprocess.TimeoutExpired:
        sys.exit(f"{' '.join(command)} did not finish in 900 s")
    if result.returncode != 0:
        sys.exit(f"{binary} {prm} failed:\n{result.stdout}{result.stderr}")
    statistics = list(csv.DictReader(
        open(os.path.join(directory, "statistics.csv"))))[-1]
    rows = [r for r in csv.DictReader(
        open(os.path.join(directory, "contact-00.csv")))
        if r["multiplier_node"] == "1"]
    rows.sort(key=lambda r: float(r["x"]))
    e_star = 1. / (1. - nu * nu)
    active = (lambda r: r["active"] == "1")
    stick = (lambda r: r["friction_status"] == "stick")
    # (the half ball carries half the load; only x is loaded tangentially)
    copies = 1. if dimension == 2 else 2.
    P = copies * abs(float(statistics["contact_force"]))
    Q = copies * abs(sum(float(r["tangential_force_x"]) for r in rows))
    if dimension == 2:
        a_hertz = math.sqrt(4. * P / (math.pi * e_star))
        (a, centre), (c, stick_centre) = (zone_half_width(rows, z)
                                          for z in (active, stick))
        c_mindlin = a * math.sqrt(max(1. - Q / (MU * P), 0.))
        h = min(abs(float(r["x"]) - float(s["x"]))
                for r, s in zip(rows, rows[1:]))
    else:
        a_hertz = (3. * P / (4. * e_star)) ** (1. / 3.)
        (a, centre), (c, stick_centre) = (zone_radius(rows, z)
                                          for z in (active, stick))
        c_mindlin = a * max(1. - Q / (MU * P), 0.) ** (1. / 3.)
        h = float(contact_size if contact_size is not None else size)
    return {"nu": nu, "beta": (1 - 2 * nu) / (2 * (1 - nu)), "P": P,
            "Q/(mu P)": Q / (MU * P), "a": a, "a Hertz": a_hertz,
            "c/a": c / a, "c/a CM": c_mindlin / a,
            "e/a": (stick_centre - centre) / a, "h/a": h / a}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("work", nargs="?", default="cattaneo-mindlin")
    parser.add_argument("--poisson", default="0.3,0.4,0.45,0.49")
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--dimension", type=int, default=2)
    parser.add_argument("--tangential", type=float, default=None,
                        help="d, the tangential displacement of the top "
                        "(the example's: 0.002 in 2D, 0.0015 in 3D)")
    parser.add_argument("--contact-size", type=float, default=None,
                        help="h_contact of the mesh (the example's: 0.002 in "
                        "2D, 0.01 in 3D)")
    args = parser.parse_args()
    results = [study(os.path.abspath(args.binary), os.path.abspath(args.work),
                     float(nu), args.steps, args.tangential,
                     args.contact_size, args.dimension)
               for nu in args.poisson.split(",")]
    keys = list(results[0].keys())
    print(" | ".join(f"{k:>9}" for k in keys))
    for r in results:
        print(" | ".join(f"{r[k]:9.4g}" for k in keys))


if __name__ == "__main__":
    main()
