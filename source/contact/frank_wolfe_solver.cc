#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <deal.II/lac/lapack_full_matrix.h>

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
                      Patterns::Double(1e-14, 1.),
                      "Stop when the KKT residual of the dual problem is "
                      "below this fraction of max |d| (at least 1e-14: "
                      "round-off allows no less).");
    prm.declare_entry("Maximum columns",
                      "100000",
                      Patterns::Integer(1),
                      "Limit on the columns of the dual operator formed (one "
                      "elasticity solve each); reaching it stops unconverged.");
    prm.declare_entry("Direct columns limit",
                      "500000",
                      Patterns::Integer(0),
                      "Up to this many DoFs, and with Linear solver/Type = "
                      "automatic, the columns are formed with one sparse "
                      "direct factorisation (a back-substitution each) "
                      "instead of one AMG-CG solve each.");
    prm.declare_entry("Progress interval",
                      "10",
                      Patterns::Double(0.),
                      "Print the step, the columns formed and the KKT "
                      "residual every this many seconds (0: never).");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  void
  FrankWolfeSolver<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.enter_subsection("Frank-Wolfe");
    max_iterations       = prm.get_integer("Maximum iterations");
    tolerance            = prm.get_double("Tolerance");
    max_columns          = prm.get_integer("Maximum columns");
    direct_columns_limit = prm.get_integer("Direct columns limit");
    progress_interval    = prm.get_double("Progress interval");
    prm.leave_subsection();
    prm.leave_subsection();
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

    // d = B K^{-1} F - b from the unconstrained solution (K_s, with the
    // supports of the free rigid motions, if any).
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
    const double scale = std::max(max_norm(d), 1e-300);

    // A body held only by the contact: the dual solution must also balance
    // the load on the free rigid motions, C^T y = h. An augmented
    // Lagrangian keeps the cone y >= 0 Frank-Wolfe's only constraint: the
    // dual energy gets mu^T (C^T y - h) + rho/2 |C^T y - h|^2, whose
    // Hessian is S + rho C C^T, and mu, updated between Frank-Wolfe runs,
    // converges to minus the rigid displacement.
    const FullMatrix<double> &C = problem.rigid_constraint_rows();
    const Vector<double>     &h = problem.rigid_load();
    const unsigned int        r = problem.n_rigid_motions();
    Vector<double>            mu(r);
    double                    rho = 0.;
    if (r > 0)
      {
        double c_max = 0.;
        for (unsigned int i = 0; i < m; ++i)
          for (unsigned int j = 0; j < r; ++j)
            c_max = std::max(c_max, std::abs(C(i, j)));
        // S y ~ d for y ~ |h| / |C|: the penalty of the same size
        rho = scale / (std::max(h.l2_norm(), 1e-300) * c_max);
      }
    // the linear term of the augmented dual energy
    Vector<double> d_augmented(d);
    const auto     update_linear_term = [&]() {
      Vector<double> shift(r);
      for (unsigned int j = 0; j < r; ++j)
        shift[j] = -mu[j] + rho * h[j];
      d_augmented = d;
      if (r > 0)
        C.vmult_add(d_augmented, shift);
    };
    update_linear_term();
    Vector<double> g(d_augmented); // g = (S + rho C C^T) y - d_augmented
    g *= -1.;

    std::map<unsigned int, Vector<double>> columns; // S e_i
    // S e_i, formed on first use; nullptr once "Maximum columns" is reached
    const auto dual_column =
      [&](const unsigned int i) -> const Vector<double> * {
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
    // column i of the augmented Hessian S + rho C C^T
    Vector<double> column(m);
    const auto     augmented_column = [&](const unsigned int i) -> bool {
      const Vector<double> *s = dual_column(i);
      if (s == nullptr)
        return false;
      column = *s;
      if (r > 0)
        {
          Vector<double> c_i(r);
          for (unsigned int j = 0; j < r; ++j)
            c_i[j] = rho * C(i, j);
          C.vmult_add(column, c_i);
        }
      return true;
    };
    // C^T y - h
    const auto rigid_imbalance = [&]() {
      Vector<double> imbalance(r);
      if (r > 0)
        {
          C.Tvmult(imbalance, y);
          imbalance -= h;
        }
      return imbalance;
    };

    // The multiplier update: Newton's step on C^T y(mu) = h with the
    // support A of y fixed, where y_A = H_AA^{-1} d_augmented_A(mu), i.e.
    // mu += (C_A^T H_AA^{-1} C_A)^{-1} (C^T y - h); the classical step
    // rho (C^T y - h) of the method of multipliers converges linearly
    // with a rate close to one here.
    const auto multiplier_step = [&](const Vector<double> &imbalance) {
      std::vector<unsigned int> support;
      for (unsigned int i = 0; i < m; ++i)
        if (y[i] > 0.)
          support.push_back(i);
      Vector<double> step(imbalance);
      step *= rho;
      const unsigned int n = support.size();
      if (n == 0)
        return step;
      LAPACKFullMatrix<double> H(n, n);
      for (unsigned int b = 0; b < n; ++b)
        {
          augmented_column(support[b]); // formed when it entered
          for (unsigned int a = 0; a < n; ++a)
            H(a, b) = column[support[a]];
        }
      H.compute_lu_factorization();
      FullMatrix<double> jacobian(r, r);
      for (unsigned int k = 0; k < r; ++k)
        {
          Vector<double> x(n);
          for (unsigned int a = 0; a < n; ++a)
            x[a] = C(support[a], k);
          H.solve(x);
          for (unsigned int j = 0; j < r; ++j)
            for (unsigned int a = 0; a < n; ++a)
              jacobian(j, k) += C(support[a], j) * x[a];
        }
      // (singular when the support does not stop the free motions: keep
      // the classical step then)
      LAPACKFullMatrix<double> J(r, r);
      J = jacobian;
      J.compute_svd();
      if (J.singular_value(r - 1) <= 1e-12 * J.singular_value(0))
        return step;
      J.compute_inverse_svd();
      J.vmult(step, imbalance);
      return step;
    };

    // (rank 0 prints; every rank takes the same steps)
    ConditionalOStream progress(
      std::cout, Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0);
    Timer  progress_timer;
    double next_progress = progress_interval;
    bool   capped        = false;
    for (report.iterations = 0; report.iterations < max_iterations && !capped;
         ++report.iterations)
      {
        // (the clock is read every 16 steps: a step costs a column update)
        if (progress_interval > 0. && report.iterations % 16 == 0 &&
            progress_timer.wall_time() >= next_progress)
          {
            progress << "   Frank-Wolfe: step " << report.iterations << ", "
                     << columns.size() << " columns, KKT residual "
                     << report.residual << " after "
                     << std::round(progress_timer.wall_time()) << " s"
                     << std::endl;
            next_progress = progress_timer.wall_time() + progress_interval;
          }
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
            // converged for this mu: done if the load is balanced on the
            // free rigid motions, else update the multiplier
            const Vector<double> imbalance = rigid_imbalance();
            if (r == 0 || imbalance.l2_norm() <=
                            tolerance * std::max(h.l2_norm(), 1e-300))
              {
                report.converged = true;
                break;
              }
            const Vector<double> step = multiplier_step(imbalance);
            mu += step;
            C.vmult_add(g, step); // g = H y - d_augmented(mu)
            update_linear_term();
            continue;
          }

        // Descent rate per unit length of each candidate direction.
        const double ray_rate = -g[ray];
        const double away_rate =
          (away != numbers::invalid_unsigned_int) ? g[away] : 0.;
        const double y_norm    = y.l2_norm();
        const double apex_rate = (y_norm > 0.) ? (g * y) / y_norm : 0.;

        if (ray_rate >= away_rate && ray_rate >= apex_rate)
          {
            if (!augmented_column(ray))
              {
                capped = true; // report the residual reached
                break;
              }
            const double t = -g[ray] / column[ray];
            y[ray] += t;
            g.add(t, column);
          }
        else if (away_rate >= apex_rate)
          {
            augmented_column(away); // formed when it entered
            double t = g[away] / column[away];
            if (t >= y[away])
              {
                t       = y[away];
                y[away] = 0.; // drop step: exactly inactive again
              }
            else
              y[away] -= t;
            g.add(-t, column);
          }
        else
          {
            // towards the apex: direction -y; H y = g + d_augmented
            Vector<double> Hy(g);
            Hy += d_augmented;
            const double t = std::min(1., (g * y) / (Hy * y));
            y *= (1. - t);
            g.sadd(1. - t, -t, d_augmented);
          }
      }

    // Displacement of the final multipliers, plus the rigid motion -mu
    // that the supports held back.
    report.linear_iterations += problem.solve_with_dual(y, u);
    ++report.linear_solves;
    if (r > 0)
      {
        Vector<double> c(mu);
        c *= -1.;
        problem.add_rigid_motion(c, u);
      }
    return report;
  }

  template <int dim>
  bool
  FrankWolfeSolver<dim>::prefers_direct_solver(
    const types::global_dof_index n_dofs) const
  {
    return n_dofs <= direct_columns_limit;
  }

  template class FrankWolfeSolver<2>;
  template class FrankWolfeSolver<3>;

  SIGNORINI_REGISTER_TEMPLATE(ContactSolver,
                              FrankWolfeSolver,
                              1,
                              "Frank-Wolfe",
                              "on the dual problems [23], [24] as in the "
                              "paper, doc/theory.md section 4");
} // namespace Signorini
