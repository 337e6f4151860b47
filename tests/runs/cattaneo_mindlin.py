#!/usr/bin/env python3
"""Frictional Hertz contact against Hertz and Cattaneo-Mindlin, 2D and 3D.

Usage: cattaneo_mindlin.py SIGNORINI_BINARY SOURCE_DIR WORK_DIRECTORY

prm/hertz-friction.prm (a cylinder) and prm/hertz-friction-3d.prm (a ball),
Coulomb mu = 0.3: a normal load P, then a tangential load Q < mu P along the
load path, on their geometries meshed coarser by the contact point (h/a
about 0.045 in 2D, 0.2 in 3D), through
bench/cattaneo_mindlin/cattaneo_mindlin_study.py, for nu = 0.45 and 0.3.
Every step must converge (the study stops otherwise), and
- the contact half-width (radius) a is Hertz's within 3 % (2D) or 5 % (3D,
  where a node spacing is a fifth of a);
- nu = 0.45 (Dundurs' beta = 0.09: nearly uncoupled): the stick zone is
  Cattaneo-Mindlin's, c = a sqrt(1 - Q / (mu P)) (3D: cube root), within
  1.5 node spacings (2D) or half of one (3D), and centred within 0.1 a
  (3D 0.15 a);
- nu = 0.3 (beta = 0.29, about mu): the coupling Cattaneo-Mindlin ignores
  shows. The stick zone is shifted by more than 0.2 a and narrower by more
  than 0.2 a (3D 0.1 a), and its departure from Cattaneo-Mindlin is more
  than 3 times that at nu = 0.45.
The 3D ball at nu = 0.3 on 2 ranks gives the same sets and figures (its
sliding nodes' springs all belong to one rank: the others must still take
part in every exchange of the solve).
"""
import os
import sys

# dimension: (h_contact, a against Hertz, c against Cattaneo-Mindlin in
# node spacings, centring at nu = 0.45, narrowing at nu = 0.3)
CASES = {2: (0.004, 0.03, 1.5, 0.1, 0.2),
         3: (0.02, 0.05, 0.5, 0.15, 0.1)}


def main():
    binary, source, work = sys.argv[1:4]
    sys.path.insert(0, os.path.join(source, "bench", "cattaneo_mindlin"))
    from cattaneo_mindlin_study import study  # noqa: E402

    problems = []
    for dim, (size, width, spacings, centring, narrowing) in CASES.items():
        rows = {nu: study(os.path.abspath(binary), os.path.abspath(work), nu,
                          contact_size=size, dimension=dim)
                for nu in [0.45, 0.3]}
        for nu, r in rows.items():
            print(f"{dim}D: " + ", ".join(f"{k} {v:.4g}"
                                          for k, v in r.items()))
            if not abs(r["a"] / r["a Hertz"] - 1.) < width:
                problems.append(f"{dim}D, nu = {nu}: a = {r['a']}, Hertz "
                                f"{r['a Hertz']}")
            if not 0. < r["Q/(mu P)"] < 1.:
                problems.append(f"{dim}D, nu = {nu}: Q / (mu P) = "
                                f"{r['Q/(mu P)']}")
        near, coupled = rows[0.45], rows[0.3]
        if not abs(near["c/a"] - near["c/a CM"]) < spacings * near["h/a"]:
            problems.append(f"{dim}D, nu = 0.45: c/a = {near['c/a']}, "
                            f"Cattaneo-Mindlin {near['c/a CM']} (h/a = "
                            f"{near['h/a']})")
        if not abs(near["e/a"]) < centring:
            problems.append(f"{dim}D, nu = 0.45: stick zone offset "
                            f"{near['e/a']} a")
        if not (coupled["e/a"] > 0.2 and
                coupled["c/a CM"] - coupled["c/a"] > narrowing and
                abs(coupled["c/a"] - coupled["c/a CM"]) >
                3. * abs(near["c/a"] - near["c/a CM"])):
            problems.append(f"{dim}D, nu = 0.3: c/a = {coupled['c/a']} "
                            f"(Cattaneo-Mindlin {coupled['c/a CM']}), offset "
                            f"{coupled['e/a']} a: the coupling should show")
        if dim == 3:
            parallel = study(os.path.abspath(binary), os.path.abspath(work),
                             0.3, contact_size=size, dimension=dim, ranks=2)
            for key, value in rows[0.3].items():
                if not abs(parallel[key] - value) <= 1e-9 * abs(value):
                    problems.append(f"3D, nu = 0.3: {key} {value} on 1 rank, "
                                    f"{parallel[key]} on 2")
    for p in problems:
        print("  " + p)
    print("FAILED" if problems else "Cattaneo-Mindlin: Hertz width, the "
          "stick zone at nu = 0.45, the coupling at nu = 0.3, in 2D and 3D, "
          "1 and 2 ranks alike")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
