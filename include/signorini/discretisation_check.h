#ifndef signorini_discretisation_check_h
#define signorini_discretisation_check_h

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/lac/affine_constraints.h>

#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * Throw std::invalid_argument, naming @p caller, unless @p dof_handler is
   * the discretisation the library is written for (doc/library.md): a mesh
   * of simplices that every rank holds whole (no artificial cells: a
   * serial Triangulation on one rank, or a parallel::shared::Triangulation
   * without artificial cells), and the vector P1 element
   * FESystem(FE_SimplexP(1), dim). A quadrilateral mesh or a P2 element
   * would otherwise be read as P1 triangles (memory corruption in the
   * estimator, the mid-side dofs left free to penetrate the foundation),
   * and artificial cells give each rank another contact problem. With
   * @p hanging_node_constraints given, also throw when the mesh has hanging
   * nodes and these constraints are empty (forgotten: the solution would
   * be discontinuous). The same decision on every rank.
   */
  template <int dim>
  void
  check_discretisation(
    const DoFHandler<dim>           &dof_handler,
    const std::string               &caller,
    const AffineConstraints<double> *hanging_node_constraints = nullptr);
} // namespace Signorini

#endif
