#include <signorini/contact/frank_wolfe_solver.h>

namespace Signorini
{
  template <int dim>
  void
  FrankWolfeSolver<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.enter_subsection("Frank-Wolfe");
    prm.declare_entry("Maximum iterations",
                      "1000000",
                      Patterns::Integer(1),
                      "Limit on the number of Frank-Wolfe steps.");
    prm.declare_entry("Tolerance",
                      "1e-12",
                      Patterns::Double(0., 1.),
                      "Stop when the KKT residual of the dual problem is "
                      "below this fraction of max |d|.");
    prm.declare_entry("Maximum columns",
                      "100000",
                      Patterns::Integer(1),
                      "Limit on the columns of the dual operator formed (one "
                      "elasticity solve each); reaching it stops unconverged.");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  void
  FrankWolfeSolver<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.enter_subsection("Frank-Wolfe");
    max_iterations = prm.get_integer("Maximum iterations");
    tolerance      = prm.get_double("Tolerance");
    max_columns    = prm.get_integer("Maximum columns");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  std::string
  FrankWolfeSolver<dim>::name() const
  {
    return "Frank-Wolfe";
  }



  template <int dim>
  typename ContactSolver<dim>::Report
  FrankWolfeSolver<dim>::solve(const DiscreteContactProblem<dim> &problem,
                               LA::Vector                        &u,
                               Vector<double>                    &y,
                               const std::vector<bool> & /*initial_active*/)
  {
    typename ContactSolver<dim>::Report report;
    const unsigned int                  m = problem.n_constraints();

    // d = B K^{-1} F - b from the unconstrained solution.
    y.reinit(m);
    report.linear_iterations += problem.solve_with_dual(y, u);
    ++report.linear_solves;
    if (m == 0)
      {
        report.converged = true;
        return report;
      }
    Vector<double> d = problem.constraint_values(u);
    d -= problem.bounds();
    Vector<double> g(d); // g = S y - d
    g *= -1.;
    const double scale = std::max(max_norm(d), 1e-300);

    std::map<unsigned int, Vector<double>> columns; // S e_i
    // S e_i, formed on first use; nullptr once "Maximum columns" is reached
    const auto column = [&](const unsigned int i) -> const Vector<double> * {
      auto it = columns.find(i);
      if (it == columns.end())
        {
          if (columns.size() >= max_columns)
            return nullptr;
          Vector<double> s;
          report.linear_iterations += problem.dual_operator_column(i, s);
          ++report.linear_solves;
          it = columns.emplace(i, std::move(s)).first;
        }
      return &it->second;
    };

    for (report.iterations = 0; report.iterations < max_iterations;
         ++report.iterations)
      {
        // Linear subproblem over the cone and the away atom.
        unsigned int ray = 0, away = numbers::invalid_unsigned_int;
        double       kkt = 0.;
        for (unsigned int i = 0; i < m; ++i)
          {
            if (g[i] < g[ray])
              ray = i;
            if (y[i] > 0.)
              {
                kkt = std::max(kkt, std::abs(g[i]));
                if (away == numbers::invalid_unsigned_int || g[i] > g[away])
                  away = i;
              }
          }
        kkt             = std::max(kkt, -g[ray]);
        report.residual = kkt / scale;
        if (report.residual <= tolerance)
          {
            report.converged = true;
            break;
          }

        // Descent rate per unit length of each candidate direction.
        const double ray_rate = -g[ray];
        const double away_rate =
          (away != numbers::invalid_unsigned_int) ? g[away] : 0.;
        const double y_norm    = y.l2_norm();
        const double apex_rate = (y_norm > 0.) ? (g * y) / y_norm : 0.;

        if (ray_rate >= away_rate && ray_rate >= apex_rate)
          {
            const Vector<double> *column_ray = column(ray);
            if (column_ray == nullptr)
              break; // capped: report the residual reached
            const Vector<double> &s = *column_ray;
            const double          t = -g[ray] / s[ray];
            y[ray] += t;
            g.add(t, s);
          }
        else if (away_rate >= apex_rate)
          {
            const Vector<double> &s = *column(away); // formed when it entered
            double                t = g[away] / s[away];
            if (t >= y[away])
              {
                t       = y[away];
                y[away] = 0.; // drop step: exactly inactive again
              }
            else
              y[away] -= t;
            g.add(-t, s);
          }
        else
          {
            // towards the apex: direction -y; S y = g + d
            Vector<double> Sy(g);
            Sy += d;
            const double t = std::min(1., (g * y) / (Sy * y));
            y *= (1. - t);
            g.sadd(1. - t, -t, d);
          }
      }

    // Displacement of the final multipliers.
    report.linear_iterations += problem.solve_with_dual(y, u);
    ++report.linear_solves;
    return report;
  }

  template class FrankWolfeSolver<2>;
} // namespace Signorini
