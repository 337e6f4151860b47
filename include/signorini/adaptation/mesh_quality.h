#ifndef signorini_adaptation_mesh_quality_h
#define signorini_adaptation_mesh_quality_h

#include <deal.II/base/point.h>

#include <deal.II/grid/tria.h>

#include <vector>

namespace Signorini
{
  using namespace dealii;

  /// The smallest interior angle of all triangles, in degrees (in 3D: the
  /// smallest dihedral angle of all tetrahedra); throws if a cell is
  /// degenerate (zero area or volume) or inverted (oriented unlike the first
  /// cell).
  template <int dim>
  double
  minimum_angle(const Triangulation<dim> &mesh);

  /**
   * The cells that get the reduced convergence rate of the size prediction:
   * those with a vertex at a singular point. Singular points are found, not
   * given: the boundary vertices where the boundary id changes (a change of
   * boundary condition: clamped to free, end of a load, edge of the contact
   * zone) and the vertices @p extra_vertices (the last contact and first
   * separated node of GC, from the solver's active set).
   */
  template <int dim>
  std::vector<bool>
  cells_near_singular_points(const Triangulation<dim>        &mesh,
                             const std::vector<unsigned int> &extra_vertices);
} // namespace Signorini

#endif
