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
   * deal.II 9.4's point location and interpolate_to_different_mesh are not
   * reliable on triangles (dealii-9.4-triangles.md), so the source cell of
   * each vertex is found with an rtree of cell bounding boxes and a
   * barycentric test.
   */
  template <int dim>
  Vector<double>
  interpolate_at_vertices(const DoFHandler<dim> &source,
                          const Vector<double>  &u,
                          const DoFHandler<dim> &target);
} // namespace Signorini

#endif
