#include <signorini/contact/active_set_solver.h>
#include <signorini/input_error.h>
#include <signorini/progress.h>

#include <algorithm>
#include <numeric>
#include <set>
#include <string>

namespace Signorini
{
  namespace
  {
    /**
     * An active set that lets a free rigid motion move gives a singular
     * system. Add rows to @p active in the order @p candidates until the
     * free motions are stopped.
     */
    template <int dim>
    void
    stop_rigid_motions(const DiscreteContactProblem<dim> &problem,
                       const std::vector<unsigned int>   &candidates,
                       std::vector<bool>                 &active)
    {
      for (const unsigned int i : candidates)
        {
          if (problem.blocks_rigid_motions(active))
            return;
          active[i] = true;
        }
    }

    /// The rows ordered by decreasing @p key.
    std::vector<unsigned int>
    rows_by_decreasing(const std::vector<double> &key)
    {
      std::vector<unsigned int> rows(key.size());
      std::iota(rows.begin(), rows.end(), 0u);
      std::stable_sort(rows.begin(),
                       rows.end(),
                       [&](const unsigned int a, const unsigned int b) {
                         return key[a] > key[b];
                       });
      return rows;
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
                      "set (with friction: the stick and slip sets too) "
                      "still changes (the final solves use Linear "
                      "solver/Relative tolerance; 0: every solve at that "
                      "accuracy; otherwise at least 1e-16).");
    prm.declare_entry("Preconditioner update fraction",
                      "0.02",
                      Patterns::Double(0., 1.),
                      "Rebuild the elasticity preconditioner for the current "
                      "active set when more than this fraction of the contact "
                      "rows changed state since it was built (with friction: "
                      "their dofs, normal and tangential, whose treatment "
                      "changed, against the number of rows).");
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
    // (as Linear solver/Relative tolerance: below 1e-16 CG breaks down,
    // 1e-300 gave NaN)
    if (inexact_tolerance > 0. && inexact_tolerance < 1e-16)
      throw InputError("Contact/Active set/Inexact tolerance = " +
                       prm.get("Inexact tolerance") +
                       ": 0 (every solve at Linear solver/Relative "
                       "tolerance) or from 1e-16 to 1");
    preconditioner_update_fraction =
      prm.get_double("Preconditioner update fraction");
    prm.leave_subsection();
    prm.leave_subsection();
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
    // motions (check_rigid_motions() made sure the whole zone can), so it
    // starts with the rows closest to contact (smallest bound per unit of
    // row weight) that stop them.
    std::vector<bool> active = (initial_active.size() == m) ?
                                 initial_active :
                                 std::vector<bool>(m, false);
    if (!problem.blocks_rigid_motions(active))
      {
        std::vector<double> closeness(m);
        for (unsigned int i = 0; i < m; ++i)
          closeness[i] =
            -problem.bounds()[i] / problem.condition().row_weight(i);
        stop_rigid_motions(problem, rows_by_decreasing(closeness), active);
      }
    std::set<std::vector<bool>> visited{active};
    // (without constraints the first solve is the last: make it exact)
    bool              exact = (inexact_tolerance == 0. || m == 0);
    std::vector<bool> preconditioned(m, false);
    Progress          progress("active set", u.get_mpi_communicator());

    while (true)
      {
        progress.report([&]() {
          return "iteration " + std::to_string(report.iterations) + ", " +
                 std::to_string(
                   std::count(active.begin(), active.end(), true)) +
                 " of " + std::to_string(m) + " rows active, " +
                 std::to_string(report.linear_iterations) + " CG iterations";
        });
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
        // (keeping the rows with the largest multipliers, the last to leave)
        if (!problem.blocks_rigid_motions(next))
          {
            std::vector<double> multiplier(m, -1e300);
            for (unsigned int i = 0; i < m; ++i)
              if (active[i])
                multiplier[i] = y[i];
            stop_rigid_motions(problem, rows_by_decreasing(multiplier), next);
          }

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

  template <int dim>
  bool
  ActiveSetSolver<dim>::uses_initial_active_set() const
  {
    return true;
  }

  template class ActiveSetSolver<2>;
  template class ActiveSetSolver<3>;

  SIGNORINI_REGISTER_TEMPLATE(
    ContactSolver,
    ActiveSetSolver,
    0,
    "active set",
    "primal-dual active set method, doc/theory.md section 3");
} // namespace Signorini
