#ifndef signorini_contact_solver_h
#define signorini_contact_solver_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/vector.h>

#include <signorini/contact/discrete_problem.h>
#include <signorini/linear_algebra.h>

#include <memory>
#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * A solver of the discrete contact problem: given the DiscreteContactProblem
   * it returns the displacement u and the dual variable y >= 0 with
   * K u + B^T y = F, B u <= b, y^T (b - B u) = 0, to its tolerance.
   */
  template <int dim>
  class ContactSolver
  {
  public:
    struct Report
    {
      /// Outer iterations (active-set solves, or Frank-Wolfe steps).
      unsigned int iterations = 0;
      /// CG iterations of all elasticity solves together.
      unsigned int linear_iterations = 0;
      /// Elasticity solves (linear systems) performed.
      unsigned int linear_solves = 0;
      /// Relative KKT residual reached (0 for an exact active set).
      double residual  = 0.;
      bool   converged = false;
    };

    virtual ~ContactSolver() = default;

    /// "active set" or "Frank-Wolfe"
    virtual std::string
    name() const = 0;

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

  template <int dim>
  void
  declare_contact_solver_parameters(ParameterHandler &prm);

  /// Create (and configure) the solver named by Contact/Solver.
  template <int dim>
  std::unique_ptr<ContactSolver<dim>>
  create_contact_solver(ParameterHandler &prm);

  /// Same with an explicit name, parameters from @p prm.
  template <int dim>
  std::unique_ptr<ContactSolver<dim>>
  create_contact_solver(const std::string &name, ParameterHandler &prm);
} // namespace Signorini

#endif
