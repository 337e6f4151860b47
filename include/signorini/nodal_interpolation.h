#ifndef signorini_nodal_interpolation_h
#define signorini_nodal_interpolation_h

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/lac/vector.h>

namespace Signorini
{
  using namespace dealii;

  /**
   * The vector P1 function @p u of @p source interpolated at the vertices of
   * @p target (same finite element on both). Exact when the target mesh
   * refines the source mesh; otherwise the usual nodal interpolation error
   * on the target cells that a source edge crosses (e.g. the green edges of
   * an adapted mesh compared on a uniform reference).
   *
   * The source cell of each vertex is found by a CellLocator; a vertex
   * outside the source mesh (on a curved boundary that a coarser polygon
   * approximates) extrapolates from the nearest cell.
   */
  template <int dim>
  Vector<double>
  interpolate_at_vertices(const DoFHandler<dim> &source,
                          const Vector<double>  &u,
                          const DoFHandler<dim> &target);
} // namespace Signorini

#endif
