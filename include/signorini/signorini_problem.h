#ifndef signorini_signorini_problem_h
#define signorini_signorini_problem_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>
#include <deal.II/base/timer.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <deal.II/distributed/shared_tria.h>

#include <signorini/adaptation/adaptive_mesh.h>
#include <signorini/adaptation/size_predictor.h>
#include <signorini/adaptation/target_error.h>
#include <signorini/boundary_conditions.h>
#include <signorini/contact/condition.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/contact/rigid_motions.h>
#include <signorini/contact/solution_checks.h>
#include <signorini/contact/solver.h>
#include <signorini/csv_table.h>
#include <signorini/estimator/constitutive_relation_error.h>
#include <signorini/linear_algebra.h>
#include <signorini/linear_solver.h>
#include <signorini/material.h>
#include <signorini/mesh_input.h>
#include <signorini/output_directory.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The application: the Signorini problem of doc/theory.md sections 1-2 on a
   * sequence of meshes ("cycles", or computations), in the style of deal.II
   * step-41/42: make_grid(), setup_system(), assemble_system(),
   * solve_contact(), estimate_error(), output_results(), adapt_mesh(),
   * driven by run(). The data flow one way: mesh -> solve -> admissible
   * fields and estimate -> size prediction -> new mesh. Every constant comes
   * from the parameter file; the parts of the method (mesh input, material,
   * boundary data, contact boundary, contact condition, contact solver,
   * linear solver) declare and parse their own parameters.
   */
  template <int dim>
  class SignoriniProblem
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm);

    /// Parse every part; throws InputError for inconsistent input. Relative
    /// file names in @p prm are taken from @p input_directory.
    explicit SignoriniProblem(ParameterHandler  &prm,
                              const std::string &input_directory = ".");

    /// Build the initial mesh and the discrete spaces, checking that every
    /// boundary id named in the input exists, without solving.
    void
    validate();

    void
    run();

    /// Results of the last cycle, for tests and benchmarks.
    const CsvTable &
    statistics() const;

    const LA::Vector &
    displacement() const;

    /// Active rows of the last solve (y_i > 0 beyond round-off).
    const std::vector<bool> &
    active_set() const;

    /// y of the last solve (see ContactCondition)
    const Vector<double> &
    dual() const;

    const DoFHandler<dim> &
    get_dof_handler() const;

    /// The error estimate of the last cycle.
    const typename ConstitutiveRelationError<dim>::Result &
    error_estimate() const;

    /// The unconstrained stiffness matrix: a(u, v) = u^T K v.
    const LA::SparseMatrix &
    stiffness_matrix() const;

    /// Solve once, on the initial mesh or on @p mesh, and keep the result (a
    /// reference solution).
    void
    solve_once(const Triangulation<dim> *mesh = nullptr);

  private:
    void
    make_grid();

    /// The mesh of @p cycle from the size predictor (paper section 6),
    /// rebuilt from the initial one; throws if it would exceed Maximum cells.
    void
    adapt_mesh(const unsigned int cycle);

    /// Has the last estimate reached the target error (with tolerance)?
    bool
    target_reached() const;

    /// The last contact and first separated nodes of GC (multiplier nodes on
    /// both ends of a contact edge with different states).
    std::vector<unsigned int>
    contact_transition_vertices() const;

    void
    setup_system();

    void
    assemble_system();

    /// The discrete contact problem of the current mesh (after assembly).
    DiscreteContactProblem<dim>
    contact_problem();

    /// Solve the contact problem of the current mesh and check the solution.
    void
    solve_contact();

    /// The error in constitutive relation of the solution (if enabled).
    void
    estimate_error();

    /// The statistics row of cycle @p cycle: mesh, solve, checks, estimate.
    void
    record_statistics(const unsigned int cycle);

    void
    compute_exact_error();

    /// The reference problem: the same input without estimate, adaptation
    /// or output, solved on the initial mesh refined @p levels times or on
    /// @p mesh.
    std::unique_ptr<SignoriniProblem<dim>>
    solve_reference(const unsigned int levels, const Triangulation<dim> *mesh);

    struct ExactError
    {
      double eps_ex             = 0.; ///< ||U_ref - U_h|| / ||U_ref + U_h||
      double effectivity        = 0.; ///< eps / eps_ex
      double prager_synge_ratio = 0.; ///< ||U_ref - U^|| / e
    };

    /// Compare (U_h, U^) of a computation with the reference solution.
    ExactError
    exact_error(const DoFHandler<dim> &computation_dofs,
                const Vector<double>  &u_h,
                const Vector<double>  &u_hat,
                const double           eps,
                const double           e) const;

    /// eps_ex, the effectivity and the Prager-Synge check of the current
    /// cycle against a reference computed beforehand.
    void
    compare_with_reference();

    /// The same for every computation, against a reference built from the
    /// final mesh (after the cycles).
    void
    compare_computations_with_final_reference();

    /// Keep the mesh and fields of the current cycle for the latter.
    void
    keep_computation();



    /// The active set of the previous cycle carried to the current contact
    /// nodes (empty if there is none or the option is off).
    std::vector<bool>
    initial_active_set_guess() const;

    void
    output_results(const unsigned int cycle);

    void
    write_contact_table(const unsigned int cycle);

    /// Refuse, before any mesh is built, the meshes whose size is known
    /// from the input (the initial mesh, uniform cycles, a reference on the
    /// initial mesh) beyond Maximum cells: throws InputError.
    void
    check_mesh_sizes() const;

    // Input
    ParameterHandler                               &prm;
    std::string                                     output_directory;
    unsigned int                                    n_cycles;
    bool                                            write_vtu;
    bool                                            print_timing;
    MeshInput<dim>                                  mesh_input;
    LinearElasticMaterial<dim>                      material;
    BoundaryConditions<dim>                         boundary_conditions;
    std::unique_ptr<Functions::ParsedFunction<dim>> exact_solution;
    /// No mesh of more cells is built (Maximum cells)
    double max_cells;

    // Discretisation: the computational mesh is the conforming version of
    // an adaptive hierarchy built on the initial mesh
    AdaptiveMesh<dim>              adaptive_mesh;
    std::unique_ptr<SizePredictor> size_predictor;
    AdaptationTarget               adaptation_target;
    double                         predicted_cells = 0.;
    // Every rank holds the whole mesh (parallel::shared: it accepts
    // simplices and the flat conforming meshes of AdaptiveMesh) and owns a
    // METIS partition of the cells and the dofs
    MPI_Comm mpi_communicator;
    ConditionalOStream
      pcout; // active on rank 0, which also writes the CSV files
    parallel::shared::Triangulation<dim> triangulation;
    const FESystem<dim>                  fe;
    const MappingFE<dim>                 mapping;
    DoFHandler<dim>                      dof_handler;
    const FE_SimplexP<dim>               scalar_fe;
    DoFHandler<dim> scalar_dof_handler; // contact fields in the output

    IndexSet locally_owned_dofs;
    IndexSet locally_relevant_dofs;
    // Constraints: hanging nodes, Dirichlet data, and both merged (with and
    // without the Dirichlet values)
    AffineConstraints<double> hanging_node_constraints;
    AffineConstraints<double> dirichlet_constraints;
    AffineConstraints<double> constraints;
    AffineConstraints<double> homogeneous_constraints;

    // The rigid motions the Dirichlet data leave to the contact
    RigidMotions<dim> rigid_motions;

    // Contact
    ContactBoundary<dim>                   contact_boundary;
    std::unique_ptr<ContactCondition<dim>> contact_condition;
    std::unique_ptr<ContactSolver<dim>>    contact_solver;
    bool                                   guess_from_previous_cycle = true;
    /// (position, active) of the multiplier nodes of the previous cycle
    std::vector<std::pair<Point<dim>, bool>> previous_contact_state;

    // Linear algebra
    LA::SparseMatrix  stiffness;
    LA::SparseMatrix  condensed_stiffness;
    LA::Vector        load;
    LA::Vector        solution;
    Vector<double>    dual_solution;
    std::vector<bool> active_rows; // of the last solve, per multiplier node
    bool              last_solve_converged = true;
    /// Whether the current computation has an error estimate (the
    /// estimator is enabled and the computation did not fail).
    bool estimated = false;
    /// What solve_contact() found, for the statistics.
    struct ContactSummary
    {
      typename ContactSolver<dim>::Report report;
      SolutionChecks                      checks;
      unsigned int                        n_active      = 0;
      double                              energy        = 0.;
      double                              contact_force = 0.;
      double                              setup_seconds = 0.;
      double                              solve_seconds = 0.;
    } contact_summary;
    /// Why the last computation failed (solver or solution checks).
    std::string solve_failure;
    /// Largest relative solution check a converged computation may have.
    double           check_tolerance = 1e-6;
    ElasticitySolver linear_solver;

    // Error in constitutive relation
    ConstitutiveRelationError<dim>                  estimator;
    typename ConstitutiveRelationError<dim>::Result estimate;
    LA::Vector                                      admissible_displacement;
    double                                          estimate_seconds       = 0.;
    unsigned int                                    reference_extra_levels = 0;
    bool reference_from_final_mesh = false;
    /// What a later comparison needs of each computation
    struct Computation
    {
      Triangulation<dim> mesh;
      DoFHandler<dim>    dof_handler;
      Vector<double>     displacement;
      Vector<double>     admissible_displacement;
      double             eps = 0.;
      double             e   = 0.;
    };
    std::vector<std::unique_ptr<Computation>> computations;
    std::unique_ptr<ParameterHandler>         reference_parameters;
    std::unique_ptr<SignoriniProblem<dim>>    reference;

    // Output
    OutputDirectory                             output_files;
    TimerOutput                                 timer;
    CsvTable                                    statistics_table;
    std::vector<std::pair<double, std::string>> vtu_files;
  };
} // namespace Signorini

#endif
