#include <signorini/cell_locator.h>
#include <signorini/nodal_interpolation.h>

#include <stdexcept>

namespace Signorini
{
  template <int dim>
  Vector<double>
  interpolate_at_vertices(const DoFHandler<dim> &source,
                          const Vector<double>  &u,
                          const DoFHandler<dim> &target)
  {
    const CellLocator<dim> locator(source.get_triangulation());
    Vector<double>         result(target.n_dofs());
    std::vector<bool>      done(target.get_triangulation().n_vertices(), false);
    for (const auto &cell : target.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        {
          if (done[cell->vertex_index(v)])
            continue;
          done[cell->vertex_index(v)] = true;
          // (a vertex just outside, e.g. on a curved boundary, extrapolates)
          const auto location = locator.locate(cell->vertex(v));
          if (!location.found)
            throw std::runtime_error(
              "interpolate_at_vertices: the source mesh has no cells");
          const typename DoFHandler<dim>::active_cell_iterator source_cell(
            &source.get_triangulation(),
            locator.cell(location.cell)->level(),
            locator.cell(location.cell)->index(),
            &source);
          for (unsigned int c = 0; c < dim; ++c)
            {
              double value = 0.;
              for (unsigned int w = 0; w <= dim; ++w)
                value +=
                  location.weights[w] * u[source_cell->vertex_dof_index(w, c)];
              result[cell->vertex_dof_index(v, c)] = value;
            }
        }
    return result;
  }

  template Vector<double>
  interpolate_at_vertices(const DoFHandler<2> &,
                          const Vector<double> &,
                          const DoFHandler<2> &);
  template Vector<double>
  interpolate_at_vertices(const DoFHandler<3> &,
                          const Vector<double> &,
                          const DoFHandler<3> &);
} // namespace Signorini
