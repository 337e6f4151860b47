// The error density smoothing of the size prediction (ErrorDensitySmoothing)
// on the paper's block (96 triangles, cells of two areas) and the extruded
// block (1 152 tetrahedra):
// - 0 passes: eps_E unchanged;
// - a uniform density (eps_E^2 = |E|) is a fixed point, whatever the cells'
//   measures;
// - a spike (eps_E = 1 on one cell, 0 elsewhere): the global error kept
//   (sum of squares 1), one pass moves it to the cells sharing a vertex with
//   the spiked one and to no other, two passes one layer further, and the
//   spiked cell keeps the largest share.

#include <deal.II/base/mpi.h>

#include <signorini/adaptation/error_density_smoothing.h>
#include <signorini/mesh_input.h>

#include "tests.h"

#include <set>

using namespace SignoriniTests;

namespace
{
  /// The cells sharing a vertex with a cell of @p cells, and those.
  template <int dim>
  std::set<unsigned int>
  grow(const Triangulation<dim> &mesh, const std::set<unsigned int> &cells)
  {
    std::set<unsigned int> vertices;
    for (const auto &cell : mesh.active_cell_iterators())
      if (cells.count(cell->active_cell_index()) > 0)
        for (const unsigned int v : cell->vertex_indices())
          vertices.insert(cell->vertex_index(v));
    std::set<unsigned int> grown;
    for (const auto &cell : mesh.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (vertices.count(cell->vertex_index(v)) > 0)
          grown.insert(cell->active_cell_index());
    return grown;
  }



  ErrorDensitySmoothing
  smoothing(const unsigned int passes)
  {
    ParameterHandler prm;
    ErrorDensitySmoothing::declare_parameters(prm);
    prm.enter_subsection("Mesh adaptation");
    prm.set("Error density smoothing", std::to_string(passes));
    prm.leave_subsection();
    ErrorDensitySmoothing result;
    result.parse_parameters(prm);
    return result;
  }



  template <int dim>
  unsigned int
  check_block()
  {
    ParameterHandler prm;
    MeshInput<dim>::declare_parameters(prm);
    MeshInput<dim> input;
    input.parse_parameters(prm);
    Triangulation<dim> mesh;
    input.create(mesh);
    const unsigned int n = mesh.n_active_cells();
    deallog << dim << "D block, " << n << " cells" << std::endl;
    unsigned int failures = 0;

    Vector<double> uniform(n);
    for (const auto &cell : mesh.active_cell_iterators())
      uniform[cell->active_cell_index()] = std::sqrt(cell->measure());
    Vector<double> difference = smoothing(0).apply(mesh, uniform);
    difference -= uniform;
    expect_below("0 passes: unchanged", difference.linfty_norm(), 0., failures);
    difference = smoothing(2).apply(mesh, uniform);
    difference -= uniform;
    expect_below("uniform density: a fixed point",
                 difference.linfty_norm() / uniform.linfty_norm(),
                 1e-14,
                 failures);

    const unsigned int spiked = n / 3;
    Vector<double>     spike(n);
    spike[spiked]                    = 1.;
    std::set<unsigned int> reachable = {spiked};
    for (unsigned int passes = 1; passes <= 2; ++passes)
      {
        reachable                      = grow(mesh, reachable);
        const Vector<double> smoothed  = smoothing(passes).apply(mesh, spike);
        unsigned int         n_reached = 0, n_outside = 0;
        for (unsigned int c = 0; c < n; ++c)
          if (smoothed[c] > 0.)
            {
              ++n_reached;
              n_outside += reachable.count(c) == 0 ? 1 : 0;
            }
        deallog << passes << " passes: " << n_reached << " cells reached, "
                << reachable.size() << " within " << passes
                << " vertex layers; the spiked cell keeps "
                << std::setprecision(3) << smoothed[spiked] * smoothed[spiked]
                << " of eps^2" << std::setprecision(6) << std::endl;
        expect_below("  global error kept",
                     std::abs(smoothed.norm_sqr() - 1.),
                     1e-14,
                     failures);
        expect_below("  no cell beyond the layers reached",
                     n_outside,
                     0,
                     failures);
        expect_below("  every cell of the layers reached",
                     reachable.size() - n_reached,
                     0,
                     failures);
        expect_below("  the spiked cell keeps the largest share",
                     smoothed.linfty_norm() - smoothed[spiked],
                     0.,
                     failures);
      }
    return failures;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const unsigned int failures = check_block<2>() + check_block<3>();
  deallog << (failures == 0 ? "all checks passed" : "FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
