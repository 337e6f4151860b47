#include <signorini/adaptation/error_density_smoothing.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace Signorini
{
  void
  ErrorDensitySmoothing::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    prm.declare_entry("Error density smoothing",
                      "0",
                      Patterns::Integer(0, 10),
                      "Passes of vertex-patch averaging of the error density "
                      "eps_E^2 / |E| before the sizes are predicted (0: none); "
                      "on Delaunay tetrahedra, whose eps_E scatter with their "
                      "shapes, it keeps the prediction from chasing that "
                      "scatter.");
    prm.leave_subsection();
  }



  void
  ErrorDensitySmoothing::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    passes = prm.get_integer("Error density smoothing");
    prm.leave_subsection();
  }



  template <int dim>
  Vector<double>
  ErrorDensitySmoothing::apply(const Triangulation<dim> &mesh,
                               const Vector<double>     &local_error) const
  {
    AssertDimension(local_error.size(), mesh.n_active_cells());
    if (passes == 0)
      return local_error;
    std::vector<double> measure(mesh.n_active_cells());
    std::vector<double> density(mesh.n_active_cells());
    std::vector<double> patch_measure(mesh.n_vertices(), 0.);
    for (const auto &cell : mesh.active_cell_iterators())
      {
        const unsigned int c = cell->active_cell_index();
        measure[c]           = cell->measure();
        density[c]           = local_error[c] * local_error[c] / measure[c];
        for (const unsigned int v : cell->vertex_indices())
          patch_measure[cell->vertex_index(v)] += measure[c];
      }
    std::vector<double> vertex_density(mesh.n_vertices());
    for (unsigned int pass = 0; pass < passes; ++pass)
      {
        // the mean density of every vertex patch, then of every cell the
        // mean of its vertices'
        std::fill(vertex_density.begin(), vertex_density.end(), 0.);
        for (const auto &cell : mesh.active_cell_iterators())
          {
            const unsigned int c = cell->active_cell_index();
            for (const unsigned int v : cell->vertex_indices())
              vertex_density[cell->vertex_index(v)] +=
                density[c] * measure[c] / patch_measure[cell->vertex_index(v)];
          }
        for (const auto &cell : mesh.active_cell_iterators())
          {
            double sum = 0.;
            for (const unsigned int v : cell->vertex_indices())
              sum += vertex_density[cell->vertex_index(v)];
            density[cell->active_cell_index()] = sum / cell->n_vertices();
          }
      }
    Vector<double> smoothed(local_error.size());
    for (unsigned int c = 0; c < smoothed.size(); ++c)
      smoothed[c] = std::sqrt(density[c] * measure[c]);
    // the same global error: the averages move error, they must not add any
    const double scale = local_error.l2_norm() / smoothed.l2_norm();
    if (std::isfinite(scale))
      smoothed *= scale;
    return smoothed;
  }

  template Vector<double>
  ErrorDensitySmoothing::apply(const Triangulation<2> &,
                               const Vector<double> &) const;
  template Vector<double>
  ErrorDensitySmoothing::apply(const Triangulation<3> &,
                               const Vector<double> &) const;
} // namespace Signorini
