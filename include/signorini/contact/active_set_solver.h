#ifndef signorini_contact_active_set_solver_h
#define signorini_contact_active_set_solver_h

#include <signorini/contact/solver.h>

namespace Signorini
{
  /**
   * Primal-dual active set method (semismooth Newton, Hintermueller, Ito and
   * Kunisch 2002) on the discrete problem. With the current displacement u
   * and dual variable y, the next active set is
   *   A = { i : y_i + c (B u - b)_i > 0 },
   * i.e. active rows stay while their y_i is non-negative and inactive rows
   * enter when they are violated. Each step minimises the energy under
   * (B u)_A = b_A as affine constraints (for the integral condition they
   * couple an active node to its neighbours, see
   * ContactCondition::add_active_constraints()) and recovers y_A from the
   * residual. It stops when the active set repeats; the last solve is done
   * to the full linear tolerance, earlier ones are inexact (Newton on a
   * piecewise linear system only needs the right active set).
   *
   * The preconditioner of the elasticity solves is rebuilt for the current
   * active set when it has drifted from the one it was built for by more
   * than "Preconditioner update fraction" of the rows, so that late
   * iterations, which move the active set by a node or two, cost little
   * more than one unconstrained solve. A good initial active set (from the
   * previous mesh) cuts the number of iterations.
   */
  template <int dim>
  class ActiveSetSolver : public ContactSolver<dim>
  {
  public:
    /// Section Contact/Active set.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read section Contact/Active set.
    void
    parse_parameters(ParameterHandler &prm);

    /// The method described above, from @p u (and @p initial_active).
    typename ContactSolver<dim>::Report
    solve(const DiscreteContactProblem<dim> &problem,
          LA::Vector                        &u,
          Vector<double>                    &y,
          const std::vector<bool>           &initial_active = {}) override;

    /// Yes: a good guess cuts the iterations.
    bool
    uses_initial_active_set() const override;

    /// Limit on the number of active-set updates.
    unsigned int max_iterations = 100;
    /// CG tolerance while the active set still changes.
    double inexact_tolerance = 1e-6;
    /// Rebuild the preconditioner when this fraction of rows changed.
    double preconditioner_update_fraction = 0.02;
  };
} // namespace Signorini

#endif
