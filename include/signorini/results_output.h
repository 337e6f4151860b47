#ifndef signorini_results_output_h
#define signorini_results_output_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/parameter_handler.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/vector.h>

#include <signorini/adaptation/adaptive_mesh.h>
#include <signorini/adaptation/size_predictor.h>
#include <signorini/contact_computation.h>
#include <signorini/csv_table.h>
#include <signorini/estimator/constitutive_relation_error.h>
#include <signorini/exact_solution.h>
#include <signorini/output_directory.h>
#include <signorini/reference_solution.h>

#include <string>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * What a run reports, in one place: the screen (rank 0), the statistics
   * table (one row per computation, statistics.csv), the contact table of
   * every computation (contact-CC.csv) and the ParaView files
   * (solution-CC.vtu, or a piece per rank and a .pvtu record, and
   * solution.pvd), all in the output directory; on a load path of several
   * steps also the same per step (load-steps.csv, contact-CC-SS.csv,
   * solution-CC-SS.vtu and steps-CC.pvd). Each step of a computation
   * reports through one member, which prints its screen lines and adds its
   * statistics columns; write() closes the row and writes the files.
   *
   * The statistics are a CsvTable rather than deal.II's TableHandler: the
   * comparison with a reference solved after the computations fills in the
   * rows of earlier computations, and the file is CSV for spreadsheets and
   * scripts.
   *
   * The local exact error: with a reference solved before the computations
   * (Reference solution/Mesh = initial mesh), the VTU of each computation
   * also has the cell fields eps_ex_E (ReferenceSolution::Comparison::local,
   * normalised as eps_E) and local_effectivity = eps_E / eps_ex_E (NaN
   * where eps_ex_E = 0), unless that reference is not finer than the mesh
   * everywhere (then some cells would hold no reference cell).
   *
   * A reference on the final mesh is solved after the loop, when every VTU,
   * the last one included, has been written: no VTU gets these fields. The
   * statistics table may be rewritten (it is one table whose rows are
   * filled in); a computation's VTU is not: write() produces the files of a
   * computation when its cycle ends, before the next step can fail, and
   * solution.pvd lists them as they are. Adding the fields to the last VTU
   * would mean either rewriting it after the reference solve (a listed
   * file that changes later, or stays without them if the reference
   * fails) or holding it back until then (a failed reference would leave
   * the last computation without its file). For local exact errors, use
   * the initial-mesh reference.
   */
  template <int dim>
  class ResultsOutput
  {
  public:
    /// Output directory and section Output.
    static void
    declare_parameters(ParameterHandler &prm);

    ResultsOutput();

    void
    parse_parameters(ParameterHandler &prm);

    /// Create the output directory (checked writable; call once the input
    /// is known to be valid).
    void
    initialize();

    /// Delete the files of the previous run there and write the parameters
    /// used (parameters.prm).
    void
    start_run(const ParameterHandler &prm);

    /// The screen: std::cout on rank 0.
    ConditionalOStream &
    screen();

    /// Output/Print timing
    bool
    print_timing() const;

    const CsvTable &
    statistics() const;

    /// The mesh of computation @p cycle: cells, DoFs, nodes of GC; with a
    /// size prediction (@p with_prediction) also the predicted count and
    /// the mesh quality.
    void
    mesh(const unsigned int             cycle,
         const AdaptiveMesh<dim>       &adaptive_mesh,
         const ContactComputation<dim> &computation,
         const double                   predicted_cells,
         const bool                     with_prediction);

    /// The contact solve on screen: iterations, active nodes, energy,
    /// contact force and the solution checks (also for a reference).
    void
    print_contact_solve(const ContactComputation<dim> &computation);

    /// The same, and its statistics columns.
    void
    contact_solve(const ContactComputation<dim> &computation);

    /// Step @p step of the load path of computation @p cycle (Contact/Load
    /// steps > 1): a screen line, a row of load-steps.csv, contact-CC-SS.csv
    /// and, if enabled, solution-CC-SS.vtu in steps-CC.pvd (with the time t
    /// of the step).
    void
    load_step(const unsigned int             cycle,
              const unsigned int             step,
              const ContactComputation<dim> &computation);

    /// The error in constitutive relation of the computation.
    void
    error_estimate(
      const typename ConstitutiveRelationError<dim>::Result &estimate,
      const double                                           seconds);

    /// The size predictor's prediction for the next mesh.
    void
    size_prediction(const std::string               &predictor,
                    const SizePredictor::Prediction &prediction);

    /// The error against the exact solution, and the effectivity of the
    /// @p estimate if there is one.
    void
    exact_error(
      const typename ExactSolution<dim>::Error              &error,
      const typename ConstitutiveRelationError<dim>::Result *estimate);

    /// The computation against a reference of @p reference_dofs DoFs that
    /// may not be finer than its mesh everywhere (@p underestimated); keeps
    /// its local exact errors (if finer) for the VTU of write().
    void
    reference_comparison(
      const typename ReferenceSolution<dim>::Comparison &comparison,
      const types::global_dof_index                      reference_dofs,
      const bool                                         underestimated,
      const bool                                         with_estimate);

    /// Every computation against a reference solved after them: fills in
    /// their rows and rewrites statistics.csv.
    void
    final_reference_comparison(
      const std::vector<typename ReferenceSolution<dim>::Comparison>
                &comparisons,
      const bool with_estimate);

    /// One line of progress (a heading, the target reached or not).
    void
    message(const std::string &text);

    /// Close the statistics row of computation @p cycle and write its
    /// files: statistics.csv, contact-CC.csv and, if enabled, the VTU with
    /// the displacement, stresses, contact fields, @p eps_E (if given) and
    /// the local exact errors of reference_comparison() (if called for this
    /// computation).
    void
    write(const unsigned int             cycle,
          const ContactComputation<dim> &computation,
          const Vector<double>          *eps_E);

  private:
    void
    write_statistics();

    void
    write_contact_table(const std::string             &file_name,
                        const ContactComputation<dim> &computation);

    /// The VTU @p base.vtu (or pieces and @p base.pvtu) of @p computation;
    /// returns its name. @p what names it in errors.
    std::string
    write_vtu(const std::string             &base,
              const std::string             &what,
              const ContactComputation<dim> &computation,
              const Vector<double>          *eps_E,
              const Vector<double>          *eps_ex_E);

    MPI_Comm           mpi_communicator;
    ConditionalOStream pcout;
    std::string        directory;
    bool               with_vtu = true;
    /// Output/Cells per file
    unsigned int    cells_per_file = 100000;
    bool            with_timing    = true;
    OutputDirectory output_files;
    CsvTable        statistics_table;
    /// eps_ex,E of the current computation (reference_comparison()), empty
    /// if there is none; write() consumes it
    Vector<double> local_exact_error;
    /// (cycle, file) of the VTU files written, for solution.pvd
    std::vector<std::pair<double, std::string>> vtu_files;
    /// One row per load step (Contact/Load steps > 1): load-steps.csv
    CsvTable steps_table;
    /// (t, file) of the current cycle's load steps, for steps-CC.pvd
    std::vector<std::pair<double, std::string>> step_vtu_files;
  };
} // namespace Signorini

#endif
