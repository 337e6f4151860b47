#ifndef signorini_contact_discrete_problem_h
#define signorini_contact_discrete_problem_h

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <signorini/contact/condition.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/linear_algebra.h>
#include <signorini/linear_solver.h>

#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The discrete Signorini problem as the contact solvers see it:
   *
   *   min 1/2 u^T K u - F^T u  subject to  B u <= b  (and the base
   *   constraints: hanging nodes, Dirichlet data),
   *
   * with optimality conditions K u + B^T y = F, y >= 0, B u <= b,
   * y^T (B u - b) = 0. B and b come from the ContactCondition; K and F are
   * unconstrained (raw) so that residuals are true nodal forces.
   */
  template <int dim>
  class DiscreteContactProblem
  {
  public:
    DiscreteContactProblem(
      const LA::SparseMatrix          &stiffness,
      const LA::Vector                &load,
      const AffineConstraints<double> &constraints,
      const AffineConstraints<double> &homogeneous_constraints,
      const AffineConstraints<double> &hanging_node_constraints,
      const ContactBoundary<dim>      &boundary,
      const ContactCondition<dim>     &condition,
      ElasticitySolver                &linear_solver);

    unsigned int
    n_constraints() const;

    /// B u
    Vector<double>
    constraint_values(const LA::Vector &u) const;

    /// b - B u (>= 0 where admissible)
    Vector<double>
    slack(const LA::Vector &u) const;

    const Vector<double> &
    bounds() const;

    /**
     * Minimise the energy under the base constraints and (B u)_i = b_i for
     * the active rows. Returns the CG iterations; @p u is the initial guess.
     */
    unsigned int
    solve_with_active_set(const std::vector<bool> &active,
                          LA::Vector              &u,
                          const double relative_tolerance = 0.) const;

    /**
     * Tune the linear solver's preconditioner to the active set @p active
     * (see ElasticitySolver::update_preconditioner()); an all-false set
     * restores the base preconditioner.
     */
    void
    update_preconditioner(const std::vector<bool> &active) const;

    /// Solve K u = F + sum_k forces_k nu_c (at node k of GC) under the base
    /// constraints.
    unsigned int
    solve_with_normal_forces(const Vector<double> &forces,
                             LA::Vector           &u,
                             const double relative_tolerance = 0.) const;

    /// Solve K u = F - B^T y under the base constraints.
    unsigned int
    solve_with_dual(const Vector<double> &y,
                    LA::Vector           &u,
                    const double          relative_tolerance = 0.) const;

    /// Column i of the dual operator S = B K^{-1} B^T (homogeneous base
    /// constraints). Returns the CG iterations.
    unsigned int
    dual_operator_column(const unsigned int i, Vector<double> &column) const;

    /// The dual variable of an active set from the residual of u.
    Vector<double>
    dual_from_residual(const std::vector<bool> &active,
                       const LA::Vector        &u) const;

    /**
     * The nodal residual F - K u with hanging-node rows moved to their
     * masters: the force the rest of the body does not balance at each dof
     * (the reactions at Dirichlet dofs, the contact forces on GC).
     */
    LA::Vector
    residual(const LA::Vector &u) const;

    /// 1/2 u^T K u - F^T u
    double
    energy(const LA::Vector &u) const;

    const ContactBoundary<dim> &
    boundary() const;

    const ContactCondition<dim> &
    condition() const;

    const LA::Vector &
    load() const;

    const AffineConstraints<double> &
    constraints() const;

    /// A typical size of the entries of B u, for relative tolerances.
    double
    constraint_scale(const LA::Vector &u) const;

  private:
    const LA::SparseMatrix          &stiffness_matrix;
    const LA::Vector                &load_vector;
    const AffineConstraints<double> &base_constraints;
    const AffineConstraints<double> &homogeneous_base_constraints;
    const AffineConstraints<double> &hanging_node_constraints;
    const ContactBoundary<dim>      &contact_boundary;
    const ContactCondition<dim>     &contact_condition;
    ElasticitySolver                &linear_solver;
  };
} // namespace Signorini

#endif
