#ifndef signorini_contact_solution_checks_h
#define signorini_contact_solution_checks_h

#include <deal.II/base/point.h>

#include <deal.II/lac/vector.h>

#include <signorini/contact/discrete_problem.h>

#include <string>
#include <utility>
#include <vector>

namespace Signorini
{
  /**
   * Independent checks of a computed contact solution (u, y), all relative:
   * - feasibility: max (B u - b)_+ (pointwise: q_N <= G; integral:
   *   M q_N <= ghat), over the scale of B u;
   * - multiplier_sign: max (y)_- over max |y| (Gamma <= 0, or Lambda <= 0);
   * - complementarity: max |y_i (b - B u)_i| over both scales;
   * - residual: max over dofs free of Dirichlet data of |F + f_c - K u|, f_c
   *   the contact forces -B^T y, over max |F + f_c| or, if larger, the
   *   largest force K_ii |u_D,i| of the imposed displacements (the scale
   *   of a problem loaded only by them, such as a rigid translation);
   * - resultant: global equilibrium of applied load, contact forces and
   *   Dirichlet reactions (taken as the residual at Dirichlet dofs): the
   *   largest of the force components and of the moment (divided by the
   *   diameter; in 3D of the three components of the moment), over the sum
   *   of the magnitudes of all these nodal forces or, if larger, that of
   *   the forces K_ii |u_D,i|.
   */
  struct SolutionChecks
  {
    double feasibility     = 0.;
    double multiplier_sign = 0.;
    double complementarity = 0.;
    double residual        = 0.;
    double resultant       = 0.;
    /// Friction: max (|f_k| - s_k) (the cone or the Tresca disc) relative
    /// to the largest tangential force carried, normal force or force of
    /// the problem (not to the bounds: a huge unreached one hid the rest).
    double friction_bound = 0.;
    /// Friction: the largest slip of a sticking node, relative to the
    /// constraint scale.
    double stick = 0.;
    /// Friction: max |f_k + s_k t_k / |t_k|| over the sliding nodes (the
    /// force at the bound, opposing the slip t_k), relative as
    /// friction_bound.
    double slip = 0.;

    /// Not a check: the scale of the residual, the largest applied force
    /// (contact forces included) or K_ii |u_D,i| of the imposed
    /// displacements (the forces scale of check_friction()).
    double force_scale = 0.;

    /// The largest check and its name (a NaN check counts as the largest).
    std::pair<std::string, double>
    largest() const;
  };

  /**
   * @p support_points and @p dof_component give the position and the
   * component of every dof; @p dirichlet_constraints identify the supports.
   */
  template <int dim>
  SolutionChecks
  check_solution(const DiscreteContactProblem<dim> &problem,
                 const LA::Vector                  &u,
                 const Vector<double>              &y,
                 const AffineConstraints<double>   &dirichlet_constraints,
                 const std::vector<Point<dim>>     &support_points,
                 const std::vector<unsigned int>   &dof_component,
                 const std::vector<std::pair<types::global_dof_index, double>>
                   &friction_forces = {});

  template <int dim>
  struct FrictionState;

  /// The friction checks of @p state into @p checks (@p scale_primal: the
  /// scale of the displacements, DiscreteContactProblem::constraint_scale();
  /// @p scale_dual: that of the normal forces, max y).
  template <int dim>
  void
  check_friction(const FrictionState<dim> &state,
                 const double              scale_primal,
                 const double              scale_dual,
                 SolutionChecks           &checks);
} // namespace Signorini

#endif
