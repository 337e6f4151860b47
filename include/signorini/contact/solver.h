#ifndef signorini_contact_solver_h
#define signorini_contact_solver_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/vector.h>

#include <signorini/contact/discrete_problem.h>
#include <signorini/linear_algebra.h>
#include <signorini/registry.h>

#include <memory>
#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * A solver of the discrete contact problem: given the DiscreteContactProblem
   * it returns the displacement u and the dual variable y >= 0 with
   * K u + B^T y = F, B u <= b, y^T (b - B u) = 0, to its tolerance. The
   * solvers form a family chosen by Contact/Solver (registry()).
   */
  template <int dim>
  class ContactSolver
  {
  public:
    /// What a solve did.
    struct Report
    {
      /// Outer iterations (active-set solves, or Frank-Wolfe steps).
      unsigned int iterations = 0;
      /// CG iterations of all elasticity solves together.
      unsigned int linear_iterations = 0;
      /// Elasticity solves (linear systems) performed.
      unsigned int linear_solves = 0;
      /// Relative KKT residual reached (0 for an exact active set).
      double residual = 0.;
      /// Whether the solver reached its tolerance.
      bool converged = false;
      /// Why it did not, when the solver can say more than that it reached
      /// its iteration limit (empty otherwise).
      std::string failure;

      /// Add the work of @p other (its iterations, linear solves and their
      /// iterations) to this report's: a solve made of several.
      void
      add_counts(const Report &other)
      {
        iterations += other.iterations;
        linear_iterations += other.linear_iterations;
        linear_solves += other.linear_solves;
      }
    };

    virtual ~ContactSolver() = default;

    /// The solvers, chosen by Contact/Solver; each registers itself
    /// (SIGNORINI_REGISTER_TEMPLATE()).
    static Registry<ContactSolver<dim>> &
    registry();

    /// The name the solver is chosen by.
    const std::string &
    name() const;

    /// Whether solve() uses a guess of the active set (worth computing on
    /// coarser meshes, see ContactComputation::enable_nested_start()).
    virtual bool
    uses_initial_active_set() const;

    /// Whether the linear solves of a problem with @p n_dofs DoFs should
    /// use the sparse direct factorisation even above Linear solver/Direct
    /// solver limit (when Linear solver/Type = automatic): a solver that
    /// solves with one matrix many times.
    virtual bool
    prefers_direct_solver(const types::global_dof_index n_dofs) const;

    /**
     * @p u holds the initial guess on entry; @p initial_active, if not
     * empty, a guess of the active set (one flag per constraint row), e.g.
     * from the previous mesh.
     */
    virtual Report
    solve(const DiscreteContactProblem<dim> &problem,
          LA::Vector                        &u,
          Vector<double>                    &y,
          const std::vector<bool>           &initial_active = {}) = 0;
  };
} // namespace Signorini

#endif
