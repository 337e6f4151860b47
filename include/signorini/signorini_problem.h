#ifndef signorini_signorini_problem_h
#define signorini_signorini_problem_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/vector.h>

#include <deal.II/distributed/shared_tria.h>

#include <signorini/adaptation/adaptive_mesh.h>
#include <signorini/adaptation/error_density_smoothing.h>
#include <signorini/adaptation/gmsh_remesher.h>
#include <signorini/adaptation/size_predictor.h>
#include <signorini/adaptation/target_error.h>
#include <signorini/contact_computation.h>
#include <signorini/csv_table.h>
#include <signorini/estimator/constitutive_relation_error.h>
#include <signorini/exact_solution.h>
#include <signorini/linear_algebra.h>
#include <signorini/mesh_input.h>
#include <signorini/phase_timer.h>
#include <signorini/reference_solution.h>
#include <signorini/results_output.h>

#include <memory>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * Declare the entry Dimension (2 or 3) with default @p default_dimension:
   * main reads it first, then lets SignoriniProblem<dim> declare and read
   * the rest.
   */
  void
  declare_dimension(ParameterHandler  &prm,
                    const unsigned int default_dimension);



  /**
   * The application: the Signorini problem of doc/theory.md sections 1-2 on a
   * sequence of meshes ("cycles", or computations), in the style of deal.II
   * step-42. run() calls, for every cycle, make_grid() or adapt_mesh(),
   * setup_system(), assemble_system(), solve_contact(), estimate_error(),
   * compare_with_known_solutions() and output_results(), and stops at the
   * target error. Each step is one call of a part: the mesh (MeshInput,
   * SizePredictor, AdaptiveMesh or GmshRemesher), the finite element
   * computation on it (ContactComputation: material, boundary data, contact
   * condition and solver), the error estimate (ConstitutiveRelationError), the
   * solutions it is checked against (ExactSolution, ReferenceSolution) and what
   * is reported (ResultsOutput). The data flow one way: mesh -> solve ->
   * admissible fields and estimate -> size prediction -> new mesh. Every
   * part declares and parses its own parameters.
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
    /// boundary id named in the input exists and that the data are finite,
    /// and that the body has an equilibrium, without solving.
    void
    validate();

    void
    run();

    /// Results of the cycles so far, for tests and benchmarks.
    const CsvTable &
    statistics() const;

    /// Active rows of the last solve (y_i > 0 beyond round-off).
    const std::vector<bool> &
    active_set() const;

    /// y of the last solve (see ContactCondition)
    const Vector<double> &
    dual() const;

    /// The error estimate of the last cycle.
    const typename ConstitutiveRelationError<dim>::Result &
    error_estimate() const;

  private:
    /// The initial mesh.
    void
    make_grid();

    /// The mesh of @p cycle from the size predictor (paper section 6),
    /// realised by refinement of the initial mesh (AdaptiveMesh) or by
    /// remeshing (GmshRemesher); throws if it would exceed Maximum cells.
    void
    adapt_mesh(const unsigned int cycle);

    /// DoFs and constraints on the current mesh; reports the mesh.
    void
    setup_system(const unsigned int cycle);

    void
    assemble_system();

    /// Solve the contact problem of the current mesh and check the solution.
    void
    solve_contact(const unsigned int cycle);

    /// The error in constitutive relation of the solution (if enabled and
    /// the solve succeeded).
    void
    estimate_error();

    /// The exact error against a manufactured solution and a reference
    /// solved beforehand, if any; keeps the computation for a reference
    /// solved afterwards.
    void
    compare_with_known_solutions();

    void
    output_results(const unsigned int cycle);

    /// May the reference be coarser than the current mesh somewhere (then
    /// eps_ex is underestimated)?
    bool
    reference_not_finer() const;

    /// Is the next mesh made by Gmsh (Mesh adaptation/Realisation =
    /// remeshing) rather than refined from the initial mesh?
    bool
    remeshing() const;

    /// Has the last estimate reached the target error (with tolerance)?
    bool
    target_reached() const;

    /// The reference on the initial mesh refined uniformly, before the
    /// computations.
    void
    solve_reference_on_initial_mesh();

    /// The reference on the last mesh refined uniformly, after the
    /// computations, and every computation against it.
    void
    compare_computations_with_final_reference();

    /// Throws if the reference solve failed (after reporting it).
    void
    check_reference();

    /// Refuse, before any mesh is built, the meshes whose size is known
    /// from the input (the initial mesh, uniform cycles, a reference on the
    /// initial mesh) beyond Maximum cells: throws InputError.
    void
    check_mesh_sizes() const;

    // Input
    ParameterHandler &prm;
    unsigned int      n_cycles;
    /// No mesh of more cells is built (Maximum cells)
    double             max_cells;
    MeshInput<dim>     mesh_input;
    ExactSolution<dim> exact_solution;

    // What is reported, and when
    ResultsOutput<dim> results;
    PhaseTimer         timer;

    // The mesh: the conforming version of an adaptive hierarchy built on the
    // initial mesh. Every rank holds the whole mesh (parallel::shared: it
    // accepts simplices and the flat conforming meshes of AdaptiveMesh) and
    // owns a METIS partition of the cells and the dofs.
    parallel::shared::Triangulation<dim> triangulation;
    AdaptiveMesh<dim>                    adaptive_mesh;
    std::unique_ptr<SizePredictor>       size_predictor;
    AdaptationTarget                     adaptation_target;
    ErrorDensitySmoothing                error_density_smoothing;
    GmshRemesher<dim>                    remesher;
    double                               predicted_cells = 0.;

    // The computation on the current mesh
    ContactComputation<dim> computation;

    // Error in constitutive relation
    ConstitutiveRelationError<dim>                  estimator;
    typename ConstitutiveRelationError<dim>::Result estimate;
    LA::Vector                                      admissible_displacement;
    /// Whether the current computation has an error estimate (the
    /// estimator is enabled and the computation did not fail).
    bool estimated = false;

    ReferenceSolution<dim> reference;
  };
} // namespace Signorini

#endif
