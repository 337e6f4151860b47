// The extruded block against the 2D plane-strain block: prm/block-3d.prm's
// problem (u_z = 0 on the faces z = 0 and z = 1, the 2D block's loads,
// integral condition, active set method) on the 2D block's meshes extruded
// (Block subdivisions 4, 3, 1: 288, 2 304 and 18 432 tetrahedra over 96,
// 384 and 1 536 triangles). The cross sections of the 3D meshes are the 2D
// meshes, so the 3D space contains the 2D one extended constantly in z:
// the 3D energy can only be lower, and it must approach the 2D one as the
// tetrahedra, which let the displacement vary across a layer, are refined
// (exact equality mesh by mesh cannot hold). Checked: E_3D <= E_2D on every
// mesh, and the relative gap (E_2D - E_3D) / |E_2D| below 5e-3 and falling
// by more than half per refinement (doc/benchmarks.md, "3D": 3.8e-3,
// 1.3e-3, 2.7e-4).

#include "tests.h"

using namespace SignoriniTests;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  unsigned int failures = 0;

  const unsigned int n_meshes = 3;
  const Result       plane    = run<2>("block.prm",
                              {{"Number of cycles", std::to_string(n_meshes)},
                                        {"Output directory", "output-2d"}});
  const Result       extruded =
    run<3>("../runs/block_3d_frank_wolfe.prm",
           {{"Number of cycles", std::to_string(n_meshes)},
            {"Contact/Condition", "integral"},
            {"Contact/Solver", "active set"},
            {"Output directory", "output-3d"}});

  double previous_gap = 0.;
  for (unsigned int k = 0; k < n_meshes; ++k)
    {
      const double energy_2d = plane.history.at("energy")[k];
      const double energy_3d = extruded.history.at("energy")[k];
      const double gap       = (energy_2d - energy_3d) / std::abs(energy_2d);
      deallog << static_cast<unsigned int>(plane.history.at("cells")[k])
              << " triangles, energy " << std::setprecision(10) << energy_2d
              << "; "
              << static_cast<unsigned int>(extruded.history.at("cells")[k])
              << " tetrahedra, energy " << energy_3d << "; relative gap "
              << std::setprecision(2) << gap << std::endl;
      expect_below("  E_3D <= E_2D", -gap, 1e-12, failures);
      expect_below("  gap below 5e-3", gap, 5e-3, failures);
      if (k > 0)
        expect_below("  gap falls by more than half",
                     gap,
                     0.5 * previous_gap,
                     failures);
      previous_gap = gap;
    }

  deallog << (failures == 0 ? "all checks passed" : "FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
