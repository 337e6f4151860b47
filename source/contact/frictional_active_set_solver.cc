#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/contact/frictional_active_set_solver.h>
#include <signorini/input_error.h>
#include <signorini/progress.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// What the method needs to know of each constraint row (node of GC).
    template <int dim>
    struct FrictionRows
    {
      /// The dofs of the node, dim per row.
      std::vector<types::global_dof_index> dofs;
      /// The tangential components free to slide: those without Dirichlet
      /// data (a support takes the force of the others, e.g. on a plane of
      /// symmetry).
      std::vector<std::array<bool, dim>> sliding;
      /// Whether a component slides at all.
      std::vector<bool> frictional;
      /// K_ii of the dofs (c_k: the scale that makes f - c t a force
      /// whatever the units).
      Vector<double> stiffness_diagonal;
    };

    template <int dim>
    FrictionRows<dim>
    describe_rows(const DiscreteContactProblem<dim> &problem)
    {
      const ContactBoundary<dim> &boundary = problem.boundary();
      const unsigned int          m        = problem.n_constraints();
      const unsigned int          c_star   = boundary.constrained_component();
      const Tensor<1, dim>        nu       = boundary.direction();
      for (unsigned int c = 0; c < dim; ++c)
        if (c != c_star && nu[c] != 0.)
          throw InputError("Contact/Friction needs Contact/Direction along a "
                           "coordinate axis (the tangential components are "
                           "then the other ones)");
      FrictionRows<dim> rows;
      rows.sliding.resize(m);
      rows.frictional.assign(m, false);
      const auto &constraints = problem.constraints();
      for (unsigned int i = 0; i < m; ++i)
        {
          const auto &node = boundary.node(boundary.multiplier_nodes()[i]);
          for (unsigned int c = 0; c < dim; ++c)
            {
              rows.dofs.push_back(node.dofs[c]);
              rows.sliding[i][c] =
                (c != c_star && !constraints.is_constrained(node.dofs[c]));
              rows.frictional[i] = rows.frictional[i] || rows.sliding[i][c];
            }
        }
      LA::Vector diagonal(problem.load());
      for (const auto i : diagonal.locally_owned_elements())
        diagonal[i] = problem.stiffness().diag_element(i);
      diagonal.compress(VectorOperation::insert);
      rows.stiffness_diagonal = gather(diagonal, rows.dofs);
      return rows;
    }

    /// What one step of the method solves for the sets it is given.
    struct FrictionSystem
    {
      /// The sticking nodes' tangential dofs and where they stick.
      std::vector<std::pair<types::global_dof_index, double>> fixed;
      /// The sliding nodes' nodal forces.
      std::vector<std::pair<types::global_dof_index, double>> forces;
      /// The sliding nodes' springs across their slip direction (3D).
      std::vector<
        std::tuple<types::global_dof_index, types::global_dof_index, double>>
        springs;
    };

    /// The step's system: nodes in contact stick at @p origin or slide under
    /// @p slip_force, with the spring k (I - n n^T), n = slip_force /
    /// |slip_force|, on the slip t - origin (in K, and its part in origin
    /// with the force).
    template <int dim>
    FrictionSystem
    friction_system(const FrictionRows<dim>           &rows,
                    const std::vector<bool>           &active,
                    const std::vector<bool>           &stick,
                    const std::vector<Tensor<1, dim>> &slip_force,
                    const std::vector<double>         &spring,
                    const std::vector<Tensor<1, dim>> &origin)
    {
      FrictionSystem system;
      const auto    &dofs = rows.dofs;
      for (unsigned int i = 0; i < active.size(); ++i)
        if (active[i] && rows.frictional[i])
          for (unsigned int a = 0; a < dim; ++a)
            if (rows.sliding[i][a])
              {
                if (stick[i])
                  {
                    system.fixed.emplace_back(dofs[dim * i + a], origin[i][a]);
                    continue;
                  }
                double     force        = slip_force[i][a];
                const auto norm_squared = slip_force[i].norm_square();
                for (unsigned int b = 0; b < dim; ++b)
                  if (rows.sliding[i][b] && spring[i] > 0. && norm_squared > 0.)
                    {
                      const double value =
                        spring[i] *
                        ((a == b ? 1. : 0.) -
                         slip_force[i][a] * slip_force[i][b] / norm_squared);
                      if (value != 0.)
                        system.springs.emplace_back(dofs[dim * i + a],
                                                    dofs[dim * i + b],
                                                    value);
                      force += value * origin[i][b];
                    }
                system.forces.emplace_back(dofs[dim * i + a], force);
              }
      return system;
    }



    /**
     * How fast the fixed point on the Tresca threshold, s -> mu y(s),
     * contracts at a solution with its @p sets (the sliding nodes' forces
     * and springs among them): the spectral radius of its linearisation J,
     * which moves each sliding node's force along its direction by the
     * change of its bound, to which the normal forces y answer linearly
     * (exactly: the system is linear for given sets). Below 1, I - J is
     * regular and the solution locally unique. The largest modulus of the
     * Ritz values of Arnoldi on J restricted to the sliding nodes, one
     * solve per step, counted in @p report: at least @p min_steps steps,
     * then until the estimate rho_k is safely on one side of 1 (rho_k + 10
     * |rho_k - rho_{k-1}| < 1, or rho_k >= 1), at most @p max_steps (exact
     * once the steps span the sliding nodes); 0 without sliding nodes.
     */
    template <int dim>
    double
    contraction_at_solution(const DiscreteContactProblem<dim>   &problem,
                            const FrictionSets<dim>             &sets,
                            const LA::Vector                    &u,
                            const Vector<double>                &y,
                            const double                         mu,
                            const unsigned int                   min_steps,
                            const unsigned int                   max_steps,
                            typename ContactSolver<dim>::Report &report)
    {
      const FrictionRows<dim>   rows       = describe_rows(problem);
      const auto               &active     = sets.active;
      const auto               &stick      = sets.stick;
      const auto               &slip_force = sets.slip_force;
      std::vector<unsigned int> sliding;
      double                    scale = 0.;
      for (unsigned int i = 0; i < active.size(); ++i)
        if (active[i] && rows.frictional[i] && !stick[i] &&
            slip_force[i].norm() > 0.)
          {
            sliding.push_back(i);
            scale = std::max(scale, slip_force[i].norm());
          }
      const unsigned int n = sliding.size();
      if (n == 0 || mu == 0.)
        return 0.;

      // J v, v on the sliding nodes (applied to scale v, the size of the
      // bounds: the normal forces it changes are then well above the
      // solver's tolerance)
      LA::Vector v_u(u);
      const auto apply = [&](const Vector<double> &v) {
        std::vector<Tensor<1, dim>> perturbed = slip_force;
        for (unsigned int k = 0; k < n; ++k)
          perturbed[sliding[k]] += scale * v[k] /
                                   slip_force[sliding[k]].norm() *
                                   slip_force[sliding[k]];
        const FrictionSystem system = friction_system(
          rows, active, stick, perturbed, sets.spring, sets.origin);
        v_u = u;
        report.linear_iterations += problem.solve_with_friction(
          active, system.fixed, system.forces, system.springs, v_u);
        ++report.linear_solves;
        const Vector<double> next = problem.dual_from_residual(active, v_u);
        Vector<double>       result(n);
        for (unsigned int k = 0; k < n; ++k)
          result[k] = mu * (next[sliding[k]] - y[sliding[k]]) / scale;
        return result;
      };

      // Arnoldi from the direction of the bounds
      const unsigned int          steps = std::min(n, max_steps);
      std::vector<Vector<double>> basis(1, Vector<double>(n));
      for (unsigned int k = 0; k < n; ++k)
        basis[0][k] = slip_force[sliding[k]].norm();
      basis[0] /= basis[0].l2_norm();
      FullMatrix<double> hessenberg(steps + 1, steps);
      // the largest modulus of the Ritz values after @p size steps
      const auto ritz_radius = [&](const unsigned int size) {
        LAPACKFullMatrix<double> ritz(size, size);
        for (unsigned int i = 0; i < size; ++i)
          for (unsigned int j = 0; j < size; ++j)
            ritz(i, j) = hessenberg(i, j);
        ritz.compute_eigenvalues();
        double radius = 0.;
        for (unsigned int i = 0; i < size; ++i)
          radius = std::max(radius, std::abs(ritz.eigenvalue(i)));
        return radius;
      };
      double radius = 0., previous = 0.;
      for (unsigned int j = 0; j < steps; ++j)
        {
          Vector<double> w    = apply(basis[j]);
          const double   norm = w.l2_norm();
          for (unsigned int i = 0; i <= j; ++i)
            {
              hessenberg(i, j) = basis[i] * w;
              w.add(-hessenberg(i, j), basis[i]);
            }
          hessenberg(j + 1, j) = w.l2_norm();
          previous             = radius;
          radius               = ritz_radius(j + 1);
          // (an invariant subspace: its Ritz values are eigenvalues; else
          // they approach the spectrum from either side, slowly where it
          // clusters: 6 steps gave 0.94 for 0.99 on a strip)
          if (hessenberg(j + 1, j) <= 1e-12 * norm ||
              (j + 1 >= min_steps &&
               (radius >= 1. ||
                radius + 100. * std::abs(radius - previous) < 1.)))
            break;
          w /= hessenberg(j + 1, j);
          basis.push_back(w);
        }
      return radius;
    }



    /// Tresca's s_k: the threshold at the node times its area.
    template <int dim>
    std::vector<double>
    tresca_bounds(const FrictionLaw<dim>     &law,
                  const ContactBoundary<dim> &boundary)
    {
      const Vector<double> areas = boundary.nodal_areas();
      const auto          &rows  = boundary.multiplier_nodes();
      std::vector<double>  bounds(rows.size());
      for (unsigned int i = 0; i < rows.size(); ++i)
        {
          bounds[i] =
            law.threshold_at(boundary.node(rows[i]).position) * areas[rows[i]];
        }
      return bounds;
    }
  } // namespace



  template <int dim>
  unsigned int
  FrictionState<dim>::count(const Status s) const
  {
    return std::count(status.begin(), status.end(), s);
  }



  template <int dim>
  Tensor<1, dim>
  FrictionState<dim>::total_force() const
  {
    Tensor<1, dim> total;
    for (const auto &f : force)
      total += f;
    return total;
  }



  template <int dim>
  void
  FrictionalActiveSetSolver<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.declare_entry("Friction solver",
                      "semismooth Newton",
                      Patterns::Selection("semismooth Newton|fixed point"),
                      "Coulomb friction: the active set method with the "
                      "bound mu y lagged by one step (semismooth Newton), "
                      "or the fixed point on the Tresca threshold mu y, each "
                      "Tresca problem solved by that method (a second route "
                      "to the same solution, which says when it does not "
                      "contract). Tresca: the same.");
    prm.declare_entry("Uniqueness check",
                      "true",
                      Patterns::Bool(),
                      "Coulomb friction: estimate how fast the fixed point "
                      "on the Tresca threshold contracts at the solution "
                      "(6 to 50 more linear solves per solve) and refuse the "
                      "solution where it does not (rate >= 1: not shown to "
                      "be locally unique).");
    prm.leave_subsection();
  }



  template <int dim>
  bool
  FrictionalActiveSetSolver<dim>::parse_uniqueness_check(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    const bool check = prm.get_bool("Uniqueness check");
    prm.leave_subsection();
    return check;
  }



  template <int dim>
  typename FrictionalActiveSetSolver<dim>::Method
  FrictionalActiveSetSolver<dim>::parse_method(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    const bool fixed_point = (prm.get("Friction solver") == "fixed point");
    prm.leave_subsection();
    return fixed_point ? Method::fixed_point : Method::semismooth_newton;
  }



  template <int dim>
  FrictionalActiveSetSolver<dim>::FrictionalActiveSetSolver(
    const FrictionLaw<dim> &law,
    const unsigned int      max_iterations,
    const Method            method,
    const double            preconditioner_update_fraction,
    const bool              check_uniqueness)
    : law(law)
    , max_iterations(max_iterations)
    , method(method)
    , preconditioner_update_fraction(preconditioner_update_fraction)
    , check_uniqueness(check_uniqueness)
  {}



  template <int dim>
  std::string
  FrictionalActiveSetSolver<dim>::name(const Method method)
  {
    return method == Method::fixed_point ?
             "frictional active set (fixed point)" :
             "frictional active set (semismooth Newton)";
  }



  template <int dim>
  typename ContactSolver<dim>::Report
  FrictionalActiveSetSolver<dim>::solve(
    const DiscreteContactProblem<dim> &problem,
    LA::Vector                        &u,
    Vector<double>                    &y,
    FrictionState<dim>                &state,
    const std::vector<bool>           &initial_active,
    const FrictionState<dim>          *previous) const
  {
    state.fixed_point = {};
    state.contraction_at_solution.reset();
    if (method == Method::fixed_point &&
        law.type() == FrictionLaw<dim>::Type::coulomb)
      return solve_fixed_point(problem, u, y, state, initial_active, previous);
    FrictionSets<dim> sets;
    auto              report = solve_with_bounds(
      problem, u, y, state, initial_active, previous, nullptr, sets);
    judge_uniqueness(problem, u, y, sets, state, report);
    return report;
  }



  template <int dim>
  void
  FrictionalActiveSetSolver<dim>::judge_uniqueness(
    const DiscreteContactProblem<dim>   &problem,
    const LA::Vector                    &u,
    const Vector<double>                &y,
    const FrictionSets<dim>             &sets,
    FrictionState<dim>                  &state,
    typename ContactSolver<dim>::Report &report) const
  {
    if (!check_uniqueness || !report.converged ||
        law.type() != FrictionLaw<dim>::Type::coulomb)
      return;
    state.contraction_at_solution = contraction_at_solution(
      problem, sets, u, y, law.coefficient(), 6, 50, report);
    if (*state.contraction_at_solution >= 1.)
      {
        std::ostringstream text;
        text << "the fixed point on the Tresca threshold does not contract "
                "at the solution found (rate "
             << std::setprecision(3) << *state.contraction_at_solution
             << " >= 1): at Contact/Friction coefficient = "
             << law.coefficient()
             << " the static Coulomb problem may have several solutions "
                "here, and this one is not shown to be unique";
        report.converged = false;
        report.failure   = text.str();
      }
  }



  template <int dim>
  typename ContactSolver<dim>::Report
  FrictionalActiveSetSolver<dim>::solve_fixed_point(
    const DiscreteContactProblem<dim> &problem,
    LA::Vector                        &u,
    Vector<double>                    &y,
    FrictionState<dim>                &state,
    const std::vector<bool>           &initial_active,
    const FrictionState<dim>          *previous) const
  {
    const unsigned int  m          = problem.n_constraints();
    const double        mu         = law.coefficient();
    const double        load_scale = problem.load().linfty_norm();
    std::vector<double> bounds(m, 0.); // s^0 = 0: frictionless
    std::vector<bool>   active =
      (initial_active.size() == m) ? initial_active : std::vector<bool>(m);
    typename ContactSolver<dim>::Report report;
    FrictionSets<dim>                   sets;
    double previous_change = std::numeric_limits<double>::infinity();
    while (true)
      {
        const auto tresca = solve_with_bounds(
          problem, u, y, state, active, previous, &bounds, sets);
        report.iterations += tresca.iterations;
        report.linear_solves += tresca.linear_solves;
        report.linear_iterations += tresca.linear_iterations;
        report.residual = tresca.residual;
        ++state.fixed_point.tresca_solves;
        if (!tresca.converged)
          {
            report.failure = "the Tresca problem of fixed-point iteration " +
                             std::to_string(state.fixed_point.tresca_solves) +
                             " did not converge";
            return report;
          }
        // s^{j+1} = mu y(s^j), and how much it moved, relative to the
        // forces of the problem (stopping near round-off, or at the linear
        // solver's tolerance where the change stops shrinking)
        double change = 0.;
        for (unsigned int i = 0; i < m; ++i)
          {
            const double next = mu * std::max(y[i], 0.);
            change            = std::max(change, std::abs(next - bounds[i]));
            bounds[i]         = next;
            active[i] =
              (state.status[i] != FrictionState<dim>::Status::separated);
          }
        // (the contraction of the map, from the changes above round-off;
        // the reactions too, for a problem driven by its Dirichlet data)
        const double force_scale = std::max(
          {max_norm(y), load_scale, problem.residual(u).linfty_norm()});
        if (std::isfinite(previous_change) && change > 1e-10 * force_scale)
          state.fixed_point.contraction =
            std::max(state.fixed_point.contraction, change / previous_change);
        // (1e-12, not round-off: where the change crossed 1e-14 depended
        // on the rank count and the units)
        if (change <= 1e-12 * force_scale ||
            (change <= 1e-8 * force_scale && change >= 0.5 * previous_change))
          {
            report.converged = true;
            break;
          }
        if (state.fixed_point.tresca_solves >= max_iterations)
          {
            std::ostringstream text;
            text << "the fixed point on the Tresca threshold did not converge "
                    "in "
                 << max_iterations << " Tresca solves";
            if (state.fixed_point.contraction >= 1.)
              text << ": it does not contract (its changes grew by a "
                      "factor "
                   << std::setprecision(3) << state.fixed_point.contraction
                   << "), so at mu = " << mu
                   << " the Coulomb problem may have several solutions or "
                      "none";
            report.failure = text.str();
            break;
          }
        previous_change = change;
      }
    // the Coulomb bounds of the solution (the checks measure how far it is
    // from the Coulomb law, not from the last Tresca problem)
    for (unsigned int i = 0; i < m; ++i)
      state.bound[i] = mu * std::max(y[i], 0.);
    judge_uniqueness(problem, u, y, sets, state, report);
    return report;
  }



  template <int dim>
  typename ContactSolver<dim>::Report
  FrictionalActiveSetSolver<dim>::solve_with_bounds(
    const DiscreteContactProblem<dim> &problem,
    LA::Vector                        &u,
    Vector<double>                    &y,
    FrictionState<dim>                &state,
    const std::vector<bool>           &initial_active,
    const FrictionState<dim>          *previous,
    const std::vector<double>         *given_bounds,
    FrictionSets<dim>                 &sets) const
  {
    using Status                         = typename FrictionState<dim>::Status;
    const ContactBoundary<dim> &boundary = problem.boundary();
    const unsigned int          m        = problem.n_constraints();
    const unsigned int          c_star   = boundary.constrained_component();
    const FrictionRows<dim>     rows     = describe_rows(problem);
    const auto                 &dofs     = rows.dofs;
    const auto                 &sliding  = rows.sliding;
    const auto                 &frictional         = rows.frictional;
    const auto                 &stiffness_diagonal = rows.stiffness_diagonal;
    const std::vector<double>   tresca_bound =
      (law.type() == FrictionLaw<dim>::Type::tresca) ?
          tresca_bounds(law, boundary) :
          std::vector<double>(m, 0.);
    const auto bound = [&](const unsigned int i) {
      return given_bounds != nullptr ? (*given_bounds)[i] :
             law.type() == FrictionLaw<dim>::Type::coulomb ?
                                       law.coefficient() * std::max(y[i], 0.) :
                                       tresca_bound[i];
    };

    const double load_scale = problem.load().linfty_norm();

    typename ContactSolver<dim>::Report report;
    std::vector<bool>                   active = (initial_active.size() == m) ?
                                                   initial_active :
                                                   std::vector<bool>(m, false);
    // every node in contact starts sticking, with no slip force (on a load
    // step, the elastic predictor: sticking where the previous step left
    // it; starting a node from its previous slip force, that force acts on
    // a body whose load changed, which made the unloading of a slipping
    // strip alternate between slips either way)
    std::vector<bool>           stick(m, true);
    std::vector<Tensor<1, dim>> slip_force(m);
    // and the spring k_k across the slip direction n_k = slip_force / s_k
    std::vector<double> spring(m, 0.);
    // where the node slides from
    std::vector<Tensor<1, dim>> origin(m);
    if (previous != nullptr)
      {
        AssertDimension(previous->displacement.size(), m);
        origin = previous->displacement;
      }
    state.status.assign(m, Status::separated);
    state.force.assign(m, Tensor<1, dim>());
    state.slip.assign(m, Tensor<1, dim>());
    state.displacement.assign(m, Tensor<1, dim>());
    state.accumulated_slip.assign(m, Tensor<1, dim>());
    state.bound.assign(m, 0.);
    // the sets the preconditioner was last built for
    std::vector<bool> preconditioned_active(m, false),
      preconditioned_stick(m, false);
    Progress progress("frictional active set", u.get_mpi_communicator());
    double   previous_change = std::numeric_limits<double>::infinity();

    while (true)
      {
        progress.report(
          [&]() { return "iteration " + std::to_string(report.iterations); });
        const FrictionSystem system =
          friction_system(rows, active, stick, slip_force, spring, origin);
        // (the sticking nodes' tangential dofs are held like the active
        // normal rows: without them in the preconditioner, CG took 4 to 9
        // times the iterations of a frictionless solve)
        unsigned int drift = 0;
        for (unsigned int i = 0; i < m; ++i)
          drift += (active[i] != preconditioned_active[i] ||
                    (active[i] && stick[i] != preconditioned_stick[i])) ?
                     1 :
                     0;
        if (drift > preconditioner_update_fraction * m)
          {
            std::vector<types::global_dof_index> fixed_dofs;
            for (const auto &[dof, value] : system.fixed)
              fixed_dofs.push_back(dof);
            problem.update_preconditioner(active, fixed_dofs);
            preconditioned_active = active;
            preconditioned_stick  = stick;
          }
        report.linear_iterations += problem.solve_with_friction(
          active, system.fixed, system.forces, system.springs, u);
        ++report.linear_solves;
        ++report.iterations;
        y = problem.dual_from_residual(active, u);

        // the tangential forces on the body (K u = F + f: f = -(F - K u))
        // and displacements of the nodes
        // (and the largest force on any dof, the reactions of the Dirichlet
        // data included: the scale of a problem driven by them)
        const LA::Vector     all_forces   = problem.residual(u);
        const double         reaction     = all_forces.linfty_norm();
        const Vector<double> residual     = gather(all_forces, dofs);
        const Vector<double> displacement = gather(u, dofs);
        const Vector<double> slack        = problem.slack(u);
        const double         tol_slack    = 1e-9 * problem.constraint_scale(u);
        const double         tol_y        = 1e-9 * max_norm(y);
        // (the force of a free tangential dof is round-off, not friction)
        double tol_force = std::max({max_norm(y), load_scale, reaction});
        for (unsigned int i = 0; i < m; ++i)
          for (unsigned int c = 0; c < dim; ++c)
            if (c != c_star)
              tol_force = std::max(tol_force, std::abs(residual[dim * i + c]));
        tol_force *= 1e-9;
        std::vector<bool>           next_active(m), next_stick(m, true);
        std::vector<Tensor<1, dim>> next_force(m);
        std::vector<double>         next_spring(m, 0.);
        double                      largest_bound = 0., change = 0.;
        for (unsigned int i = 0; i < m; ++i)
          {
            next_active[i] =
              active[i] ? (y[i] >= -tol_y) : (slack[i] < -tol_slack);
            Tensor<1, dim> force, tangential;
            for (unsigned int c = 0; c < dim; ++c)
              if (sliding[i][c])
                {
                  force[c]      = -residual[dim * i + c];
                  tangential[c] = displacement[dim * i + c];
                }
            const Tensor<1, dim> slip = tangential - origin[i];
            const double         s    = bound(i);
            largest_bound             = std::max(largest_bound, s);
            state.status[i]           = !active[i] ?
                                          Status::separated :
                                          (stick[i] ? Status::stick : Status::slip);
            state.force[i]            = active[i] ? force : Tensor<1, dim>();
            state.slip[i]             = slip;
            state.displacement[i]     = tangential;
            state.accumulated_slip[i] =
              (previous != nullptr ? previous->accumulated_slip[i] :
                                     Tensor<1, dim>()) +
              (state.status[i] == Status::slip ? slip : Tensor<1, dim>());
            state.bound[i] = s;
            if (!next_active[i] || !frictional[i])
              continue;
            double       c_k       = 0.;
            unsigned int n_sliding = 0;
            for (unsigned int c = 0; c < dim; ++c)
              if (sliding[i][c])
                {
                  c_k += stiffness_diagonal[dim * i + c];
                  ++n_sliding;
                }
            c_k /= n_sliding;
            const Tensor<1, dim> xi = force - c_k * slip;
            next_stick[i]           = !(xi.norm() > s + tol_force);
            // a node whose slip would reverse passes through stick first
            // (in 2D, where n is a sign, the plain step let a band of nodes
            // by the stick zone of a Hertz contact reverse at every step,
            // a cycle of period 2)
            if (!next_stick[i] && !stick[i] && active[i] &&
                xi * slip_force[i] < 0.)
              next_stick[i] = true;
            if (!next_stick[i])
              {
                // the semismooth Newton step linearises s xi / |xi|: the
                // force s n along n = xi / |xi|, and across n a spring
                // k = s c / (|xi| - s) on the tangential slip (capped: near
                // |xi| = s it holds the node across n)
                next_force[i]  = s * xi / xi.norm();
                next_spring[i] = std::min(s * c_k / (xi.norm() - s), 1e3 * c_k);
                if (!stick[i] && active[i])
                  change = std::max(change, (next_force[i] - force).norm());
                else
                  change = std::numeric_limits<double>::infinity();
              }
          }
        // (the slip forces converge on to round-off and the linear
        // solver's tolerance, where the change stops shrinking; relative to
        // the forces of the problem, of which the bounds may be a small
        // part)
        const bool   same_sets = (next_active == active && next_stick == stick);
        const double force_scale =
          std::max({largest_bound, max_norm(y), load_scale, reaction});
        // (a Tresca problem of the fixed point has exact slip forces once
        // the sets settle: its change is round-off, which at 1e-14 decided
        // by the rank count; 1e-12 is safely above)
        const double round_off = (given_bounds != nullptr ? 1e-12 : 1e-14);
        if (same_sets &&
            (change <= round_off * force_scale ||
             (change <= 1e-8 * force_scale && change >= 0.5 * previous_change)))
          {
            report.converged = true;
            break;
          }
        previous_change =
          same_sets ? change : std::numeric_limits<double>::infinity();
        if (report.iterations >= max_iterations)
          break;
        active     = next_active;
        stick      = next_stick;
        slip_force = next_force;
        spring     = next_spring;
      }

    sets = {active, stick, slip_force, spring, origin};

    // the relative KKT residual: the normal conditions as
    // ActiveSetSolver's, and the friction cone
    const Vector<double> slack = problem.slack(u);
    const double scale_primal  = std::max(problem.constraint_scale(u), 1e-300);
    const double scale_dual    = std::max(max_norm(y), 1e-300);
    for (unsigned int i = 0; i < m; ++i)
      report.residual =
        std::max({report.residual,
                  -slack[i] / scale_primal,
                  -y[i] / scale_dual,
                  std::abs(y[i] * slack[i]) / (scale_dual * scale_primal),
                  (state.force[i].norm() - state.bound[i]) / scale_dual});
    return report;
  }



  template struct FrictionState<2>;
  template struct FrictionState<3>;
  template class FrictionalActiveSetSolver<2>;
  template class FrictionalActiveSetSolver<3>;
} // namespace Signorini
