#ifndef signorini_contact_frictional_active_set_solver_h
#define signorini_contact_frictional_active_set_solver_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>

#include <signorini/contact/friction_law.h>
#include <signorini/contact/solver.h>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace Signorini
{
  /**
   * The frictional state of the contact nodes: one entry per constraint row
   * (multiplier node) of the condition, or per node of GC where said. The
   * law holds between the row's tangential multiplier and weighted slip:
   * for the pointwise condition they are the node's tangential force and
   * slip, for the integral one the nodal value of the tangential traction
   * and the slip weighted like the normal rows, (M (t - origin))_i.
   */
  template <int dim>
  struct FrictionState
  {
    enum class Status : unsigned char
    {
      separated,
      stick,
      slip
    };

    std::vector<Status> status;
    /// The tangential multiplier: the tangential force the foundation
    /// exerts on the body (its nodal value, a traction, for the integral
    /// condition).
    std::vector<Tensor<1, dim>> force;
    /// Per node of GC: the tangential nodal forces, W^T force.
    std::vector<Tensor<1, dim>> nodal_force;
    /// The slip of the row's node: the tangential displacement since the
    /// previous load step (the whole tangential displacement in a static
    /// problem, which starts from the unloaded state).
    std::vector<Tensor<1, dim>> slip;
    /// The weighted slip (W slip)_i, on which the law acts (the slip for
    /// the pointwise condition).
    std::vector<Tensor<1, dim>> weighted_slip;
    /// Per node of GC: the tangential displacement.
    std::vector<Tensor<1, dim>> displacement;
    /// Per node of GC: where it slides from (the previous load step's
    /// tangential displacement; zero in a static problem).
    std::vector<Tensor<1, dim>> origin;
    /// The slip accumulated along the load path: the sum of the slips of
    /// the steps in which the node slid (the slip itself in a static
    /// problem).
    std::vector<Tensor<1, dim>> accumulated_slip;
    /// The bound of |force|: mu times the normal multiplier (Coulomb), or
    /// the threshold times the node's area (Tresca; the threshold itself
    /// for the integral condition).
    std::vector<double> bound;

    unsigned int
    count(const Status s) const;

    /// The fields of the rows and nodes cleared: each of the @p n_rows rows
    /// separated, without force, slip or bound, each node of GC without
    /// displacement or force, sliding from @p origin (the fixed point's and
    /// the uniqueness check's figures are kept).
    void
    reset(const unsigned int n_rows, std::vector<Tensor<1, dim>> origin);

    /// sum_k nodal_force_k
    Tensor<1, dim>
    total_force() const;

    /// The fixed point on the Tresca threshold (Friction solver = fixed
    /// point, Coulomb): its Tresca solves and its contraction, the largest
    /// ratio of two successive changes of the bounds above round-off (0
    /// before two).
    struct FixedPoint
    {
      unsigned int tresca_solves = 0;
      double       contraction   = 0.;
    } fixed_point;

    /// Coulomb (Contact/Uniqueness check): the contraction of the fixed
    /// point on the Tresca threshold at the solution (0 without sliding
    /// nodes). Below 1 the solution is locally unique.
    std::optional<double> contraction_at_solution;
    /// The Arnoldi steps (linear solves) behind contraction_at_solution:
    /// the estimate is exact once they reach the number of sliding nodes.
    unsigned int contraction_steps = 0;
  };

  /**
   * Where the frictional active set method may start (a coarser mesh's
   * solution): per row, whether it sticks, and the tangential multiplier a
   * sliding row slides under.
   */
  template <int dim>
  struct FrictionGuess
  {
    std::vector<bool>           stick;
    std::vector<Tensor<1, dim>> slip_force;
  };



  /**
   * The sets of the frictional active set method where it stopped, with the
   * sliding nodes' forces and springs and where the nodes slide from: the
   * linear system of its last step.
   */
  template <int dim>
  struct FrictionSets
  {
    std::vector<bool>           active;
    std::vector<bool>           stick;
    std::vector<Tensor<1, dim>> slip_force;
    std::vector<double>         spring;
    /// Per node of GC.
    std::vector<Tensor<1, dim>> origin;
    /// Whether the method stopped because its exact steps kept returning
    /// to sets they had left (a cycle).
    bool cycled = false;
  };



  /**
   * Primal-dual active set method for friction (Hueber, Stadler and
   * Wohlmuth, SIAM J. Sci. Comput. 30 (2008); doc/theory.md section 8) on
   * either condition (written here for the pointwise one: for the integral
   * one read the row's multiplier for f_k, its weighted slip for t_k, and
   * c_k over W_kk^2), with the contact direction along a coordinate
   * axis (the other components are the tangential ones; a tangential
   * component with Dirichlet data does not slide). The normal rows follow
   * ActiveSetSolver's rule. Friction is the fixed point
   *   f_k = P_s(xi_k),  xi_k = f_k - c_k t_k
   * (f_k the tangential force on node k, t_k its tangential displacement,
   * P_s the projection onto the disc |f| <= s_k, c_k > 0 any scale: here
   * K_ii of its tangential dofs; t_k the slip since the previous load step).
   * The law acts on the nodes in contact (Coulomb; for Tresca on every
   * node of GC, the classical convex problem).
   * Such a node sticks (t_k = 0 is imposed) when |xi_k| <= s_k; otherwise
   * it slides, and the semismooth Newton step linearises s xi / |xi|: the
   * prescribed force s_k n_k along n_k = xi_k / |xi_k|, and across n_k a spring
   * s_k c_k / (|xi_k| - s_k) on t_k (none in 2D, where n_k is a sign). A node
   * entering contact takes the same rule (its force is zero: it sticks unless
   * it moved), and a sliding node whose direction would reverse sticks for
   * one step (doc/theory.md section 8). Each step is one symmetric positive
   * definite elasticity solve (stick: constraints, slip: nodal forces and
   * springs), inexact while the sets change (ActiveSetSolver's Inexact
   * tolerance), exact once they hold or repeat. The Coulomb bound s_k =
   * mu y_k is that of the previous step; the method stops, on an exact
   * step, when the sets repeat and the slip forces have converged (they
   * change by at most 1e-12 of the problem's forces, or stop shrinking
   * below 1e-8 of them: the linear solver's tolerance). Where its exact
   * steps cycle through sets, a Coulomb problem goes to the fixed point
   * on the Tresca threshold, which converges or says that it does not
   * contract.
   */
  template <int dim>
  class FrictionalActiveSetSolver
  {
  public:
    /// How the Coulomb bound mu y_k is coupled to the normal problem.
    enum class Method
    {
      /// Lagged by one step of the method above.
      semismooth_newton,
      /// The fixed point on the Tresca threshold: s^{j+1} = mu y(s^j), each
      /// Tresca problem solved to convergence by the method above, from
      /// s^0 = 0 (the frictionless problem). The second route to the same
      /// solution; where the map does not contract (a large mu) it says
      /// so rather than return one of several answers.
      fixed_point
    };

    /// Contact/Friction solver.
    static void
    declare_parameters(ParameterHandler &prm);

    static Method
    parse_method(ParameterHandler &prm);
    /// Contact/Uniqueness check and Uniqueness check steps: the least
    /// number of steps of the check, 0 if it is off.
    static unsigned int
    parse_uniqueness_check(ParameterHandler &prm);
    /// Warn (once per run) of the parameters above that @p law does not
    /// use but the input changed: the friction solver without friction,
    /// the uniqueness check without Coulomb's law or switched off.
    static void
    warn_unused_parameters(ParameterHandler &prm, const FrictionLaw<dim> &law);

    /// @p preconditioner_update_fraction: rebuild the elasticity
    /// preconditioner for the current sets (active normal rows, sticking
    /// nodes' tangential dofs, sliding nodes' springs) when the dofs whose
    /// treatment changed since it was built (a row's normal dof if its
    /// contact did, its tangential dofs if its stick state did or its
    /// spring changed by more than a factor 2) exceed this fraction of the
    /// number of rows (Active set/Preconditioner update fraction;
    /// infinity: never). With @p uniqueness_check_steps > 0, a Coulomb
    /// solution where the fixed point on the Tresca threshold does not
    /// contract is refused, the rate estimated in at least that many
    /// steps.
    /// While the sets change, the solves stop at the relative CG tolerance
    /// @p inexact_tolerance (Active set/Inexact tolerance; 0: every solve
    /// at the linear solver's).
    FrictionalActiveSetSolver(const FrictionLaw<dim> &law,
                              const unsigned int      max_iterations,
                              const Method method = Method::semismooth_newton,
                              const double preconditioner_update_fraction =
                                std::numeric_limits<double>::infinity(),
                              const unsigned int uniqueness_check_steps = 2,
                              const double       inexact_tolerance      = 0.);

    /// Throw an InputError naming the parameter if friction cannot be
    /// applied to @p problem: a contact direction off the coordinate axes,
    /// or a body the Dirichlet data leave free to move.
    static void
    check_applicable(const DiscreteContactProblem<dim> &problem);

    /// The name of @p method, for reports.
    static std::string
    name(const Method method);

    /**
     * Solve @p problem from @p u and the normal active set @p
     * initial_active (may be empty); @p y the normal dual variable, @p
     * state the friction. With @p previous (the state of the previous load
     * step on the same mesh) a node slides against where that step left it,
     * and every node in contact starts sticking there (the elastic
     * predictor); without, against the unloaded state, and from the sets of
     * @p guess if given (else every node in contact sticks; a guessed
     * start whose sets cycle starts again from u = 0, out of contact; the
     * report counts both starts).
     */
    typename ContactSolver<dim>::Report
    solve(const DiscreteContactProblem<dim> &problem,
          LA::Vector                        &u,
          Vector<double>                    &y,
          FrictionState<dim>                &state,
          const std::vector<bool>           &initial_active = {},
          const FrictionState<dim>          *previous       = nullptr,
          const FrictionGuess<dim>          *guess          = nullptr) const;

  private:
    /// The method above with the bounds s_k given by @p bounds if not null
    /// (a Tresca problem), or by the law; the sets where it stopped in @p
    /// sets.
    typename ContactSolver<dim>::Report
    solve_with_bounds(const DiscreteContactProblem<dim> &problem,
                      LA::Vector                        &u,
                      Vector<double>                    &y,
                      FrictionState<dim>                &state,
                      const std::vector<bool>           &initial_active,
                      const FrictionState<dim>          *previous,
                      const std::vector<double>         *bounds,
                      FrictionSets<dim>                 &sets,
                      const FrictionGuess<dim>          *guess = nullptr) const;
    /// Coulomb: the solution of @p report is refused (not converged) where
    /// the fixed point on the Tresca threshold does not contract at it
    /// (FrictionState::contraction_at_solution >= 1), its uniqueness not
    /// shown.
    void
    judge_uniqueness(const DiscreteContactProblem<dim>   &problem,
                     const LA::Vector                    &u,
                     const Vector<double>                &y,
                     const FrictionSets<dim>             &sets,
                     FrictionState<dim>                  &state,
                     typename ContactSolver<dim>::Report &report) const;

    /// Method::fixed_point.
    typename ContactSolver<dim>::Report
    solve_fixed_point(const DiscreteContactProblem<dim> &problem,
                      LA::Vector                        &u,
                      Vector<double>                    &y,
                      FrictionState<dim>                &state,
                      const std::vector<bool>           &initial_active,
                      const FrictionState<dim>          *previous) const;

    const FrictionLaw<dim> &law;
    const unsigned int      max_iterations;
    const Method            method;
    const double            preconditioner_update_fraction;
    const unsigned int      uniqueness_check_steps;
    const double            inexact_tolerance;
  };
} // namespace Signorini

#endif
