#include <signorini/contact/active_set_solver.h>

#include <algorithm>
#include <numeric>
#include <set>

namespace Signorini
{
  namespace
  {
    /**
     * An active set that lets a free rigid motion move gives a singular
     * system. Keep the rows of @p active with the largest dual values
     * (the last ones to leave) in @p next until the free motions are
     * stopped.
     */
    template <int dim>
    void
    keep_rigid_motions_blocked(const DiscreteContactProblem<dim> &problem,
                               const std::vector<bool>           &active,
                               const Vector<double>              &y,
                               std::vector<bool>                 &next)
    {
      std::vector<unsigned int> rows(active.size());
      std::iota(rows.begin(), rows.end(), 0u);
      std::stable_sort(rows.begin(),
                       rows.end(),
                       [&](const unsigned int a, const unsigned int b) {
                         return (active[a] ? y[a] : -1e300) >
                                (active[b] ? y[b] : -1e300);
                       });
      for (const unsigned int i : rows)
        {
          if (problem.blocks_rigid_motions(next))
            return;
          next[i] = true;
        }
    }
  } // namespace

  template <int dim>
  void
  ActiveSetSolver<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.enter_subsection("Active set");
    prm.declare_entry("Maximum iterations",
                      "100",
                      Patterns::Integer(1),
                      "Limit on the number of active-set updates.");
    prm.declare_entry("Inexact tolerance",
                      "1e-6",
                      Patterns::Double(0., 1.),
                      "Relative CG tolerance of the solves while the active "
                      "set still changes (the final solve uses Linear "
                      "solver/Relative tolerance).");
    prm.declare_entry("Preconditioner update fraction",
                      "0.02",
                      Patterns::Double(0., 1.),
                      "Rebuild the elasticity preconditioner for the current "
                      "active set when more than this fraction of the contact "
                      "rows changed state since it was built.");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  void
  ActiveSetSolver<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.enter_subsection("Active set");
    max_iterations    = prm.get_integer("Maximum iterations");
    inexact_tolerance = prm.get_double("Inexact tolerance");
    preconditioner_update_fraction =
      prm.get_double("Preconditioner update fraction");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  std::string
  ActiveSetSolver<dim>::name() const
  {
    return "active set";
  }



  template <int dim>
  typename ContactSolver<dim>::Report
  ActiveSetSolver<dim>::solve(const DiscreteContactProblem<dim> &problem,
                              LA::Vector                        &u,
                              Vector<double>                    &y,
                              const std::vector<bool>           &initial_active)
  {
    typename ContactSolver<dim>::Report report;
    const unsigned int                  m = problem.n_constraints();
    // Without a guess the first step (empty active set) is the
    // unconstrained problem. A body held only by the contact has no
    // unconstrained problem: every active set must stop its free rigid
    // motions (check_rigid_motions() made sure the whole zone does), so it
    // starts in full contact.
    const bool        floating = (problem.n_rigid_motions() > 0);
    std::vector<bool> active   = (initial_active.size() == m) ?
                                   initial_active :
                                   std::vector<bool>(m, floating);
    if (!problem.blocks_rigid_motions(active))
      active.assign(m, true);
    std::set<std::vector<bool>> visited{active};
    // (without constraints the first solve is the last: make it exact)
    bool              exact = (inexact_tolerance == 0. || m == 0);
    std::vector<bool> preconditioned(m, false);

    while (true)
      {
        unsigned int drift = 0;
        for (unsigned int i = 0; i < m; ++i)
          drift += (active[i] != preconditioned[i]) ? 1 : 0;
        if (drift > preconditioner_update_fraction * m)
          {
            problem.update_preconditioner(active);
            preconditioned = active;
          }
        report.linear_iterations +=
          problem.solve_with_active_set(active,
                                        u,
                                        exact ? 0. : inexact_tolerance);
        ++report.linear_solves;
        ++report.iterations;
        y = problem.dual_from_residual(active, u);
        if (m == 0)
          {
            report.converged = true;
            break;
          }

        // Thresholds against round-off and the CG tolerance on nodes that
        // are in contact with a zero force (the contact/separation point).
        const Vector<double> slack     = problem.slack(u);
        const double         tol_slack = 1e-9 * problem.constraint_scale(u);
        const double         tol_y     = 1e-9 * max_norm(y);
        std::vector<bool>    next(m);
        for (unsigned int i = 0; i < m; ++i)
          next[i] = active[i] ? (y[i] >= -tol_y) : (slack[i] < -tol_slack);
        if (!problem.blocks_rigid_motions(next))
          keep_rigid_motions_blocked(problem, active, y, next);

        if (next == active)
          {
            if (exact)
              {
                report.converged = true;
                break;
              }
            exact = true; // confirm the active set with a full-accuracy solve
            continue;
          }
        if (!visited.insert(next).second)
          {
            if (!exact)
              exact = true; // inexact solves may cycle: go exact
            else
              throw std::runtime_error(
                "the active set method cycles (an active set repeated after " +
                std::to_string(report.iterations) +
                " iterations); use Contact/Solver = Frank-Wolfe");
          }
        if (report.iterations >= max_iterations)
          throw std::runtime_error(
            "the active set method did not converge in Contact/Active set/"
            "Maximum iterations = " +
            std::to_string(max_iterations));
        active = next;
      }

    if (m == 0)
      return report;

    // Report the relative KKT residual of the final iterate.
    const Vector<double> slack = problem.slack(u);
    const double scale_primal  = std::max(problem.constraint_scale(u), 1e-300);
    const double scale_dual    = std::max(max_norm(y), 1e-300);
    for (unsigned int i = 0; i < m; ++i)
      report.residual =
        std::max({report.residual,
                  -slack[i] / scale_primal,
                  -y[i] / scale_dual,
                  std::abs(y[i] * slack[i]) / (scale_dual * scale_primal)});
    return report;
  }

  template class ActiveSetSolver<2>;
} // namespace Signorini
