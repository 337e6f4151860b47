#ifndef signorini_contact_discrete_problem_h
#define signorini_contact_discrete_problem_h

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <signorini/contact/condition.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/contact/rigid_motions.h>
#include <signorini/linear_algebra.h>
#include <signorini/linear_solver.h>

#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The discrete Signorini problem as the contact solvers see it:
   *
   *   min 1/2 u^T K u - F^T u  subject to  B u <= b  (and the base
   *   constraints: hanging nodes, Dirichlet data),
   *
   * with optimality conditions K u + B^T y = F, y >= 0, B u <= b,
   * y^T (B u - b) = 0. B and b come from the ContactCondition; K and F are
   * unconstrained (raw) so that residuals are true nodal forces.
   *
   * When the Dirichlet data leave rigid motions N free (RigidMotions), K is
   * singular on them and only the contact holds the body: the problem has a
   * unique solution when C = B N stops every free motion and the rigid load
   * h = N^T F lies inside the cone of the rows of C (the load presses the
   * body onto the foundation); check_rigid_motions() tests both. Solves
   * that need an invertible operator whatever the active set (the dual
   * ones) then fix one support dof per free motion: K_s^{-1} is a
   * generalised inverse of K on the loads the free motions do not see, and
   * the dual solution must satisfy C^T y = h (see FrankWolfeSolver).
   */
  template <int dim>
  class DiscreteContactProblem
  {
  public:
    DiscreteContactProblem(
      const LA::SparseMatrix          &stiffness,
      const LA::Vector                &load,
      const AffineConstraints<double> &constraints,
      const AffineConstraints<double> &homogeneous_constraints,
      const AffineConstraints<double> &hanging_node_constraints,
      const ContactBoundary<dim>      &boundary,
      const ContactCondition<dim>     &condition,
      const RigidMotions<dim>         &rigid_motions,
      ElasticitySolver                &linear_solver);

    /// Number of rigid motions the Dirichlet data leave free.
    unsigned int
    n_rigid_motions() const;

    /**
     * Throw an InputError naming the motion when a free rigid motion is not
     * stopped by the contact, or when the load does not press the body onto
     * the foundation (a free motion that lifts it off or slides it does no
     * negative work): then no (unique) equilibrium exists.
     */
    void
    check_rigid_motions() const;

    /// Whether the rows @p active of B alone stop every free rigid motion.
    bool
    blocks_rigid_motions(const std::vector<bool> &active) const;

    /// C = B N (one column per free motion).
    const FullMatrix<double> &
    rigid_constraint_rows() const;

    /// h = N^T F: the load's work on each free motion.
    const Vector<double> &
    rigid_load() const;

    /// The normal components nu_c . N_j at every node of GC (one column per
    /// free motion).
    FullMatrix<double>
    rigid_normal_components() const;

    /// u += N c.
    void
    add_rigid_motion(const Vector<double> &c, LA::Vector &u) const;

    unsigned int
    n_constraints() const;

    /// B u
    Vector<double>
    constraint_values(const LA::Vector &u) const;

    /// b - B u (>= 0 where admissible)
    Vector<double>
    slack(const LA::Vector &u) const;

    const Vector<double> &
    bounds() const;

    /**
     * Minimise the energy under the base constraints and (B u)_i = b_i for
     * the active rows. Returns the CG iterations; @p u is the initial guess.
     */
    unsigned int
    solve_with_active_set(const std::vector<bool> &active,
                          LA::Vector              &u,
                          const double relative_tolerance = 0.) const;

    /**
     * The same with friction (FrictionalActiveSetSolver): besides (B u)_A =
     * b_A, the constraints @p stick_constraints hold (the tangential
     * components of the sticking rows: where the previous load step left
     * them), and the nodal forces @p forces (dof, value) act with the load
     * (the friction forces of the sliding rows), and the @p springs
     * (ElasticitySolver::solve()) add to K.
     */
    unsigned int
    solve_with_friction(
      const std::vector<bool>         &active,
      const AffineConstraints<double> &stick_constraints,
      const std::vector<std::pair<types::global_dof_index, double>> &forces,
      const ElasticitySolver::Springs                               &springs,
      LA::Vector                                                    &u,
      const double relative_tolerance = 0.) const;

    /**
     * Tune the linear solver's preconditioner to the active set @p active
     * and the displacement dofs @p fixed_dofs held by other constraints
     * (the sticking nodes' tangential dofs), with @p springs added to K
     * (the sliding nodes', lumped onto K's pattern; see
     * ElasticitySolver::update_preconditioner()); an all-false set restores
     * the base preconditioner.
     */
    void
    update_preconditioner(
      const std::vector<bool>                    &active,
      const std::vector<types::global_dof_index> &fixed_dofs = {},
      const ElasticitySolver::Springs            &springs    = {}) const;

    /// Solve K u = F + sum_k forces_k nu_c (at node k of GC) under the base
    /// constraints (and the supports of the free rigid motions).
    unsigned int
    solve_with_normal_forces(const Vector<double> &forces,
                             LA::Vector           &u,
                             const double relative_tolerance = 0.) const;

    /// The same with the nodal forces @p forces (dof, value; every rank
    /// may list all of them) in any direction.
    unsigned int
    solve_with_nodal_forces(
      const std::vector<std::pair<types::global_dof_index, double>> &forces,
      LA::Vector                                                    &u,
      const double relative_tolerance = 0.) const;

    /// Solve K u = F - B^T y under the base constraints (and the supports).
    unsigned int
    solve_with_dual(const Vector<double> &y,
                    LA::Vector           &u,
                    const double          relative_tolerance = 0.) const;

    /// Column i of the dual operator S = B K^{-1} B^T (homogeneous base
    /// constraints, K_s with supports). Returns the CG iterations.
    unsigned int
    dual_operator_column(const unsigned int i, Vector<double> &column) const;

    /// The dual variable of an active set from the residual of u.
    Vector<double>
    dual_from_residual(const std::vector<bool> &active,
                       const LA::Vector        &u) const;

    /**
     * The nodal residual F - K u with hanging-node rows moved to their
     * masters: the force the rest of the body does not balance at each dof
     * (the reactions at Dirichlet dofs, the contact forces on GC).
     */
    LA::Vector
    residual(const LA::Vector &u) const;

    /// 1/2 u^T K u - F^T u
    double
    energy(const LA::Vector &u) const;

    const ContactBoundary<dim> &
    boundary() const;

    const ContactCondition<dim> &
    condition() const;

    const LA::Vector &
    load() const;

    /// K (raw, as the residuals use it).
    const LA::SparseMatrix &
    stiffness() const;

    const AffineConstraints<double> &
    constraints() const;

    /// A typical size of the entries of B u, for relative tolerances: of
    /// u, the gaps and the displacement force_scale() / max K_ii the loads
    /// give a node on its own (the scale when u and the gaps vanish: a
    /// load the foundation carries at a node that nothing else holds).
    double
    constraint_scale(const LA::Vector &u) const;

    /// The forces of the problem: the largest load, or the largest K_ii
    /// |g_i| over the dofs with Dirichlet data g_i (the forces the imposed
    /// displacements exert on their own: a body moved by its Dirichlet data
    /// and out of contact has no other).
    double
    force_scale() const;

  private:
    /// F plus the nodal @p forces (dof, value) on the dofs of this rank.
    LA::Vector
    load_with(const std::vector<std::pair<types::global_dof_index, double>>
                &forces) const;

    /// The base constraints, with the supports when rigid motions are free.
    const AffineConstraints<double> &
    free_body_constraints() const;

    /// Throw std::invalid_argument when the homogeneous constraints are
    /// not the constraints without their values, or when K looks condensed
    /// (doc/library.md).
    void
    check_constraints_and_matrix() const;

    const LA::SparseMatrix          &stiffness_matrix;
    const LA::Vector                &load_vector;
    const AffineConstraints<double> &base_constraints;
    const AffineConstraints<double> &homogeneous_base_constraints;
    const AffineConstraints<double> &hanging_node_constraints;
    const ContactBoundary<dim>      &contact_boundary;
    const ContactCondition<dim>     &contact_condition;
    const RigidMotions<dim>         &rigid_motions;
    ElasticitySolver                &linear_solver;
    /// max K_ii over all ranks.
    double largest_diagonal = 0.;
    /// The base constraints plus u_s = 0 at the supports (if any).
    AffineConstraints<double> supported_constraints;
    AffineConstraints<double> homogeneous_supported_constraints;
    FullMatrix<double>        rigid_rows;
    Vector<double>            rigid_load_vector;
  };
} // namespace Signorini

#endif
