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
#include <map>
#include <set>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// The most Arnoldi steps of the uniqueness check, and the most its
    /// least number (Contact/Uniqueness check steps) may be.
    constexpr unsigned int max_uniqueness_steps = 50;
    /// The defaults of Contact/Friction solver, Uniqueness check and
    /// Uniqueness check steps.
    constexpr const char *default_friction_solver  = "semismooth Newton";
    constexpr const char *default_uniqueness_check = "true";
    constexpr const char *default_uniqueness_steps = "2";

    /**
     * What the method needs to know of the condition's rows and the nodes
     * of GC. The friction law acts on each row i like the normal one: on
     * the tangential multiplier lambda_i (the nodal force of the pointwise
     * condition, the nodal value of the tangential traction of the integral
     * one) and the weighted slip w_i = (W (t - origin))_i, whose nodal
     * forces are W^T lambda.
     */
    template <int dim>
    struct FrictionRows
    {
      const ContactCondition<dim> *condition;
      const ContactBoundary<dim>  *boundary;
      unsigned int                 c_star;
      /// The dofs of every node of GC, dim per node.
      std::vector<types::global_dof_index> node_dofs;
      /// The node of GC of each row.
      std::vector<unsigned int> row_node;
      /// The tangential components of a row's node free to slide: those
      /// without Dirichlet data (a support takes the force of the others,
      /// e.g. on a plane of symmetry).
      std::vector<std::array<bool, dim>> sliding;
      /// Whether a component slides at all.
      std::vector<bool> frictional;
      /// W_ii: the multiplier times it is about the nodal force (1 for the
      /// pointwise condition, the node's share of GC for the integral one).
      std::vector<double> weight;
      /// c_i: the mean K_jj of the row's sliding dofs over W_ii^2, the
      /// scale that makes lambda_i - c_i w_i a multiplier whatever the units
      /// and the mesh.
      std::vector<double> scale;

      unsigned int
      n_nodes() const
      {
        return node_dofs.size() / dim;
      }

      types::global_dof_index
      dof(const unsigned int node, const unsigned int c) const
      {
        return node_dofs[dim * node + c];
      }
    };

    template <int dim>
    FrictionRows<dim>
    describe_rows(const DiscreteContactProblem<dim> &problem)
    {
      const ContactBoundary<dim> &boundary = problem.boundary();
      const unsigned int          m        = problem.n_constraints();
      const unsigned int          c_star   = boundary.constrained_component();
      FrictionRows<dim>           rows;
      rows.condition = &problem.condition();
      rows.boundary  = &boundary;
      rows.c_star    = c_star;
      for (unsigned int k = 0; k < boundary.n_nodes(); ++k)
        for (unsigned int c = 0; c < dim; ++c)
          rows.node_dofs.push_back(boundary.node(k).dofs[c]);
      rows.row_node = boundary.multiplier_nodes();
      rows.sliding.resize(m);
      rows.frictional.assign(m, false);
      const auto &constraints = problem.constraints();
      for (unsigned int i = 0; i < m; ++i)
        for (unsigned int c = 0; c < dim; ++c)
          {
            rows.sliding[i][c] =
              (c != c_star &&
               !constraints.is_constrained(rows.dof(rows.row_node[i], c)));
            rows.frictional[i] = rows.frictional[i] || rows.sliding[i][c];
          }
      LA::Vector diagonal(problem.load());
      for (const auto i : diagonal.locally_owned_elements())
        diagonal[i] = problem.stiffness().diag_element(i);
      diagonal.compress(VectorOperation::insert);
      const Vector<double> node_diagonal = gather(diagonal, rows.node_dofs);
      rows.weight.resize(m);
      rows.scale.assign(m, 0.);
      for (unsigned int i = 0; i < m; ++i)
        {
          rows.weight[i]         = rows.condition->row_weight(i);
          unsigned int n_sliding = 0;
          for (unsigned int c = 0; c < dim; ++c)
            if (rows.sliding[i][c])
              {
                rows.scale[i] += node_diagonal[dim * rows.row_node[i] + c];
                ++n_sliding;
              }
          if (n_sliding > 0)
            rows.scale[i] /= n_sliding * rows.weight[i] * rows.weight[i];
        }
      return rows;
    }

    /// What one step of the method solves for the sets it is given.
    struct FrictionSystem
    {
      /// The sticking rows: (W t)_i = (W origin)_i for their sliding
      /// components, and the dofs these constraints are solved for.
      AffineConstraints<double>            stick;
      std::vector<types::global_dof_index> stick_dofs;
      /// The sliding rows' nodal forces.
      std::vector<std::pair<types::global_dof_index, double>> forces;
      /// The sliding rows' springs across their slip direction (3D).
      ElasticitySolver::Springs springs;
      /// The same with the entry of node k and node l put on node k's
      /// diagonal block (the same for the pointwise condition): the
      /// preconditioner's, as K's pattern couples a node's dofs but not
      /// two nodes of a row of W, which may be two edges apart.
      ElasticitySolver::Springs lumped_springs;
    };

    /// The step's system: the rows the law acts on (@p rubbing) stick at
    /// @p origin (per node of GC) or slide under the multiplier
    /// @p slip_force, with the spring
    /// k (I - n n^T), n = slip_force / |slip_force|, on the weighted slip
    /// (W^T k (I - n n^T) W in K, and its part in origin with the forces
    /// W^T slip_force).
    template <int dim>
    FrictionSystem
    friction_system(const FrictionRows<dim>           &rows,
                    const std::vector<bool>           &rubbing,
                    const std::vector<bool>           &stick,
                    const std::vector<Tensor<1, dim>> &slip_force,
                    const std::vector<double>         &spring,
                    const std::vector<Tensor<1, dim>> &origin)
    {
      FrictionSystem     system;
      const unsigned int m = rubbing.size();
      for (unsigned int c = 0; c < dim; ++c)
        {
          std::vector<bool> sticking(m, false);
          bool              any = false;
          for (unsigned int i = 0; i < m; ++i)
            if (rubbing[i] && stick[i] && rows.sliding[i][c])
              {
                sticking[i] = any = true;
                system.stick_dofs.push_back(rows.dof(rows.row_node[i], c));
              }
          if (!any)
            continue;
          Vector<double> origin_c(rows.n_nodes());
          for (unsigned int k = 0; k < origin_c.size(); ++k)
            origin_c[k] = origin[k][c];
          rows.condition->add_component_constraints(
            sticking,
            c,
            rows.condition->constraint_values(origin_c),
            *rows.boundary,
            system.stick);
        }
      for (unsigned int i = 0; i < m; ++i)
        {
          if (!rubbing[i] || !rows.frictional[i] || stick[i])
            continue;
          const auto  &row          = rows.condition->weight_row(i);
          const double norm_squared = slip_force[i].norm_square();
          for (const auto &[k, w_k] : row)
            for (unsigned int a = 0; a < dim; ++a)
              if (rows.sliding[i][a])
                {
                  double force = w_k * slip_force[i][a];
                  if (spring[i] > 0. && norm_squared > 0.)
                    for (const auto &[l, w_l] : row)
                      for (unsigned int b = 0; b < dim; ++b)
                        if (rows.sliding[i][b])
                          {
                            const double value =
                              w_k * w_l * spring[i] *
                              ((a == b ? 1. : 0.) - slip_force[i][a] *
                                                      slip_force[i][b] /
                                                      norm_squared);
                            if (value != 0.)
                              {
                                system.springs.emplace_back(rows.dof(k, a),
                                                            rows.dof(l, b),
                                                            value);
                                system.lumped_springs.emplace_back(
                                  rows.dof(k, a), rows.dof(k, b), value);
                              }
                            force += value * origin[l][b];
                          }
                  system.forces.emplace_back(rows.dof(k, a), force);
                }
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
     * solve per step, counted in @p report: at least @p min_steps steps
     * (6 once rho_k > 1/2), then until the estimate rho_k is on one side of
     * 1 by more than 10 times its last change (|1 - rho_k| > 10 |rho_k -
     * rho_{k-1}|), at most @p max_steps (exact once the steps span the
     * sliding nodes), their number in @p steps_taken; 0 without sliding
     * nodes.
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
                            unsigned int                        &steps_taken,
                            typename ContactSolver<dim>::Report &report)
    {
      steps_taken                          = 0;
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
          active, system.stick, system.forces, system.springs, v_u);
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
          steps_taken          = j + 1;
          // (an invariant subspace: its Ritz values are eigenvalues; else
          // they approach the spectrum from either side, J not being
          // normal: on the strip in full slip at mu = 2 and nu = 0, 0.29,
          // 0.73, 0.93, 0.75, 0.76 for 0.79; and they may hold still
          // away from it, 0.929 after 5 steps for 0.737 on the strip at mu
          // = 2.2, hence 6 steps at least where the rate may decide)
          const unsigned int least =
            (radius > 0.5 ? std::max(min_steps, 6u) : min_steps);
          if (hessenberg(j + 1, j) <= 1e-12 * norm ||
              (j + 1 >= least &&
               std::abs(1. - radius) > 10. * std::abs(radius - previous)))
            break;
          w /= hessenberg(j + 1, j);
          basis.push_back(w);
        }
      return radius;
    }



    /// Tresca's s_i: the threshold at the row's node times its area,
    /// divided by the row sum of W (the bound of a nodal force for the
    /// pointwise condition, of the traction's nodal value for the integral
    /// one, whose row sums are the nodes' areas).
    template <int dim>
    std::vector<double>
    tresca_bounds(const FrictionLaw<dim> &law, const FrictionRows<dim> &rows)
    {
      const Vector<double> areas = rows.boundary->nodal_areas();
      std::vector<double>  bounds(rows.row_node.size());
      for (unsigned int i = 0; i < bounds.size(); ++i)
        {
          const unsigned int k = rows.row_node[i];
          bounds[i] = law.threshold_at(rows.boundary->node(k).position) *
                      areas[k] / rows.condition->row_sum(i);
        }
      return bounds;
    }



    /**
     * From @p all_forces, the forces on the body at @p u (K u = F + f:
     * f = -(F - K u)), for every tangential component of the rows
     * @p rubbing: their tangential multipliers @p multiplier and weighted
     * slips @p weighted_slip from @p origin, and in @p state the nodal
     * forces, the displacements of the nodes and the slips. Returns the
     * largest tangential force on a node of GC.
     */
    template <int dim>
    double
    tangential_fields(const FrictionRows<dim>           &rows,
                      const std::vector<bool>           &rubbing,
                      const LA::Vector                  &all_forces,
                      const LA::Vector                  &u,
                      const std::vector<Tensor<1, dim>> &origin,
                      FrictionState<dim>                &state,
                      std::vector<Tensor<1, dim>>       &multiplier,
                      std::vector<Tensor<1, dim>>       &weighted_slip)
    {
      const unsigned int           m         = rows.row_node.size();
      const unsigned int           n_nodes   = rows.n_nodes();
      const auto                  &sliding   = rows.sliding;
      const ContactCondition<dim> &condition = *rows.condition;
      const Vector<double> residual     = gather(all_forces, rows.node_dofs);
      const Vector<double> displacement = gather(u, rows.node_dofs);
      double               largest      = 0.;
      for (unsigned int c = 0; c < dim; ++c)
        if (c != rows.c_star)
          {
            std::vector<bool> in_contact(m);
            for (unsigned int i = 0; i < m; ++i)
              in_contact[i] = rubbing[i] && sliding[i][c];
            Vector<double> force_c(n_nodes), slip_c(n_nodes);
            for (unsigned int k = 0; k < n_nodes; ++k)
              {
                force_c[k] = -residual[dim * k + c];
                slip_c[k]  = displacement[dim * k + c] - origin[k][c];
                state.displacement[k][c] = displacement[dim * k + c];
                largest = std::max(largest, std::abs(force_c[k]));
              }
            const Vector<double> lambda_c =
              condition.dual_from_residual(in_contact, force_c);
            const Vector<double> nodal_c = condition.nodal_forces(lambda_c);
            const Vector<double> w_c     = condition.constraint_values(slip_c);
            for (unsigned int k = 0; k < n_nodes; ++k)
              state.nodal_force[k][c] = -nodal_c[k];
            for (unsigned int i = 0; i < m; ++i)
              if (sliding[i][c])
                {
                  multiplier[i][c]    = lambda_c[i];
                  weighted_slip[i][c] = w_c[i];
                  state.slip[i][c]    = slip_c[rows.row_node[i]];
                }
          }
      return largest;
    }



    /**
     * The relative KKT residual of the solution @p u, @p y, @p state: the
     * normal conditions as ActiveSetSolver's, and the friction cone
     * (relative to the forces of the problem, @p load_scale, too: Tresca
     * acts without contact, where y = 0).
     */
    template <int dim>
    double
    kkt_residual(const DiscreteContactProblem<dim> &problem,
                 const LA::Vector                  &u,
                 const Vector<double>              &y,
                 const FrictionState<dim>          &state,
                 const double                       load_scale)
    {
      const Vector<double> slack = problem.slack(u);
      const double scale_primal = std::max(problem.constraint_scale(u), 1e-300);
      const double scale_dual   = std::max(max_norm(y), 1e-300);
      double       scale_force  = std::max(scale_dual, load_scale);
      for (unsigned int i = 0; i < y.size(); ++i)
        scale_force = std::max(scale_force, state.bound[i]);
      double residual = 0.;
      for (unsigned int i = 0; i < y.size(); ++i)
        residual =
          std::max({residual,
                    -slack[i] / scale_primal,
                    -y[i] / scale_dual,
                    std::abs(y[i] * slack[i]) / (scale_dual * scale_primal),
                    (state.force[i].norm() - state.bound[i]) / scale_force});
      return residual;
    }
  } // namespace



  template <int dim>
  unsigned int
  FrictionState<dim>::count(const Status s) const
  {
    return std::count(status.begin(), status.end(), s);
  }



  template <int dim>
  void
  FrictionState<dim>::reset(const unsigned int          n_rows,
                            std::vector<Tensor<1, dim>> origin)
  {
    const std::size_t n_nodes = origin.size();
    status.assign(n_rows, Status::separated);
    force.assign(n_rows, Tensor<1, dim>());
    slip.assign(n_rows, Tensor<1, dim>());
    weighted_slip.assign(n_rows, Tensor<1, dim>());
    accumulated_slip.assign(n_rows, Tensor<1, dim>());
    bound.assign(n_rows, 0.);
    displacement.assign(n_nodes, Tensor<1, dim>());
    nodal_force.assign(n_nodes, Tensor<1, dim>());
    this->origin = std::move(origin);
  }



  template <int dim>
  Tensor<1, dim>
  FrictionState<dim>::total_force() const
  {
    Tensor<1, dim> total;
    for (const auto &f : nodal_force)
      total += f;
    return total;
  }



  template <int dim>
  void
  FrictionalActiveSetSolver<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.declare_entry("Friction solver",
                      default_friction_solver,
                      Patterns::Selection("semismooth Newton|fixed point"),
                      "Coulomb friction: the active set method with the "
                      "bound mu y lagged by one step (semismooth Newton; "
                      "where its sets cycle, the fixed point takes over), "
                      "or the fixed point on the Tresca threshold mu y, each "
                      "Tresca problem solved by that method (a second route "
                      "to the same solution, which says when it does not "
                      "contract). Tresca: the same.");
    prm.declare_entry("Uniqueness check",
                      default_uniqueness_check,
                      Patterns::Bool(),
                      "Coulomb friction: estimate how fast the fixed point "
                      "on the Tresca threshold contracts at the solution "
                      "(Uniqueness check steps to " +
                        std::to_string(max_uniqueness_steps) +
                        " more linear solves per "
                        "solve) and refuse the solution where it does not "
                        "(rate >= 1: not shown to be locally unique).");
    prm.declare_entry("Uniqueness check steps",
                      default_uniqueness_steps,
                      Patterns::Integer(1, max_uniqueness_steps),
                      "Coulomb friction: the least number of Arnoldi steps "
                      "(one linear solve each) of the uniqueness check (at "
                      "least 6 for a rate above 1/2); more estimate a small "
                      "rate more closely (exact once they reach the number "
                      "of sliding nodes).");
    prm.leave_subsection();
  }



  template <int dim>
  unsigned int
  FrictionalActiveSetSolver<dim>::parse_uniqueness_check(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    const bool         check = prm.get_bool("Uniqueness check");
    const unsigned int steps = prm.get_integer("Uniqueness check steps");
    prm.leave_subsection();
    return check ? steps : 0;
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
  void
  FrictionalActiveSetSolver<dim>::warn_unused_parameters(
    ParameterHandler       &prm,
    const FrictionLaw<dim> &law)
  {
    prm.enter_subsection("Contact");
    // (as given: a value other than the default is a choice the run would
    // silently ignore)
    const std::string solver = prm.get("Friction solver");
    const bool        check_changed =
      prm.get_bool("Uniqueness check") !=
      (std::string(default_uniqueness_check) == "true");
    const bool steps_changed = prm.get_integer("Uniqueness check steps") !=
                               std::stoi(default_uniqueness_steps);
    const bool check_on = prm.get_bool("Uniqueness check");
    prm.leave_subsection();
    const auto coulomb = FrictionLaw<dim>::Type::coulomb;
    if (!law.enabled() && solver != default_friction_solver)
      warn_once("friction solver",
                "Contact/Friction solver = " + solver +
                  " is not used: Contact/Friction = none",
                MPI_COMM_WORLD);
    if (law.type() != coulomb && (check_changed || steps_changed))
      warn_once("uniqueness check",
                "Contact/Uniqueness check and Uniqueness check steps are not "
                "used: they are Coulomb's, and Contact/Friction = " +
                  law.name(),
                MPI_COMM_WORLD);
    else if (law.type() == coulomb && !check_on && steps_changed)
      warn_once("uniqueness check steps",
                "Contact/Uniqueness check steps is not used: Contact/"
                "Uniqueness check = false",
                MPI_COMM_WORLD);
  }



  template <int dim>
  FrictionalActiveSetSolver<dim>::FrictionalActiveSetSolver(
    const FrictionLaw<dim> &law,
    const unsigned int      max_iterations,
    const Method            method,
    const double            preconditioner_update_fraction,
    const unsigned int      uniqueness_check_steps,
    const double            inexact_tolerance)
    : law(law)
    , max_iterations(max_iterations)
    , method(method)
    , preconditioner_update_fraction(preconditioner_update_fraction)
    , uniqueness_check_steps(uniqueness_check_steps)
    , inexact_tolerance(inexact_tolerance)
  {}



  template <int dim>
  void
  FrictionalActiveSetSolver<dim>::check_applicable(
    const DiscreteContactProblem<dim> &problem)
  {
    const ContactBoundary<dim> &boundary = problem.boundary();
    const unsigned int          c_star   = boundary.constrained_component();
    const Tensor<1, dim>        nu       = boundary.direction();
    for (unsigned int c = 0; c < dim; ++c)
      if (c != c_star && nu[c] != 0.)
        throw InputError("Contact/Friction needs Contact/Direction along a "
                         "coordinate axis (the tangential components are "
                         "then the other ones)");
    if (problem.n_rigid_motions() > 0)
      throw InputError("Contact/Friction: the Dirichlet data leave the body "
                       "free to move; friction on a body held by the contact "
                       "alone is not implemented yet");
  }



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
    const FrictionState<dim>          *previous,
    const FrictionGuess<dim>          *guess) const
  {
    check_applicable(problem);
    state.fixed_point = {};
    state.contraction_at_solution.reset();
    state.contraction_steps = 0;
    if (method == Method::fixed_point &&
        law.type() == FrictionLaw<dim>::Type::coulomb)
      return solve_fixed_point(problem, u, y, state, initial_active, previous);
    FrictionSets<dim> sets;
    auto              report = solve_with_bounds(
      problem, u, y, state, initial_active, previous, nullptr, sets, guess);
    if (!report.converged && sets.cycled && guess != nullptr &&
        !guess->stick.empty())
      {
        // the sets of a coarser mesh led the method into a cycle (the
        // integral condition at mu = 1000 on the block) that a cold start
        // avoids: start again from u = 0, every row out of contact
        const auto guessed = report;
        u                  = 0.;
        report =
          solve_with_bounds(problem, u, y, state, {}, previous, nullptr, sets);
        report.add_counts(guessed);
      }
    if (!report.converged && sets.cycled &&
        law.type() == FrictionLaw<dim>::Type::coulomb)
      {
        // The lagged bound cycles where f -> mu y(f) does not contract at a
        // row (the integral condition on the block at mu = 5 to 100,
        // doc/theory.md section 8). The second route then either converges
        // (mu = 5: a locally unique solution) or says that the map does not
        // contract, so that there may be several solutions or none.
        const auto cycled = report;
        u                 = 0.;
        report = solve_fixed_point(problem, u, y, state, {}, previous);
        report.add_counts(cycled);
        if (!report.converged)
          report.failure = "its sets cycled (" +
                           std::to_string(cycled.iterations) +
                           " iterations), and then " + report.failure;
        // (the fixed point judged the uniqueness of a solution it found)
        return report;
      }
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
    if (uniqueness_check_steps == 0 || !report.converged ||
        law.type() != FrictionLaw<dim>::Type::coulomb)
      return;
    state.contraction_at_solution =
      contraction_at_solution(problem,
                              sets,
                              u,
                              y,
                              law.coefficient(),
                              uniqueness_check_steps,
                              max_uniqueness_steps,
                              state.contraction_steps,
                              report);
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
    const double        load_scale = problem.force_scale();
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
        report.add_counts(tresca);
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
          }
        active = sets.active; // (the next Tresca problem starts from it)
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
    // from the Coulomb law, not from the last Tresca problem), and its
    // statuses: a row out of contact is separated, where the last Tresca
    // problem let it slide under its bound 0
    for (unsigned int i = 0; i < m; ++i)
      {
        state.bound[i] = mu * std::max(y[i], 0.);
        if (!sets.active[i])
          {
            state.status[i]           = FrictionState<dim>::Status::separated;
            state.accumulated_slip[i] = previous != nullptr ?
                                          previous->accumulated_slip[i] :
                                          Tensor<1, dim>();
          }
      }
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
    FrictionSets<dim>                 &sets,
    const FrictionGuess<dim>          *guess) const
  {
    using Status                      = typename FrictionState<dim>::Status;
    const unsigned int        m       = problem.n_constraints();
    const FrictionRows<dim>   rows    = describe_rows(problem);
    const unsigned int        n_nodes = rows.n_nodes();
    const std::vector<double> tresca_bound =
      (law.type() == FrictionLaw<dim>::Type::tresca) ?
        tresca_bounds(law, rows) :
        std::vector<double>(m, 0.);
    const auto bound = [&](const unsigned int i) {
      return given_bounds != nullptr ? (*given_bounds)[i] :
             law.type() == FrictionLaw<dim>::Type::coulomb ?
                                       law.coefficient() * std::max(y[i], 0.) :
                                       tresca_bound[i];
    };

    const double load_scale = problem.force_scale();
    // the rows the law acts on: those in contact for Coulomb, and all of GC,
    // in contact or not, for a Tresca problem (its own bounds, or the fixed
    // point's mu y of the previous iterate, zero where it separated): the
    // classical convex problem, whose friction term int s |u_t| has a
    // unique minimiser (the law at the rows in contact only may have no
    // solution: a block sheared by Dirichlet data, doc/theory.md)
    const bool everywhere =
      given_bounds != nullptr || law.type() == FrictionLaw<dim>::Type::tresca;
    const auto law_acts = [everywhere](const std::vector<bool> &in_contact) {
      std::vector<bool> rubbing(in_contact);
      if (everywhere)
        rubbing.assign(rubbing.size(), true);
      return rubbing;
    };

    typename ContactSolver<dim>::Report report;
    std::vector<bool>                   active = (initial_active.size() == m) ?
                                                   initial_active :
                                                   std::vector<bool>(m, false);
    // every row in contact starts sticking, with no slip force (on a load
    // step, the elastic predictor: sticking where the previous step left
    // it; starting a row from its previous slip force, that force acts on
    // a body whose load changed, which made the unloading of a slipping
    // strip alternate between slips either way)
    std::vector<bool>           stick(m, true);
    std::vector<Tensor<1, dim>> slip_force(m);
    // (or, in a static problem, from a guess of the sets: those of a
    // coarser mesh)
    const bool guessed =
      (guess != nullptr && previous == nullptr && guess->stick.size() == m &&
       guess->slip_force.size() == m);
    if (guessed)
      {
        stick      = guess->stick;
        slip_force = guess->slip_force;
      }
    // how often exact steps left each pair of sets: the method gives up
    // on a cycle, when they leave a pair for the second time from a guess,
    // the third time from a cold start
    std::map<std::pair<std::vector<bool>, std::vector<bool>>, unsigned int>
                       left_exactly;
    const unsigned int cycle_leaves = (guessed ? 2 : 3);
    // and the spring k_i across the slip direction n_i = slip_force / s_i
    std::vector<double> spring(m, 0.);
    // where the nodes slide from
    std::vector<Tensor<1, dim>> origin(n_nodes);
    if (previous != nullptr)
      {
        AssertDimension(previous->displacement.size(), n_nodes);
        origin = previous->displacement;
      }
    state.reset(m, origin);
    // the sets the preconditioner was last built for
    std::vector<bool> preconditioned_active(m, false),
      preconditioned_stick(m, false);
    std::vector<double> preconditioned_spring(m, 0.);
    Progress progress("frictional active set", u.get_mpi_communicator());
    double   previous_change = std::numeric_limits<double>::infinity();
    // while the sets change, inexact solves (as ActiveSetSolver); once they
    // hold, or a pair of sets repeats (inexact solves may cycle), every
    // solve at the linear solver's tolerance, and only these converge
    // (without rows the first solve is the last)
    bool exact  = (inexact_tolerance == 0. || m == 0);
    bool cycled = false;
    std::set<std::pair<std::vector<bool>, std::vector<bool>>> visited;

    while (true)
      {
        progress.report(
          [&]() { return "iteration " + std::to_string(report.iterations); });
        const std::vector<bool> rubbing = law_acts(active);
        const FrictionSystem    system =
          friction_system(rows, rubbing, stick, slip_force, spring, origin);
        // (the sticking rows' tangential dofs are held like the active
        // normal rows: without them in the preconditioner, CG took 4 to 9
        // times the iterations of a frictionless solve; and the sliding
        // rows' springs are added: without them, the 3D block at 315k DoFs
        // took 287 CG iterations instead of 90. The drift counts dofs, each
        // a low-rank error of the preconditioner: a row's normal dof when
        // its contact changed, its tangential ones when its stick state
        // changed or its spring by more than a factor 2; counting rows, the
        // 3D block at 1.24M DoFs took 294 CG iterations instead of 130.)
        unsigned int drift = 0;
        for (unsigned int i = 0; i < m; ++i)
          {
            drift += (active[i] != preconditioned_active[i]) ? 1 : 0;
            if ((rubbing[i] && stick[i] != preconditioned_stick[i]) ||
                std::abs(spring[i] - preconditioned_spring[i]) >
                  0.5 * std::max(
                          {spring[i], preconditioned_spring[i], rows.scale[i]}))
              for (unsigned int c = 0; c < dim; ++c)
                drift += rows.sliding[i][c] ? 1 : 0;
          }
        if (drift > preconditioner_update_fraction * m)
          {
            problem.update_preconditioner(active,
                                          system.stick_dofs,
                                          system.lumped_springs);
            preconditioned_active = active;
            preconditioned_stick  = stick;
            preconditioned_spring = spring;
          }
        const bool solved_exactly = exact;
        report.linear_iterations +=
          problem.solve_with_friction(active,
                                      system.stick,
                                      system.forces,
                                      system.springs,
                                      u,
                                      exact ? 0. : inexact_tolerance);
        ++report.linear_solves;
        ++report.iterations;
        y = problem.dual_from_residual(active, u);

        // (and the largest force on any dof, the reactions of the Dirichlet
        // data included: the scale of a problem driven by them)
        const LA::Vector            all_forces = problem.residual(u);
        const double                reaction   = all_forces.linfty_norm();
        std::vector<Tensor<1, dim>> multiplier(m), weighted_slip(m);
        // (the force of a free tangential dof is round-off, not friction)
        double tol_force = std::max({max_norm(y),
                                     load_scale,
                                     reaction,
                                     tangential_fields(rows,
                                                       rubbing,
                                                       all_forces,
                                                       u,
                                                       origin,
                                                       state,
                                                       multiplier,
                                                       weighted_slip)});
        tol_force *= 1e-9;
        const Vector<double> slack     = problem.slack(u);
        const double         tol_slack = 1e-9 * problem.constraint_scale(u);
        const double         tol_y     = 1e-9 * max_norm(y);
        std::vector<bool>    next_active(m), next_stick(m, true);
        for (unsigned int i = 0; i < m; ++i)
          next_active[i] =
            active[i] ? (y[i] >= -tol_y) : (slack[i] < -tol_slack);
        const std::vector<bool>     next_rubbing = law_acts(next_active);
        std::vector<Tensor<1, dim>> next_force(m);
        std::vector<double>         next_spring(m, 0.);
        double                      largest_bound = 0., change = 0.;
        for (unsigned int i = 0; i < m; ++i)
          {
            const Tensor<1, dim> &force  = multiplier[i];
            const Tensor<1, dim> &slip   = weighted_slip[i];
            const double          weight = rows.weight[i];
            const double          s      = bound(i);
            largest_bound                = std::max(largest_bound, s * weight);
            state.status[i]              = !rubbing[i] ?
                                             Status::separated :
                                             (stick[i] ? Status::stick : Status::slip);
            state.force[i]               = force;
            state.weighted_slip[i]       = slip;
            state.accumulated_slip[i] =
              (previous != nullptr ? previous->accumulated_slip[i] :
                                     Tensor<1, dim>()) +
              (state.status[i] == Status::slip ? state.slip[i] :
                                                 Tensor<1, dim>());
            state.bound[i] = s;
            if (!next_rubbing[i] || !rows.frictional[i])
              continue;
            const double         c_i = rows.scale[i];
            const Tensor<1, dim> xi  = force - c_i * slip;
            next_stick[i]            = !(xi.norm() > s + tol_force / weight);
            // a row whose slip would reverse passes through stick first
            // (in 2D, where n is a sign, the plain step let a band of nodes
            // by the stick zone of a Hertz contact reverse at every step,
            // a cycle of period 2)
            if (!next_stick[i] && !stick[i] && rubbing[i] &&
                xi * slip_force[i] < 0.)
              next_stick[i] = true;
            if (!next_stick[i])
              {
                // the semismooth Newton step linearises s xi / |xi|: the
                // multiplier s n along n = xi / |xi|, and across n a spring
                // k = s c / (|xi| - s) on the weighted slip (capped: near
                // |xi| = s it holds the row across n)
                next_force[i]  = s * xi / xi.norm();
                next_spring[i] = std::min(s * c_i / (xi.norm() - s), 1e3 * c_i);
                if (!stick[i] && rubbing[i])
                  change =
                    std::max(change, (next_force[i] - force).norm() * weight);
                else
                  change = std::numeric_limits<double>::infinity();
              }
          }
        // (the slip forces converge on to 1e-12 and the linear solver's
        // tolerance, where the change stops shrinking; as nodal forces,
        // W_ii times the multipliers, relative to the forces of the
        // problem, of which the bounds may be a small part)
        const bool same_sets = (next_active == active && next_stick == stick);
        double     normal_force = 0.;
        for (unsigned int i = 0; i < m; ++i)
          normal_force =
            std::max(normal_force, std::abs(y[i]) * rows.weight[i]);
        const double force_scale =
          std::max({largest_bound, normal_force, load_scale, reaction});
        // (1e-12, not round-off: at 1e-14 the last step or two were
        // round-off whose stagnation test decided by the rank count, in a
        // Tresca problem of the fixed point, whose slip forces are exact
        // once the sets settle, and on the Coulomb block started from a
        // coarser mesh's sets)
        if (solved_exactly && same_sets &&
            (change <= 1e-12 * force_scale ||
             (change <= 1e-8 * force_scale && change >= 0.5 * previous_change)))
          {
            report.converged = true;
            break;
          }
        previous_change = (solved_exactly && same_sets) ?
                            change :
                            std::numeric_limits<double>::infinity();
        if (!exact &&
            (same_sets || !visited.emplace(next_active, next_stick).second))
          exact = true;
        if (solved_exactly && !same_sets &&
            ++left_exactly[{active, stick}] >= cycle_leaves)
          {
            cycled         = true;
            report.failure = "its sets cycled (" +
                             std::to_string(report.iterations) + " iterations)";
            break;
          }
        if (report.iterations >= max_iterations)
          break;
        active     = next_active;
        stick      = next_stick;
        slip_force = next_force;
        spring     = next_spring;
      }

    sets = {active, stick, slip_force, spring, origin, cycled};

    report.residual = kkt_residual(problem, u, y, state, load_scale);
    return report;
  }



  template struct FrictionState<2>;
  template struct FrictionState<3>;
  template class FrictionalActiveSetSolver<2>;
  template class FrictionalActiveSetSolver<3>;
} // namespace Signorini
