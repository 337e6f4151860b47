#include <deal.II/base/mpi.h>

#include <signorini/contact/frictional_active_set_solver.h>
#include <signorini/contact/solution_checks.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace Signorini
{
  std::pair<std::string, double>
  SolutionChecks::largest() const
  {
    std::pair<std::string, double> worst{"", -1.};
    for (const auto &[name, value] :
         {std::make_pair("feasibility", feasibility),
          std::make_pair("multiplier sign", multiplier_sign),
          std::make_pair("complementarity", complementarity),
          std::make_pair("residual", residual),
          std::make_pair("resultant", resultant),
          std::make_pair("friction bound", friction_bound),
          std::make_pair("stick", stick),
          std::make_pair("slip", slip)})
      {
        if (std::isnan(value))
          return {name, value};
        if (value > worst.second)
          worst = {name, value};
      }
    return worst;
  }



  template <int dim>
  SolutionChecks
  check_solution(const DiscreteContactProblem<dim> &problem,
                 const LA::Vector                  &u,
                 const Vector<double>              &y,
                 const AffineConstraints<double>   &dirichlet_constraints,
                 const std::vector<Point<dim>>     &support_points,
                 const std::vector<unsigned int>   &dof_component,
                 const std::vector<std::pair<types::global_dof_index, double>>
                   &friction_forces)
  {
    SolutionChecks checks;

    // complementarity conditions
    const Vector<double> slack = problem.slack(u);
    const double scale_primal  = std::max(problem.constraint_scale(u), 1e-300);
    const double scale_dual    = std::max(max_norm(y), 1e-300);
    for (unsigned int i = 0; i < y.size(); ++i)
      {
        checks.feasibility =
          std::max(checks.feasibility, -slack[i] / scale_primal);
        checks.multiplier_sign =
          std::max(checks.multiplier_sign, -y[i] / scale_dual);
        checks.complementarity =
          std::max(checks.complementarity,
                   std::abs(y[i] * slack[i]) / (scale_primal * scale_dual));
      }

    // contact forces f_c = -B^T y as a dof vector
    LA::Vector contact_forces(problem.load());
    contact_forces = 0.;
    if (y.size() > 0)
      problem.boundary().add_normal_forces(problem.condition().nodal_forces(y),
                                           contact_forces);
    for (const auto &[dof, value] : friction_forces)
      if (contact_forces.locally_owned_elements().is_element(dof))
        contact_forces[dof] += value;
    contact_forces.compress(VectorOperation::add);

    // r = F - K u (hanging rows condensed); the unbalanced force at a dof
    // free of Dirichlet data is r + f_c, at a Dirichlet dof -(r + f_c) is
    // the reaction.
    LA::Vector imbalance = problem.residual(u);
    imbalance += contact_forces;
    LA::Vector applied(problem.load());
    applied += contact_forces;
    // the scale of the residual: the largest applied force (a load or a
    // contact force: not their sum, which vanishes where the foundation
    // carries the load of a node that nothing else holds), or, when the
    // loads vanish or are small (a rigid motion imposed by Dirichlet data),
    // the forces K_ii |u_D,i| the imposed displacements exert on their own
    // (their sum likewise for the resultant)
    double applied_scale = 0., imposed_scale = 0., imposed_sum = 0.;
    double load_sum                       = 0.; // sum of |forces|
    const AffineConstraints<double> &all  = problem.constraints();
    const LA::Vector                &load = problem.load();
    for (const auto i : u.locally_owned_elements())
      if (!all.is_constrained(i))
        applied_scale = std::max(
          {applied_scale, std::abs(load[i]), std::abs(contact_forces[i])});
      else if (dirichlet_constraints.is_inhomogeneously_constrained(i))
        {
          const double force =
            std::abs(problem.stiffness().diag_element(i) *
                     dirichlet_constraints.get_inhomogeneity(i));
          imposed_scale = std::max(imposed_scale, force);
          imposed_sum += force;
        }
    // the bounding box of the nodes
    const MPI_Comm comm  = u.get_mpi_communicator();
    Point<dim>     lower = support_points[0], upper = support_points[0];
    for (const auto i : u.locally_owned_elements())
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d] = std::min(lower[d], support_points[i][d]);
          upper[d] = std::max(upper[d], support_points[i][d]);
        }
    for (unsigned int d = 0; d < dim; ++d)
      {
        lower[d] = Utilities::MPI::min(lower[d], comm);
        upper[d] = Utilities::MPI::max(upper[d], comm);
      }
    const double     diameter = (upper - lower).norm();
    const Point<dim> center   = 0.5 * (lower + upper);
    // the moment about the centre of the box in each coordinate plane
    // (a, b): one in 2D (the plane (x, y)), three in 3D (the components of
    // (x - center) cross f); about the origin, the round-off of x cross f
    // grows with the distance of the body from it (a mesh shifted by 1e10
    // its size failed the check at 1e-6)
    static constexpr unsigned int n_planes     = dim * (dim - 1) / 2;
    static constexpr unsigned int planes[3][2] = {{0, 1}, {1, 2}, {0, 2}};
    Tensor<1, dim>                force;
    std::array<double, n_planes>  moment{};
    for (const auto i : u.locally_owned_elements())
      {
        const Tensor<1, dim> x = support_points[i] - center;
        double               f = applied[i];
        // (the forces one by one: a load and a contact force or reaction
        // that cancel at a dof still count)
        load_sum += std::abs(load[i]) + std::abs(contact_forces[i]);
        if (dirichlet_constraints.is_constrained(i))
          {
            f -= imbalance[i]; // add the reaction
            load_sum += std::abs(imbalance[i]);
          }
        else if (!all.is_constrained(i))
          checks.residual = std::max(checks.residual, std::abs(imbalance[i]));
        const unsigned int c = dof_component[i];
        force[c] += f;
        for (unsigned int p = 0; p < n_planes; ++p)
          {
            const unsigned int a = planes[p][0], b = planes[p][1];
            if (c == a)
              moment[p] += -x[b] * f;
            else if (c == b)
              moment[p] += x[a] * f;
          }
      }
    // (each rank summed over the dofs it owns)
    applied_scale   = Utilities::MPI::max(applied_scale, comm);
    imposed_scale   = Utilities::MPI::max(imposed_scale, comm);
    imposed_sum     = Utilities::MPI::sum(imposed_sum, comm);
    checks.residual = Utilities::MPI::max(checks.residual, comm);
    load_sum        = Utilities::MPI::sum(load_sum, comm);
    force           = Utilities::MPI::sum(force, comm);
    for (double &m : moment)
      m = Utilities::MPI::sum(m, comm);
    checks.force_scale = std::max(applied_scale, imposed_scale);
    checks.residual /=
      std::max(checks.force_scale, std::numeric_limits<double>::min());
    // the largest term, NaN if any is NaN
    double     largest = 0.;
    const auto include = [&largest](const double value) {
      if (!std::isnan(largest) && !(value <= largest))
        largest = value;
    };
    for (unsigned int d = 0; d < dim; ++d)
      include(std::abs(force[d]));
    for (const double m : moment)
      include(std::abs(m) / diameter);
    checks.resultant =
      largest /
      std::max({load_sum, imposed_sum, std::numeric_limits<double>::min()});
    return checks;
  }

  template <int dim>
  void
  check_friction(const FrictionState<dim> &state,
                 const double              scale_primal,
                 const double              scale_dual,
                 SolutionChecks           &checks)
  {
    using Status = typename FrictionState<dim>::Status;
    // (the forces relative to the tangential forces carried, the normal
    // forces, or the forces of the problem when these vanish: mu = 0, a
    // zero Tresca threshold, no contact; not to the bounds, of which a
    // huge one at a sticking node would hide a violation at another)
    double scale_force = std::max(scale_dual, checks.force_scale);
    for (const auto &f : state.force)
      scale_force = std::max(scale_force, f.norm());
    scale_force = std::max(scale_force, std::numeric_limits<double>::min());
    const double scale_slip =
      std::max(scale_primal, std::numeric_limits<double>::min());
    for (unsigned int i = 0; i < state.status.size(); ++i)
      {
        const double force = state.force[i].norm();
        checks.friction_bound =
          std::max(checks.friction_bound,
                   (force - state.bound[i]) / scale_force);
        // (the law's slip: weighted like the normal rows)
        const Tensor<1, dim> &w    = state.weighted_slip[i];
        const double          slip = w.norm();
        if (state.status[i] == Status::stick)
          checks.stick = std::max(checks.stick, slip / scale_slip);
        else if (state.status[i] == Status::slip && slip > 0.)
          checks.slip =
            std::max(checks.slip,
                     (state.force[i] + state.bound[i] * w / slip).norm() /
                       scale_force);
      }
  }



  template SolutionChecks
  check_solution<2>(
    const DiscreteContactProblem<2> &,
    const LA::Vector &,
    const Vector<double> &,
    const AffineConstraints<double> &,
    const std::vector<Point<2>> &,
    const std::vector<unsigned int> &,
    const std::vector<std::pair<types::global_dof_index, double>> &);
  template SolutionChecks
  check_solution<3>(
    const DiscreteContactProblem<3> &,
    const LA::Vector &,
    const Vector<double> &,
    const AffineConstraints<double> &,
    const std::vector<Point<3>> &,
    const std::vector<unsigned int> &,
    const std::vector<std::pair<types::global_dof_index, double>> &);
  template void
  check_friction<2>(const FrictionState<2> &,
                    const double,
                    const double,
                    SolutionChecks &);
  template void
  check_friction<3>(const FrictionState<3> &,
                    const double,
                    const double,
                    SolutionChecks &);
} // namespace Signorini
