#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/contact/frank_wolfe_solver.h>

#include <iomanip>
#include <sstream>

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



  namespace
  {
    /**
     * The dual energy that FrankWolfeSolver minimises over the cone y >= 0,
     * with the columns of its Hessian formed on first use.
     *
     * A body held only by the contact: the dual solution must also balance
     * the load on the free rigid motions, C^T y = h. An augmented
     * Lagrangian keeps the cone Frank-Wolfe's only constraint: the dual
     * energy gets mu^T (C^T y - h) + rho/2 |C^T y - h|^2, whose Hessian is
     * S + rho C C^T and whose linear term is d - C (mu - rho h); mu, updated
     * between Frank-Wolfe runs, converges to minus the rigid displacement.
     * Without free rigid motions (r = 0) this is the plain dual energy.
     */
    template <int dim>
    class AugmentedDual
    {
    public:
      /// The dual energy of @p problem with linear term @p d, of largest
      /// entry @p scale; forms at most @p max_columns columns of S, counting
      /// their solves in @p report.
      AugmentedDual(const DiscreteContactProblem<dim>   &problem,
                    const Vector<double>                &d,
                    const double                         scale,
                    const unsigned int                   max_columns,
                    typename ContactSolver<dim>::Report &report)
        : problem(problem)
        , C(problem.rigid_constraint_rows())
        , h(problem.rigid_load())
        , r(problem.n_rigid_motions())
        , d(d)
        , d_augmented(d)
        , mu(r)
        , column(d.size())
        , max_columns(max_columns)
        , report(report)
      {
        if (r > 0)
          {
            double c_max = 0.;
            for (unsigned int i = 0; i < d.size(); ++i)
              for (unsigned int j = 0; j < r; ++j)
                c_max = std::max(c_max, std::abs(C(i, j)));
            // S y ~ d for y ~ |h| / |C|: the penalty of the same size
            rho = scale / (std::max(h.l2_norm(), 1e-300) * c_max);
          }
        update_linear_term();
      }

      /// The linear term d_augmented(mu).
      const Vector<double> &
      linear_term() const
      {
        return d_augmented;
      }

      /// Column @p i of S + rho C C^T (valid until the next call), or
      /// nullptr if forming it would exceed the limit on the columns.
      const Vector<double> *
      hessian_column(const unsigned int i)
      {
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
        column = it->second;
        if (r > 0)
          {
            Vector<double> c_i(r);
            for (unsigned int j = 0; j < r; ++j)
              c_i[j] = rho * C(i, j);
            C.vmult_add(column, c_i);
          }
        return &column;
      }

      /// The columns of S formed so far.
      std::size_t
      n_columns() const
      {
        return columns.size();
      }

      /// Whether @p y balances the load on the free rigid motions,
      /// |C^T y - h| <= @p tolerance |h|. If not, updates mu, the linear
      /// term and with it the gradient @p g = (S + rho C C^T) y -
      /// d_augmented.
      bool
      balance_rigid_motions(const Vector<double> &y,
                            const double          tolerance,
                            Vector<double>       &g)
      {
        if (r == 0)
          return true;
        Vector<double> imbalance(r);
        C.Tvmult(imbalance, y);
        imbalance -= h;
        if (imbalance.l2_norm() <= tolerance * std::max(h.l2_norm(), 1e-300))
          return true;
        const Vector<double> step = multiplier_step(y, imbalance);
        mu += step;
        C.vmult_add(g, step);
        update_linear_term();
        return false;
      }

      /// Adds to @p u the rigid motion -mu that the supports held back.
      void
      add_held_back_motion(LA::Vector &u) const
      {
        if (r == 0)
          return;
        Vector<double> c(mu);
        c *= -1.;
        problem.add_rigid_motion(c, u);
      }

    private:
      void
      update_linear_term()
      {
        Vector<double> shift(r);
        for (unsigned int j = 0; j < r; ++j)
          shift[j] = -mu[j] + rho * h[j];
        d_augmented = d;
        if (r > 0)
          C.vmult_add(d_augmented, shift);
      }

      // The multiplier update: Newton's step on C^T y(mu) = h with the
      // support A of y fixed, where y_A = H_AA^{-1} d_augmented_A(mu), i.e.
      // mu += (C_A^T H_AA^{-1} C_A)^{-1} (C^T y - h); the classical step
      // rho (C^T y - h) of the method of multipliers converges linearly
      // with a rate close to one here.
      Vector<double>
      multiplier_step(const Vector<double> &y, const Vector<double> &imbalance)
      {
        std::vector<unsigned int> support;
        for (unsigned int i = 0; i < y.size(); ++i)
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
            // (formed when it entered the support)
            const Vector<double> *c = hessian_column(support[b]);
            Assert(c != nullptr, ExcInternalError());
            for (unsigned int a = 0; a < n; ++a)
              H(a, b) = (*c)[support[a]];
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
      }

      const DiscreteContactProblem<dim> &problem;
      /// The free rigid motions' rows of the constraints, their load and
      /// number.
      const FullMatrix<double> &C;
      const Vector<double>     &h;
      const unsigned int        r;
      /// The plain and the augmented linear terms.
      const Vector<double> d;
      Vector<double>       d_augmented;
      /// The multiplier of C^T y = h and the penalty.
      Vector<double> mu;
      double         rho = 0.;
      /// S e_i by i, and the last augmented column returned.
      std::map<unsigned int, Vector<double>> columns;
      Vector<double>                         column;
      const unsigned int                     max_columns;
      typename ContactSolver<dim>::Report   &report;
    };
  } // namespace



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
    const double       scale = std::max(max_norm(d), 1e-300);
    AugmentedDual<dim> dual(problem, d, scale, max_columns, report);
    Vector<double>     g(dual.linear_term()); // g = H y - d_augmented
    g *= -1.;

    // (rank 0 prints; every rank takes the same steps)
    ConditionalOStream progress(
      std::cout, Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0);
    Timer  progress_timer;
    double next_progress = progress_interval;
    for (report.iterations = 0; report.iterations < max_iterations;
         ++report.iterations)
      {
        // (the clock is read every 16 steps: a step costs a column update)
        if (progress_interval > 0. && report.iterations % 16 == 0 &&
            progress_timer.wall_time() >= next_progress)
          {
            progress << "   Frank-Wolfe: step " << report.iterations << ", "
                     << dual.n_columns() << " columns, KKT residual "
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
            // free rigid motions, else go on with the updated multiplier
            if (dual.balance_rigid_motions(y, tolerance, g))
              {
                report.converged = true;
                break;
              }
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
            const Vector<double> *column = dual.hessian_column(ray);
            if (column == nullptr)
              {
                std::ostringstream text;
                text << std::setprecision(3)
                     << "stopped by Contact/Frank-Wolfe/Maximum columns = "
                     << max_columns << " after " << report.iterations
                     << " iterations: KKT residual " << report.residual;
                report.failure = text.str();
                break;
              }
            const double t = -g[ray] / (*column)[ray];
            y[ray] += t;
            g.add(t, *column);
          }
        else if (away_rate >= apex_rate)
          {
            // (formed when it entered the support)
            const Vector<double> *formed = dual.hessian_column(away);
            Assert(formed != nullptr, ExcInternalError());
            const Vector<double> &column = *formed;
            double                t      = g[away] / column[away];
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
            Hy += dual.linear_term();
            const double t = std::min(1., (g * y) / (Hy * y));
            y *= (1. - t);
            g.sadd(1. - t, -t, dual.linear_term());
          }
      }

    if (!report.converged && report.failure.empty())
      {
        std::ostringstream text;
        text << std::setprecision(3)
             << "stopped by Contact/Frank-Wolfe/Maximum iterations = "
             << max_iterations << ": KKT residual " << report.residual;
        report.failure = text.str();
      }

    // Displacement of the final multipliers, plus the rigid motion -mu
    // that the supports held back.
    report.linear_iterations += problem.solve_with_dual(y, u);
    ++report.linear_solves;
    dual.add_held_back_motion(u);
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
