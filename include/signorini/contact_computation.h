#ifndef signorini_contact_computation_h
#define signorini_contact_computation_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <signorini/boundary_conditions.h>
#include <signorini/contact/condition.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/contact/friction_law.h>
#include <signorini/contact/frictional_active_set_solver.h>
#include <signorini/contact/rigid_motions.h>
#include <signorini/contact/solution_checks.h>
#include <signorini/contact/solver.h>
#include <signorini/linear_algebra.h>
#include <signorini/linear_solver.h>
#include <signorini/load_path.h>
#include <signorini/material.h>
#include <signorini/mesh_input.h>
#include <signorini/phase_timer.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The finite element computation of the Signorini problem on one mesh
   * (doc/theory.md sections 1-2): P1 displacements, the Dirichlet and
   * hanging-node constraints, the stiffness matrix and the load, and the
   * contact problem solved by the chosen condition and solver, with the
   * solution checks that decide whether it succeeded (section 6). It owns
   * the parts of the model (material, boundary data, contact boundary,
   * contact condition and solver, linear solver), which declare and parse
   * their own parameters; the mesh belongs to the caller. The application
   * computes on a sequence of meshes with one object; a reference solution
   * has its own.
   */
  template <int dim>
  class ContactComputation
  {
  public:
    /// A contact row's node, whether it was in contact and, with friction,
    /// whether it stuck and the tangential traction on it.
    struct ContactNodeState
    {
      Point<dim>     position;
      bool           in_contact = false;
      bool           sticks     = true;
      Tensor<1, dim> tangential_traction;
    };
    /// What a computation on another mesh starts its active set (and its
    /// stick and slip sets) from.
    using ContactState = std::vector<ContactNodeState>;

    /// What the last contact solve found.
    struct Summary
    {
      typename ContactSolver<dim>::Report report;
      SolutionChecks                      checks;
      unsigned int                        n_active      = 0;
      double                              energy        = 0.;
      double                              contact_force = 0.;
      double                              setup_seconds = 0.;
      /// Contact solve, the nested start's computations included.
      double solve_seconds = 0.;
      /// What the nested start did (all zero/empty if it did not run).
      struct NestedStart
      {
        /// Coarser meshes computed on (0 if none).
        unsigned int meshes = 0;
        /// Their active-set iterations together.
        unsigned int iterations = 0;
        /// Their time: setup, assembly and solves.
        double seconds = 0.;
        /// Why it was abandoned for a cold start, if it was.
        std::string failure;
      } nested;
    };

    static void
    declare_parameters(ParameterHandler &prm);

    /// Parse the parts of the model; throws InputError for inconsistent
    /// input. Sections of @p timer time the steps.
    ContactComputation(ParameterHandler &prm, PhaseTimer &timer);

    /// DoFs, constraints, contact boundary and matrices on @p mesh (which
    /// must outlive the computation's use of it). Checks that every boundary
    /// id named in the input exists and that the data are finite on the
    /// mesh (also @p exact_solution if given).
    void
    setup(const Triangulation<dim> &mesh,
          const Function<dim>      *exact_solution = nullptr);

    /// K (unconstrained: the solves apply the constraints) and F; refuses loads
    /// and prescribed displacements whose products overflow.
    void
    assemble();

    /// The algebraic contact problem of the current mesh (after assembly).
    DiscreteContactProblem<dim>
    contact_problem();

    /// Solve the contact problem, starting the active set from the state of
    /// the previous solve (or from set_initial_contact_state()) if the
    /// option is on, and check the solution: converged() says whether both
    /// the solver and the checks accept it. On a load path of several steps
    /// (Contact/Load steps) each step is solved from the one before and
    /// checked, the observer of set_load_step_observer() is called after
    /// it, and the path stops at the first step that fails; summary() is
    /// then that of the last step solved, with the iterations and times of
    /// the whole path.
    void
    solve();

    /// Call @p observer(step) after each step of a load path of several
    /// steps (summary(), displacement() and friction() are the step's).
    void
    set_load_step_observer(std::function<void(unsigned int)> observer);

    /// Contact/Load steps and Load factor.
    const LoadPath &
    load_path() const;

    /// Throw an InputError naming the step unless the data of every step
    /// of the load path are finite on the current mesh (after setup(),
    /// which checks those of its end).
    void
    check_load_path();

    /// Start the next solve from @p state (a computation on another mesh).
    void
    set_initial_contact_state(const ContactState &state);

    /**
     * The current mesh is @p input's initial mesh with its Initial
     * refinements (call after setup(), which forgets it). Then the next
     * solve, unless it starts from the previous mesh's state (Initial active
     * set from previous cycle), starts nested if Contact/Nested start is on
     * and the solver uses a guess (the active set method): the same input
     * with fewer refinements is computed on first, from the finest one with
     * at most "Nested start cells" cells (a cold start) up to one refinement
     * less than the current mesh, each started from the one before, and the
     * current solve starts from the active set and the displacement of the
     * last. The separation point is then found to within a coarse cell on
     * every mesh, so the active-set iterations stop growing with the mesh
     * (doc/theory.md section 3, doc/benchmarks.md). With friction (the
     * semismooth Newton route, one load step) the coarser meshes solve
     * it too, and the current solve starts from their stick and slip sets
     * and tangential tractions as well.
     */
    void
    enable_nested_start(const MeshInput<dim> &input);

    /// The contact state of the last solve.
    const ContactState &
    contact_state() const;

    /// Whether the last solve converged and passed the checks.
    bool
    converged() const;

    /// Why the last solve failed (solver or solution checks), if it did.
    const std::string &
    failure() const;

    const Summary &
    summary() const;

    /// The last contact and first separated nodes of GC (multiplier nodes on
    /// both ends of a contact edge with different states).
    std::vector<unsigned int>
    contact_transition_vertices() const;

    const FESystem<dim> &
    finite_element() const;

    const Mapping<dim> &
    mapping() const;

    const DoFHandler<dim> &
    dof_handler() const;

    /// The diagonal of the bounding box of the mesh of setup(): the
    /// diameter to a factor sqrt(dim), the length scale of the checks.
    double
    domain_diameter() const;

    const IndexSet &
    locally_relevant_dofs() const;

    /// The unconstrained stiffness matrix: a(u, v) = u^T K v.
    const LA::SparseMatrix &
    stiffness_matrix() const;

    /// u_h (owned entries)
    const LA::Vector &
    displacement() const;

    /// y of the last solve (see ContactCondition)
    const Vector<double> &
    dual() const;

    /// Active rows of the last solve (y_i > 0 beyond round-off).
    const std::vector<bool> &
    active_set() const;

    const LinearElasticMaterial<dim> &
    material() const;

    const BoundaryConditions<dim> &
    boundary_conditions() const;

    const ContactBoundary<dim> &
    contact_boundary() const;

    const ContactCondition<dim> &
    condition() const;

    const ContactSolver<dim> &
    solver() const;

    /// Contact/Friction and its parameters.
    const FrictionLaw<dim> &
    friction_law() const;

    /// The friction of the last solve (empty without friction).
    const FrictionState<dim> &
    friction() const;

    const ElasticitySolver &
    linear_solver() const;

  private:
    /// The public constructor with @p with_nested_start = true; the
    /// computations on coarser meshes have none (no nesting inside them).
    ContactComputation(ParameterHandler &prm,
                       PhaseTimer       &timer,
                       const bool        with_nested_start);

    /// The nested start of enable_nested_start(): the contact state of the
    /// last coarser mesh and its displacement interpolated into solution.
    /// Falls back to a cold start (Summary::nested says why) if a coarser
    /// computation throws an input or solver error.
    void
    start_from_coarser_meshes();

    /// Where a solve starts: the active set (empty: cold) and, with
    /// friction, the stick and slip sets (empty: every row in contact
    /// sticks).
    struct InitialGuess
    {
      std::vector<bool>  active;
      FrictionGuess<dim> friction;
    };

    /// The state of the previous solve (or of the nested start) carried to
    /// the current contact nodes (empty if there is none).
    InitialGuess
    initial_guess() const;

    /// Throws InputError if a boundary id of the input is not in @p mesh.
    void
    check_boundary_ids(const Triangulation<dim> &mesh) const;

    /// The Dirichlet constraints of the data (their current load step),
    /// merged with the hanging nodes' (with and without the values).
    void
    make_constraints();

    /// Set the data to those of step @p step and check them (an InputError
    /// names the step).
    void
    check_step_data(const unsigned int step);

    /// Tresca: the threshold at every contact node is finite and >= 0.
    void
    check_friction_threshold() const;

    /// "Contact/Load steps: at step k (t = ..): ", for errors in its data.
    std::string
    step_context(const unsigned int step) const;

    /// The data of step @p step of the load path: constraints and load
    /// (the stiffness does not change).
    void
    apply_load_step(const unsigned int step);

    /// Whether the current data are all zero: no load, no prescribed
    /// displacement.
    bool
    data_vanish() const;

    /// F, and K too if @p with_matrix.
    void
    assemble(const bool with_matrix);

    /// Solve the contact problem of the current data from solution and
    /// @p guess (may be empty), check and judge the solution; with
    /// friction, sliding against @p previous_friction (the state of the
    /// previous load step; null: the unloaded state).
    void
    solve_step(const InitialGuess       &guess,
               const FrictionState<dim> *previous_friction);

    /// Decide converged() from the solver's report and the checks.
    void
    judge_solution();

    /// Throw an InputError when the stresses or the displacements of the
    /// data (largest magnitudes @p data on the mesh of diameter
    /// domain_diameter()), or Coulomb's mu times those stresses
    /// (check_friction_coefficient_scale()), are beyond what the range of
    /// doubles holds in their squares.
    void
    check_data_scale(
      const typename BoundaryConditions<dim>::DataMagnitudes &data) const;

    /// Throw an InputError when Coulomb's mu times stresses of order
    /// 10^@p log_stress is beyond what the range of doubles holds in their
    /// squares.
    void
    check_friction_coefficient_scale(const double log_stress) const;

    /// Throw an InputError when a negative Contact/Gap imposes
    /// displacements, or the stresses they cause (or Coulomb's mu times
    /// those), beyond what the range of doubles holds in their squares (as
    /// check_data_scale()).
    void
    check_gap_scale() const;

    PhaseTimer &timer;
    MPI_Comm    mpi_communicator;

    // The model
    LinearElasticMaterial<dim>             material_law;
    BoundaryConditions<dim>                boundary_data;
    ContactBoundary<dim>                   gamma_c;
    std::unique_ptr<ContactCondition<dim>> contact_condition;
    std::unique_ptr<ContactSolver<dim>>    contact_solver;
    FrictionLaw<dim>                       friction_law_;
    LoadPath                               load_path_;
    std::function<void(unsigned int)>      load_step_observer;
    /// Contact/Active set/Maximum iterations (for the frictional method).
    unsigned int friction_max_iterations = 100;
    /// Contact/Active set/Preconditioner update fraction (the same).
    double friction_preconditioner_update = 0.02;
    /// Contact/Active set/Inexact tolerance (the same).
    double friction_inexact_tolerance = 1e-6;
    /// Contact/Friction solver.
    typename FrictionalActiveSetSolver<dim>::Method friction_method =
      FrictionalActiveSetSolver<dim>::Method::semismooth_newton;
    /// Contact/Uniqueness check (steps), 0: off.
    unsigned int       friction_uniqueness_steps = 2;
    FrictionState<dim> friction_state;
    ElasticitySolver   elasticity_solver;
    bool               guess_from_previous_cycle = true;
    /// Largest relative solution check a converged computation may have.
    double check_tolerance = 1e-6;
    /// Whether the nested start is on (and the solver uses a guess).
    bool nested_start = false;
    /// The largest first mesh of the nested start.
    unsigned int nested_start_cells = 2000;
    /// The input of the current mesh, if it is an input mesh.
    std::optional<MeshInput<dim>> nested_start_input;
    /// Parsed again by the computations on coarser meshes when they are
    /// made (the parameters outlive every computation).
    ParameterHandler *parameters = nullptr;

    // Discretisation
    const FESystem<dim>  fe;
    const MappingFE<dim> mapping_fe;
    DoFHandler<dim>      dofs;
    double               mesh_diameter = 0.;
    IndexSet             locally_owned_dofs;
    IndexSet             relevant_dofs;
    // Constraints: hanging nodes, Dirichlet data, and both merged (with and
    // without the Dirichlet values)
    AffineConstraints<double> hanging_node_constraints;
    AffineConstraints<double> dirichlet_constraints;
    AffineConstraints<double> constraints;
    AffineConstraints<double> homogeneous_constraints;
    // The rigid motions the Dirichlet data leave to the contact
    RigidMotions<dim> rigid_motions;

    // Linear algebra and results
    LA::SparseMatrix  stiffness;
    LA::Vector        load;
    LA::Vector        solution;
    Vector<double>    dual_solution;
    std::vector<bool> active_rows; // of the last solve, per multiplier node
    ContactState      last_contact_state;
    Summary           last_summary;
    bool              last_solve_converged = true;
    std::string       solve_failure;
  };
} // namespace Signorini

#endif
