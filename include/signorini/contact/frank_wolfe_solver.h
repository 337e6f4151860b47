#ifndef signorini_contact_frank_wolfe_solver_h
#define signorini_contact_frank_wolfe_solver_h

#include <signorini/contact/solver.h>

#include <map>

namespace Signorini
{
  /**
   * Frank-Wolfe (conditional gradient, [FRA 56], [MIN 83]) on the dual
   * problems [23] and [24], written for y = -Lambda (integral) or y = -Gamma
   * (pointwise):
   *
   *   min_{y >= 0} 1/2 y^T S y - d^T y,   S = B K^{-1} B^T,  d = B K^{-1} F -
   * b.
   *
   * The feasible set is the cone y >= 0: its extreme rays e_i and its apex 0.
   * With gradient g = S y - d, the linear subproblem min g^T s over the cone
   * is unbounded along the ray e_i of the most negative g_i (the step is then
   * found by exact line search along e_i) or attained at the apex (step
   * towards 0, line search on [0, 1]). Away steps (Guelat-Marcotte) along
   * -e_j, j the active index with the largest g_j, let a component return
   * exactly to zero, which the classical method can only approach; with
   * them the method converges linearly and ends on the exact active set.
   *
   * Only the columns of S of rows that become active are formed, one
   * elasticity solve each (cached); g is updated from them. Up to "Direct
   * columns limit" DoFs these solves use one sparse direct factorisation
   * (a back-substitution per column) rather than one AMG-CG solve each, if
   * Linear solver/Type is automatic. Long runs print a progress line every
   * "Progress interval" seconds.
   *
   * The iteration stops when the KKT residual max(-min g, max_{y_j>0} |g_j|) is
   * below "Tolerance" times the scale of d, or unconverged (with the residual
   * reached in the report) at "Maximum iterations" or when a new column
   * would exceed "Maximum columns". It starts from y = 0 and does not use an
   * initial active set.
   */
  template <int dim>
  class FrankWolfeSolver : public ContactSolver<dim>
  {
  public:
    /// Section Contact/Frank-Wolfe.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read section Contact/Frank-Wolfe.
    void
    parse_parameters(ParameterHandler &prm);

    /// The method described above (from y = 0; @p initial_active unused).
    typename ContactSolver<dim>::Report
    solve(const DiscreteContactProblem<dim> &problem,
          LA::Vector                        &u,
          Vector<double>                    &y,
          const std::vector<bool>           &initial_active = {}) override;

    /// Up to "Direct columns limit" DoFs.
    bool
    prefers_direct_solver(const types::global_dof_index n_dofs) const override;

    /// Limit on the number of Frank-Wolfe steps.
    unsigned int max_iterations = 1000000;
    /// KKT residual reached, relative to max |d|.
    double tolerance = 1e-12;
    /// Stop (unconverged) rather than form more columns of S than this.
    unsigned int max_columns = 100000;
    /// Largest problem whose columns use a direct factorisation.
    types::global_dof_index direct_columns_limit = 500000;
    /// Seconds between progress lines (0: none).
    double progress_interval = 10.;
  };
} // namespace Signorini

#endif
