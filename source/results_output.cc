#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_simplex_p.h>

#include <deal.II/numerics/data_out.h>

#include <signorini/adaptation/mesh_quality.h>
#include <signorini/cell_data_postprocessor.h>
#include <signorini/input_error.h>
#include <signorini/progress.h>
#include <signorini/results_output.h>
#include <signorini/stress_postprocessor.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// @p x with three significant digits.
    std::string
    brief(const double x)
    {
      std::ostringstream text;
      text << std::setprecision(3) << x;
      return text.str();
    }



    /// DataOut with the names of its datasets (the fields' components) in
    /// reach, to name a field in a message.
    template <int dim>
    class NamedDataOut : public DataOut<dim>
    {
    public:
      using DataOut<dim>::get_dataset_names;
    };



    /// What a message about the VTU's single precision suggests.
    const std::string single_precision_remedy =
      ": choose units (of length, and of stress for Material/Young modulus "
      "and the loads) that keep the values within it, or set Output/Write "
      "vtu = false";



    /// Values beyond what the VTU file holds, in the patches of the pieces
    /// of this rank: deal.II writes Float32, so a finite double beyond
    /// 3.4e38 has become inf in the patches. (A NaN is written on purpose
    /// where a local effectivity is undefined.)
    struct SinglePrecisionOverflow
    {
      /// the first data set with an inf (invalid_unsigned_int: none)
      unsigned int first_field = numbers::invalid_unsigned_int;
      bool         coordinates = false;
    };

    /// Add the patches built into @p data_out to @p overflow.
    template <int dim>
    void
    scan_single_precision(const NamedDataOut<dim> &data_out,
                          SinglePrecisionOverflow &overflow)
    {
      for (const auto &patch : data_out.get_patches())
        {
          for (const auto &vertex : patch.vertices)
            for (unsigned int d = 0; d < dim; ++d)
              overflow.coordinates |= std::isinf(float(vertex[d]));
          for (unsigned int i = 0; i < patch.data.n_rows(); ++i)
            for (unsigned int j = 0; j < patch.data.n_cols(); ++j)
              if (std::isinf(patch.data(i, j)))
                overflow.first_field = std::min(overflow.first_field, i);
        }
    }

    /// Throw an InputError naming the field (or the mesh coordinates) if
    /// any rank found a value beyond single precision. The same decision on
    /// every rank.
    void
    refuse_beyond_single_precision(const std::string              &what,
                                   const SinglePrecisionOverflow  &overflow,
                                   const std::vector<std::string> &names,
                                   const MPI_Comm                  communicator)
    {
      const unsigned int first_overflow =
        Utilities::MPI::min(overflow.first_field, communicator);
      const bool coordinates =
        Utilities::MPI::logical_or(overflow.coordinates, communicator);
      const std::string units =
        " beyond the single precision of the VTU output (3.4e38)" +
        single_precision_remedy;
      if (coordinates)
        throw InputError(what + ": mesh coordinates" + units);
      if (first_overflow != numbers::invalid_unsigned_int)
        throw InputError(
          what + ": the field " +
          (first_overflow < names.size() ? names[first_overflow] : "?") +
          " reaches values" + units);
    }



    /**
     * Throw an InputError if the displacements, the stresses or the forces
     * of @p computation, by their scales, are not zero but below the
     * smallest normal single precision number: DataOut would silently
     * write zeros or subnormal values into the VTU file, though the CSV
     * tables hold them. The scales, not the fields' values: a field that is
     * round-off (the stresses of a rigid motion) may well be written as 0.
     * The same decision on every rank.
     */
    template <int dim>
    void
    refuse_below_single_precision(const std::string             &what,
                                  const ContactComputation<dim> &computation)
    {
      const double length       = computation.domain_diameter();
      const double displacement = computation.displacement().linfty_norm();
      const double stress =
        computation.material().young_modulus * displacement / length;
      const std::pair<const char *, double> scales[] = {
        {"mesh coordinates (the diameter)", length},
        {"displacements", displacement},
        {"stresses (E |u|/diameter)", stress},
        {"nodal forces (E |u| diameter^(dim-2))",
         stress * std::pow(length, dim - 1)}};
      for (const auto &[name, scale] : scales)
        if (scale > 0. && scale < std::numeric_limits<float>::min())
          {
            std::ostringstream text;
            text << what << ": the " << name << " are of the order of " << scale
                 << ", below the single precision of the VTU output "
                    "(1.2e-38)"
                 << single_precision_remedy;
            throw InputError(text.str());
          }
    }



    /**
     * The fields of the nodes of GC as P1 functions that vanish away from
     * it: the contact pressure -Lambda, the nodal pressure and the active
     * set; with friction the status of each node (0 separated, 1 stick, 2
     * slip), its tangential force, its slip in the computation and its
     * accumulated slip.
     */
    template <int dim>
    struct ContactNodeFields
    {
      ContactNodeFields(const ContactComputation<dim> &computation,
                        const DoFHandler<dim>         &scalar_dof_handler)
        : pressure(scalar_dof_handler.n_dofs())
        , nodal_pressure(scalar_dof_handler.n_dofs())
        , active(scalar_dof_handler.n_dofs())
      {
        std::map<unsigned int, types::global_dof_index> dof_of_vertex;
        for (const auto &cell : scalar_dof_handler.active_cell_iterators())
          for (const unsigned int v : cell->vertex_indices())
            dof_of_vertex[cell->vertex_index(v)] = cell->vertex_dof_index(v, 0);
        const ContactBoundary<dim> &contact_boundary =
          computation.contact_boundary();
        const Vector<double> lambda =
          computation.condition().multiplier(computation.dual());
        const auto &multiplier_nodes = contact_boundary.multiplier_nodes();
        for (unsigned int i = 0; i < multiplier_nodes.size(); ++i)
          {
            const auto dof =
              dof_of_vertex[contact_boundary.node(multiplier_nodes[i]).vertex];
            pressure[dof] = -lambda[i];
            active[dof]   = computation.active_set()[i] ? 1. : 0.;
          }
        const Vector<double> pressures = contact_boundary.nodal_pressures(
          computation.condition().nodal_forces(computation.dual()));
        for (unsigned int k = 0; k < contact_boundary.n_nodes(); ++k)
          if (dof_of_vertex.count(contact_boundary.node(k).vertex) > 0)
            nodal_pressure[dof_of_vertex[contact_boundary.node(k).vertex]] =
              pressures[k];

        if (!computation.friction_law().enabled())
          return;
        const FrictionState<dim> &friction = computation.friction();
        const std::size_t         n_dofs   = computation.dof_handler().n_dofs();
        friction_status.reinit(scalar_dof_handler.n_dofs());
        tangential_force.reinit(n_dofs);
        slip.reinit(n_dofs);
        accumulated_slip.reinit(n_dofs);
        for (unsigned int i = 0; i < friction.status.size(); ++i)
          {
            const auto &node = contact_boundary.node(multiplier_nodes[i]);
            friction_status[dof_of_vertex[node.vertex]] =
              static_cast<double>(friction.status[i]);
            for (unsigned int d = 0; d < dim; ++d)
              {
                tangential_force[node.dofs[d]] =
                  friction.nodal_force[multiplier_nodes[i]][d];
                slip[node.dofs[d]] = friction.slip[i][d];
                accumulated_slip[node.dofs[d]] =
                  friction.accumulated_slip[i][d];
              }
          }
      }

      /// Adds the fields to @p data_out (the friction fields if computed).
      void
      add_to(DataOut<dim>          &data_out,
             const DoFHandler<dim> &dof_handler,
             const DoFHandler<dim> &scalar_dof_handler) const
      {
        data_out.add_data_vector(scalar_dof_handler,
                                 pressure,
                                 "contact_pressure");
        data_out.add_data_vector(scalar_dof_handler,
                                 nodal_pressure,
                                 "nodal_pressure");
        data_out.add_data_vector(scalar_dof_handler, active, "contact_active");
        if (friction_status.size() == 0)
          return;
        const std::vector<
          DataComponentInterpretation::DataComponentInterpretation>
          vector_part(dim,
                      DataComponentInterpretation::component_is_part_of_vector);
        data_out.add_data_vector(scalar_dof_handler,
                                 friction_status,
                                 "friction_status");
        data_out.add_data_vector(dof_handler,
                                 tangential_force,
                                 std::vector<std::string>(dim,
                                                          "tangential_force"),
                                 vector_part);
        data_out.add_data_vector(dof_handler,
                                 slip,
                                 std::vector<std::string>(dim, "slip"),
                                 vector_part);
        data_out.add_data_vector(dof_handler,
                                 accumulated_slip,
                                 std::vector<std::string>(dim,
                                                          "accumulated_slip"),
                                 vector_part);
      }

      Vector<double> pressure, nodal_pressure, active;
      Vector<double> friction_status, tangential_force, slip, accumulated_slip;
    };



    /**
     * Writes the patches of @p data_out (the fields of @p computation, the
     * cells this rank owns) as @p base.vtu, or, if a rank owns more than
     * @p cells_per_file cells, in pieces of at most that many, one at a time
     * (DataOut holds the patches of every cell it writes at once: about 0.9
     * kB per tetrahedron with these fields, 0.6 GB at 590k tetrahedra, more
     * than the low-memory solve; doc/benchmarks.md), each a .vtu file listed
     * in @p base.pvtu. Every piece is checked against single precision
     * before any is written (@p what names the file in errors). Returns the
     * name to list in the .pvd record.
     */
    template <int dim>
    std::string
    write_in_pieces(const std::string             &base,
                    const std::string             &what,
                    const ContactComputation<dim> &computation,
                    NamedDataOut<dim>             &data_out,
                    const unsigned int             cells_per_file,
                    OutputDirectory               &output_files,
                    const MPI_Comm                 mpi_communicator)
    {
      const bool root = Utilities::MPI::this_mpi_process(mpi_communicator) == 0;
      using cell_iterator = typename Triangulation<dim>::cell_iterator;
      const Triangulation<dim> &triangulation =
        computation.dof_handler().get_triangulation();
      const auto        range = triangulation.active_cell_iterators();
      const std::size_t n_owned =
        std::count_if(range.begin(), range.end(), [](const auto &cell) {
          return cell->is_locally_owned();
        });
      const unsigned int n_local_pieces =
        std::max<std::size_t>(1,
                              (n_owned + cells_per_file - 1) / cells_per_file);
      const std::vector<unsigned int> pieces_of_rank =
        Utilities::MPI::all_gather(mpi_communicator, n_local_pieces);
      const unsigned int rank =
        Utilities::MPI::this_mpi_process(mpi_communicator);
      const unsigned int first_piece =
        std::accumulate(pieces_of_rank.begin(),
                        pieces_of_rank.begin() + rank,
                        0u);
      const unsigned int n_pieces =
        std::accumulate(pieces_of_rank.begin(), pieces_of_rank.end(), 0u);
      // piece p: the owned cells n_owned p / n_local_pieces and on, in
      // DataOut's order, up to the first of the next piece (or the end)
      std::vector<cell_iterator> piece_start;
      unsigned int               piece = 0;
      if (n_local_pieces > 1)
        {
          std::size_t k = 0;
          for (const auto &cell : range)
            if (cell->is_locally_owned())
              {
                if (k == n_owned * piece_start.size() / n_local_pieces)
                  piece_start.push_back(cell);
                ++k;
              }
          piece_start.push_back(triangulation.end());
          data_out.set_cell_selection(
            [&](const Triangulation<dim> &) { return piece_start[piece]; },
            [&](const Triangulation<dim> &tria,
                const cell_iterator      &cell) -> cell_iterator {
              typename Triangulation<dim>::active_cell_iterator next = cell;
              do
                ++next;
              while (next != tria.end() && !next->is_locally_owned());
              return next == piece_start[piece + 1] ? tria.end() : next;
            });
        }
      const auto build_piece = [&](const unsigned int p) {
        piece = p;
        data_out.build_patches(computation.mapping());
      };

      // every piece checked before any is written
      SinglePrecisionOverflow overflow;
      for (unsigned int p = 0; p < n_local_pieces; ++p)
        {
          build_piece(p);
          scan_single_precision(data_out, overflow);
        }
      refuse_beyond_single_precision(what,
                                     overflow,
                                     data_out.get_dataset_names(),
                                     mpi_communicator);
      refuse_below_single_precision(what, computation);
      // zlib's fastest level: deal.II's default, its best, takes 3 times as
      // long for files about 10 % smaller (bench/small_runs)
      DataOutBase::VtkFlags vtk_flags;
      vtk_flags.compression_level = DataOutBase::VtkFlags::best_speed;
      data_out.set_flags(vtk_flags);
      // one file for one piece; else base.PPP.vtu, the pieces numbered rank
      // by rank, and a .pvtu record
      if (n_pieces == 1)
        {
          const std::string name = base + ".vtu";
          output_files.write(name, [&](std::ostream &out) {
            data_out.write_vtu(out);
          });
          return name;
        }
      std::vector<std::string> pieces;
      for (unsigned int p = 0; p < n_pieces; ++p)
        pieces.push_back(base + "." + Utilities::int_to_string(p, 3) + ".vtu");
      // rank 0 lists every piece before any is written, so that a run
      // stopped in between leaves no unlisted file
      if (root)
        for (const auto &file : pieces)
          output_files.record(file);
      MPI_Barrier(mpi_communicator);
      for (unsigned int p = 0; p < n_local_pieces; ++p)
        {
          if (n_local_pieces > 1)
            build_piece(p);
          output_files.write(pieces[first_piece + p], [&](std::ostream &out) {
            data_out.write_vtu(out);
          });
        }
      const std::string name = base + ".pvtu";
      if (root)
        output_files.write(name, [&](std::ostream &out) {
          data_out.write_pvtu_record(out, pieces);
        });
      return name;
    }
  } // namespace



  template <int dim>
  void
  ResultsOutput<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Output directory",
                      "output",
                      Patterns::DirectoryName(),
                      "Where the VTU/PVD files, the CSV tables and the "
                      "parameters used are written (created if needed; a "
                      "relative path is taken from the working directory, "
                      "where mesh files are taken from the parameter "
                      "file's). A "
                      "run first deletes the files of the previous run there, "
                      "as listed in .signorini-manifest, and nothing else.");
    prm.enter_subsection("Output");
    {
      prm.declare_entry("Write vtu",
                        "true",
                        Patterns::Bool(),
                        "Write solution-CC.vtu (or .pvtu and its pieces) and "
                        "solution.pvd for ParaView.");
      prm.declare_entry("Cells per file",
                        "100000",
                        Patterns::Integer(1),
                        "The most cells of one rank in one .vtu file: a rank "
                        "with more writes them in pieces, one at a time, "
                        "listed in a .pvtu record (the output's memory is "
                        "about 1 kB per cell of a piece).");
      prm.declare_entry("Print timing",
                        "true",
                        Patterns::Bool(),
                        "Print the time and the peak memory of each phase, "
                        "the solve time and, every 10 s of a long phase, a "
                        "progress line on screen (off in regression tests: "
                        "times vary).");
    }
    prm.leave_subsection();
  }



  template <int dim>
  ResultsOutput<dim>::ResultsOutput()
    : mpi_communicator(MPI_COMM_WORLD)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
  {}



  template <int dim>
  void
  ResultsOutput<dim>::parse_parameters(ParameterHandler &prm)
  {
    directory = prm.get("Output directory");
    prm.enter_subsection("Output");
    with_vtu       = prm.get_bool("Write vtu");
    cells_per_file = prm.get_integer("Cells per file");
    with_timing    = prm.get_bool("Print timing");
    Progress::set_interval(with_timing ? 10. : 0.);
    prm.leave_subsection();
  }



  template <int dim>
  void
  ResultsOutput<dim>::initialize()
  {
    output_files.initialize(directory, mpi_communicator);
  }



  template <int dim>
  void
  ResultsOutput<dim>::start_run(const ParameterHandler &prm)
  {
    // the files of the previous run go first: the directory holds one run
    if (pcout.is_active())
      {
        output_files.start_run();
        output_files.write("parameters.prm", [&](std::ostream &out) {
          prm.print_parameters(out, ParameterHandler::PRM);
        });
      }
    MPI_Barrier(mpi_communicator);
  }



  template <int dim>
  ConditionalOStream &
  ResultsOutput<dim>::screen()
  {
    return pcout;
  }



  template <int dim>
  bool
  ResultsOutput<dim>::print_timing() const
  {
    return with_timing;
  }



  template <int dim>
  const CsvTable &
  ResultsOutput<dim>::statistics() const
  {
    return statistics_table;
  }



  template <int dim>
  void
  ResultsOutput<dim>::message(const std::string &text)
  {
    pcout << text << std::endl;
  }



  template <int dim>
  void
  ResultsOutput<dim>::mesh(const unsigned int             cycle,
                           const AdaptiveMesh<dim>       &adaptive_mesh,
                           const ContactComputation<dim> &computation,
                           const double                   predicted_cells,
                           const bool                     with_prediction)
  {
    const Triangulation<dim> &triangulation =
      computation.dof_handler().get_triangulation();
    const double min_angle = minimum_angle(triangulation);
    pcout << "Cycle " << cycle << ": " << triangulation.n_active_cells()
          << " cells, " << computation.dof_handler().n_dofs() << " DoFs, "
          << computation.contact_boundary().n_nodes() << " nodes on GC ("
          << computation.condition().n_constraints() << " with a multiplier)"
          << std::endl;
    if (with_prediction)
      {
        pcout << "   mesh: " << triangulation.n_active_cells() << " cells";
        if (cycle > 0)
          pcout << " (predicted N* = "
                << static_cast<unsigned long>(std::round(predicted_cells))
                << ")";
        pcout << ", " << triangulation.n_used_vertices() << " nodes, "
              << adaptive_mesh.n_green_cells() << " green cells, minimum angle "
              << std::setprecision(4) << min_angle << " degrees"
              << std::setprecision(6) << std::endl;
      }
    statistics_table.add_value("cycle", cycle);
    statistics_table.add_value("cells", triangulation.n_active_cells());
    statistics_table.add_value("dofs", computation.dof_handler().n_dofs());
    statistics_table.add_value("nodes", triangulation.n_used_vertices());
    statistics_table.add_value("predicted_cells", predicted_cells);
    statistics_table.add_value("green_cells", adaptive_mesh.n_green_cells());
    statistics_table.add_value("min_angle", min_angle);
  }



  template <int dim>
  void
  ResultsOutput<dim>::print_contact_solve(
    const ContactComputation<dim> &computation)
  {
    const auto &summary = computation.summary();
    const auto &report  = summary.report;
    const auto &checks  = summary.checks;
    pcout << "   " << computation.condition().name() << " condition, "
          << computation.solver().name() << ": " << report.iterations
          << " iterations, " << report.linear_solves << " linear solves ("
          << report.linear_iterations << " CG iterations, "
          << computation.linear_solver().method() << ")" << std::endl
          << "   active nodes " << summary.n_active << " of "
          << computation.condition().n_constraints() << ", energy "
          << std::setprecision(10) << summary.energy << ", contact force "
          << std::setprecision(6) << summary.contact_force << std::endl
          << std::setprecision(2) << std::scientific
          << "   checks: feasibility " << checks.feasibility
          << ", multiplier sign " << checks.multiplier_sign
          << ", complementarity " << checks.complementarity << ", residual "
          << checks.residual << ", resultant " << checks.resultant
          << std::defaultfloat << std::setprecision(6) << std::endl;
    if (computation.friction_law().enabled())
      {
        using Status      = typename FrictionState<dim>::Status;
        const auto &state = computation.friction();
        pcout << "   friction (" << computation.friction_law().name()
              << "): " << state.count(Status::stick) << " nodes stick, "
              << state.count(Status::slip) << " slip, tangential force "
              << state.total_force() << std::endl
              << std::setprecision(2) << std::scientific
              << (state.fixed_point.tresca_solves > 0 ?
                    "   fixed point on the Tresca threshold: " +
                      std::to_string(state.fixed_point.tresca_solves) +
                      " Tresca solves" +
                      (state.fixed_point.contraction > 0. ?
                         ", largest ratio of successive changes " +
                           brief(state.fixed_point.contraction) :
                         std::string()) +
                      "\n" :
                    std::string())
              << (state.contraction_at_solution ?
                    "   contraction at the solution " +
                      brief(*state.contraction_at_solution) + " (" +
                      std::to_string(state.contraction_steps) +
                      (state.contraction_steps == 1 ? " Arnoldi step; " :
                                                      " Arnoldi steps; ") +
                      (*state.contraction_at_solution < 1. ?
                         "locally unique)\n" :
                         "uniqueness not shown)\n") :
                    std::string())
              << "   friction checks: bound " << checks.friction_bound
              << ", stick " << checks.stick << ", slip " << checks.slip
              << std::defaultfloat << std::setprecision(6) << std::endl;
      }
    if (summary.nested.meshes > 0)
      pcout << "   nested start: " << summary.nested.meshes << " coarser mesh"
            << (summary.nested.meshes > 1 ? "es, " : ", ")
            << summary.nested.iterations << " iterations in all" << std::endl;
    if (!summary.nested.failure.empty())
      pcout << "   nested start abandoned (cold start): "
            << summary.nested.failure << std::endl;
    if (with_timing)
      {
        pcout << "   contact solve " << summary.solve_seconds << " s";
        if (summary.nested.meshes > 0)
          pcout << " (nested start " << summary.nested.seconds << " s)";
        pcout << std::endl;
      }
  }



  namespace
  {
    /// The contact solve's columns of a statistics row.
    template <int dim>
    void
    add_contact_columns(CsvTable                      &table,
                        const ContactComputation<dim> &computation)
    {
      const auto &summary = computation.summary();
      const auto &report  = summary.report;
      table.add_value("contact_nodes", computation.condition().n_constraints());
      table.add_value("active_nodes", summary.n_active);
      table.add_value("condition", computation.condition().name());
      table.add_value("solver", computation.solver().name());
      table.add_value("linear_solver", computation.linear_solver().method());
      table.add_value("iterations", report.iterations);
      table.add_value("linear_solves", report.linear_solves);
      table.add_value("cg_iterations", report.linear_iterations);
      table.add_value("nested_meshes", summary.nested.meshes);
      table.add_value("nested_iterations", summary.nested.iterations);
      table.add_value("converged", computation.converged() ? 1u : 0u);
      table.add_value("kkt_residual", report.residual);
      table.add_value("energy", summary.energy);
      table.add_value("contact_force", summary.contact_force);
      table.add_value("setup_seconds", summary.setup_seconds);
      table.add_value("solve_seconds", summary.solve_seconds);
      table.add_value("feasibility", summary.checks.feasibility);
      table.add_value("multiplier_sign", summary.checks.multiplier_sign);
      table.add_value("complementarity", summary.checks.complementarity);
      table.add_value("residual", summary.checks.residual);
      table.add_value("resultant", summary.checks.resultant);
      table.add_value("contact_cells",
                      computation.contact_boundary().n_contact_cells());
      if (computation.friction_law().enabled())
        {
          using Status      = typename FrictionState<dim>::Status;
          const auto &state = computation.friction();
          table.add_value("stick_nodes", state.count(Status::stick));
          table.add_value("slip_nodes", state.count(Status::slip));
          table.add_value("tangential_force", state.total_force().norm());
          table.add_value("friction_bound", summary.checks.friction_bound);
          table.add_value("stick", summary.checks.stick);
          table.add_value("slip", summary.checks.slip);
          if (state.contraction_at_solution)
            {
              table.add_value("contraction_at_solution",
                              *state.contraction_at_solution);
              table.add_value("contraction_steps", state.contraction_steps);
            }
          if (state.fixed_point.tresca_solves > 0)
            {
              table.add_value("tresca_solves", state.fixed_point.tresca_solves);
              table.add_value("contraction", state.fixed_point.contraction);
            }
        }
    }
  } // namespace



  template <int dim>
  void
  ResultsOutput<dim>::contact_solve(const ContactComputation<dim> &computation)
  {
    print_contact_solve(computation);
    add_contact_columns(statistics_table, computation);
  }



  template <int dim>
  void
  ResultsOutput<dim>::load_step(const unsigned int             cycle,
                                const unsigned int             step,
                                const ContactComputation<dim> &computation)
  {
    const LoadPath &path    = computation.load_path();
    const auto     &summary = computation.summary();
    if (step == 1)
      step_vtu_files.clear();
    pcout << "   load step " << step << " of " << path.n_steps()
          << " (t = " << path.time(step) << ", factor " << path.factor(step)
          << "): " << summary.n_active << " active nodes";
    if (computation.friction_law().enabled())
      {
        using Status      = typename FrictionState<dim>::Status;
        const auto &state = computation.friction();
        pcout << ", " << state.count(Status::stick) << " stick, "
              << state.count(Status::slip) << " slip, tangential force "
              << state.total_force();
        if (state.contraction_at_solution)
          pcout << ", contraction " << brief(*state.contraction_at_solution);
      }
    pcout << ", " << summary.report.iterations << " iterations"
          << (computation.converged() ? "" : ": " + computation.failure())
          << std::endl;

    steps_table.add_value("cycle", cycle);
    steps_table.add_value("step", step);
    steps_table.add_value("time", path.time(step));
    steps_table.add_value("factor", path.factor(step));
    add_contact_columns(steps_table, computation);
    steps_table.end_row();
    // the table and the pvd record are rewritten whole: on a long path only
    // a hundred times, and at its end or failure (10 000 steps spent 93 %
    // of their time rewriting them at every step)
    const unsigned int stride = std::max(1u, path.n_steps() / 100);
    const bool rewrite        = (step % stride == 0 || step == path.n_steps() ||
                          !computation.converged());
    if (pcout.is_active() && rewrite)
      output_files.write("load-steps.csv",
                         [&](std::ostream &out) { steps_table.write(out); });

    const std::string label =
      Utilities::int_to_string(cycle, 2) + "-" +
      Utilities::int_to_string(step, Utilities::needed_digits(path.n_steps()));
    write_contact_table("contact-" + label + ".csv", computation);
    if (!with_vtu)
      return;
    step_vtu_files.emplace_back(path.time(step),
                                write_vtu("solution-" + label,
                                          "cycle " + std::to_string(cycle) +
                                            ", load step " +
                                            std::to_string(step),
                                          computation,
                                          nullptr,
                                          nullptr));
    if (pcout.is_active() && rewrite)
      output_files.write("steps-" + Utilities::int_to_string(cycle, 2) + ".pvd",
                         [&](std::ostream &out) {
                           DataOutBase::write_pvd_record(out, step_vtu_files);
                         });
  }



  template <int dim>
  void
  ResultsOutput<dim>::error_estimate(
    const typename ConstitutiveRelationError<dim>::Result &estimate,
    const double                                           seconds)
  {
    pcout << "   error in constitutive relation: eps = " << std::setprecision(4)
          << 100. * estimate.eps << " % (contact term "
          << 100. * estimate.eps_contact << " % of e^2)" << std::setprecision(6)
          << (estimate.stress_free ?
                ": no stress (to round-off), the solution is exact" :
                "")
          << std::endl;
    if (estimate.polluted_by_round_off && !estimate.stress_free)
      pcout << "Warning: the strains are within 1e5 round-offs of the "
               "displacement (a rigid motion much larger than the "
               "deformation): eps is polluted by round-off; take the rigid "
               "motion out of the data"
            << std::endl;
    // (a load step that slides far under a small load: the friction term,
    // the slip of the step times its bound between the nodes, made eps 100 %
    // for an error of 12 %)
    // (not where e^2 is round-off of the denominator: its shares mean
    // nothing)
    if (estimate.eps_contact > 0.9 && !estimate.stress_free &&
        estimate.eps > 1e-6)
      pcout << "Warning: the contact term is " << std::setprecision(3)
            << 100. * estimate.eps_contact
            << " % of e^2: eps measures mostly how far the admissible contact "
               "fields are from the contact law between the nodes, and may "
               "be far above the error (e.g. a load step whose slip is large "
               "against its loads)"
            << std::setprecision(6) << std::endl;
    if (with_timing && !estimate.step_seconds.empty())
      {
        pcout << "   estimate steps (rank 0):";
        for (const auto &[step, seconds] : estimate.step_seconds)
          pcout << (&step == &estimate.step_seconds.front().first ? " " : ", ")
                << step << ' ' << std::setprecision(3) << seconds << " s";
        pcout << std::setprecision(6) << std::endl;
      }
    statistics_table.add_value("e", std::sqrt(estimate.e_squared));
    statistics_table.add_value("eps", estimate.eps);
    statistics_table.add_value("eps_contact", estimate.eps_contact);
    statistics_table.add_value("estimate_seconds", seconds);
    statistics_table.add_value("equilibrium_defect",
                               estimate.equilibrium_defect);
    statistics_table.add_value("condition_defect", estimate.condition_defect);
  }



  template <int dim>
  void
  ResultsOutput<dim>::size_prediction(
    const std::string               &predictor,
    const SizePredictor::Prediction &prediction)
  {
    pcout << "   " << predictor << " prediction: N* = "
          << static_cast<unsigned long>(std::round(prediction.predicted_cells))
          << " elements for eps* = " << std::setprecision(4)
          << 100. * prediction.predicted_error << " %" << std::setprecision(6)
          << std::endl;
  }



  template <int dim>
  void
  ResultsOutput<dim>::exact_error(
    const typename ExactSolution<dim>::Error              &error,
    const typename ConstitutiveRelationError<dim>::Result *estimate)
  {
    pcout << "   energy-norm error " << error.energy_error;
    statistics_table.add_value("energy_error", error.energy_error);
    // (undefined for a zero exact solution: left empty)
    if (error.relative_energy_error >= 0.)
      {
        pcout << " (relative to the exact solution's norm "
              << error.relative_energy_error << ")";
        statistics_table.add_value("relative_energy_error",
                                   error.relative_energy_error);
      }
    // (eps divides e by a norm of both fields, about sqrt(2) times the
    // solution's: the effectivity is the comparison that means something;
    // not where the error is round-off, or the precision of the exact
    // solution's gradient: the uniaxial 3D block, reproduced exactly, gave
    // an effectivity of 2e-4)
    if (estimate != nullptr && error.relative_energy_error > 1e-6)
      pcout << ", effectivity e / error = "
            << std::sqrt(estimate->e_squared) / error.energy_error;
    pcout << std::endl;
  }



  template <int dim>
  void
  ResultsOutput<dim>::reference_comparison(
    const typename ReferenceSolution<dim>::Comparison &comparison,
    const types::global_dof_index                      reference_dofs,
    const bool                                         underestimated,
    const bool                                         with_estimate)
  {
    statistics_table.add_value("eps_ex", comparison.eps_ex);
    // a coarser reference leaves cells without reference cells: no field
    if (underestimated)
      local_exact_error.reinit(0);
    else
      local_exact_error = comparison.local;
    pcout << "   exact error (reference " << reference_dofs
          << " DoFs): eps_ex = " << std::setprecision(4)
          << 100. * comparison.eps_ex << " %";
    if (underestimated)
      pcout << " (the reference is not finer than this mesh everywhere: "
               "eps_ex and the effectivity are not reliable, the reference's "
               "own error enters them and the error it cannot resolve does "
               "not; see Reference solution/Mesh)";
    if (with_estimate)
      {
        statistics_table.add_value("effectivity", comparison.effectivity);
        statistics_table.add_value("prager_synge_ratio",
                                   comparison.prager_synge_ratio);
        pcout << ", effectivity " << comparison.effectivity
              << ", ||U_ref - U^|| / e = " << comparison.prager_synge_ratio;
      }
    pcout << std::setprecision(6) << std::endl;
  }



  template <int dim>
  void
  ResultsOutput<dim>::final_reference_comparison(
    const std::vector<typename ReferenceSolution<dim>::Comparison> &comparisons,
    const bool with_estimate)
  {
    for (unsigned int k = 0; k < comparisons.size(); ++k)
      {
        const auto &comparison = comparisons[k];
        statistics_table.set_value(k, "eps_ex", comparison.eps_ex);
        pcout << "   computation " << k << ": eps_ex = " << std::setprecision(4)
              << 100. * comparison.eps_ex << " %";
        if (with_estimate)
          {
            statistics_table.set_value(k,
                                       "effectivity",
                                       comparison.effectivity);
            statistics_table.set_value(k,
                                       "prager_synge_ratio",
                                       comparison.prager_synge_ratio);
            pcout << ", effectivity " << comparison.effectivity
                  << ", ||U_ref - U^|| / e = " << comparison.prager_synge_ratio;
          }
        pcout << std::setprecision(6) << std::endl;
      }
    write_statistics();
  }



  template <int dim>
  void
  ResultsOutput<dim>::write_statistics()
  {
    if (pcout.is_active())
      output_files.write("statistics.csv", [&](std::ostream &out) {
        statistics_table.write(out);
      });
  }



  template <int dim>
  void
  ResultsOutput<dim>::write_contact_table(
    const std::string             &file_name,
    const ContactComputation<dim> &computation)
  {
    // One row per node of GC, sorted by position.
    const ContactBoundary<dim> &contact_boundary =
      computation.contact_boundary();
    const unsigned int        n = contact_boundary.n_nodes();
    std::vector<unsigned int> order(n);
    for (unsigned int k = 0; k < n; ++k)
      order[k] = k;
    std::sort(order.begin(), order.end(), [&](unsigned int a, unsigned int b) {
      const auto &pa = contact_boundary.node(a).position;
      const auto &pb = contact_boundary.node(b).position;
      return std::lexicographical_compare(&pa[0],
                                          &pa[0] + dim,
                                          &pb[0],
                                          &pb[0] + dim);
    });
    std::vector<int> row_of_node(n, -1);
    const auto      &multiplier_nodes = contact_boundary.multiplier_nodes();
    for (unsigned int i = 0; i < multiplier_nodes.size(); ++i)
      row_of_node[multiplier_nodes[i]] = i;

    const Vector<double> &dual = computation.dual();
    const Vector<double>  q_n =
      contact_boundary.normal_components(computation.displacement());
    const Vector<double> lambda = computation.condition().multiplier(dual);
    const Vector<double> forces = computation.condition().nodal_forces(dual);
    const std::vector<bool> &active = computation.active_set();
    if (!pcout.is_active())
      return;
    const Vector<double> pressures = contact_boundary.nodal_pressures(forces);

    // with friction: per node its status, tangential force and slip
    using Status                       = typename FrictionState<dim>::Status;
    const FrictionState<dim> &friction = computation.friction();
    const bool        with_friction    = computation.friction_law().enabled();
    const char *const status_names[]   = {"separated", "stick", "slip"};

    output_files.write(file_name, [&](std::ostream &out) {
      const char *coordinates[] = {"x", "y", "z"};
      for (unsigned int d = 0; d < dim; ++d)
        out << coordinates[d] << ',';
      out << "multiplier_node,normal_displacement,gap,Lambda,"
             "nodal_force,active,nodal_pressure";
      if (with_friction)
        {
          out << ",friction_status";
          for (unsigned int d = 0; d < dim; ++d)
            out << ",tangential_force_" << coordinates[d];
          for (unsigned int d = 0; d < dim; ++d)
            out << ",slip_" << coordinates[d];
          for (unsigned int d = 0; d < dim; ++d)
            out << ",accumulated_slip_" << coordinates[d];
        }
      out << '\n' << std::setprecision(12);
      for (const unsigned int k : order)
        {
          const auto &node = contact_boundary.node(k);
          const int   i    = row_of_node[k];
          for (unsigned int d = 0; d < dim; ++d)
            out << node.position[d] << ',';
          out << (i >= 0 ? 1 : 0) << ',' << q_n[k] << ','
              << contact_boundary.nodal_gap()[k] << ','
              << (i >= 0 ? lambda[i] : 0.) << ',' << forces[k] << ','
              << ((i >= 0 && active[i]) ? 1 : 0) << ',' << pressures[k];
          if (with_friction)
            {
              out << ','
                  << (i >= 0 ?
                        status_names[static_cast<int>(friction.status[i])] :
                        "held");
              for (unsigned int d = 0; d < dim; ++d)
                out << ',' << friction.nodal_force[k][d];
              for (unsigned int d = 0; d < dim; ++d)
                out << ',' << (i >= 0 ? friction.slip[i][d] : 0.);
              for (unsigned int d = 0; d < dim; ++d)
                out << ',' << (i >= 0 ? friction.accumulated_slip[i][d] : 0.);
            }
          out << '\n';
        }
    });
  }



  template <int dim>
  void
  ResultsOutput<dim>::write(const unsigned int             cycle,
                            const ContactComputation<dim> &computation,
                            const Vector<double>          *eps_E)
  {
    const std::string label = Utilities::int_to_string(cycle, 2);
    write_contact_table("contact-" + label + ".csv", computation);
    statistics_table.end_row();
    write_statistics();
    if (with_vtu)
      {
        vtu_files.emplace_back(cycle,
                               write_vtu("solution-" + label,
                                         "cycle " + std::to_string(cycle),
                                         computation,
                                         eps_E,
                                         local_exact_error.size() > 0 ?
                                           &local_exact_error :
                                           nullptr));
        if (pcout.is_active())
          output_files.write("solution.pvd", [&](std::ostream &out) {
            DataOutBase::write_pvd_record(out, vtu_files);
          });
      }
    local_exact_error.reinit(0);
  }



  template <int dim>
  std::string
  ResultsOutput<dim>::write_vtu(const std::string             &base,
                                const std::string             &what,
                                const ContactComputation<dim> &computation,
                                const Vector<double>          *eps_E,
                                const Vector<double>          *eps_ex_E)
  {
    const DoFHandler<dim> &dof_handler = computation.dof_handler();
    const FE_SimplexP<dim> scalar_fe(1);
    DoFHandler<dim>        scalar_dof_handler(dof_handler.get_triangulation());
    scalar_dof_handler.distribute_dofs(scalar_fe);
    const ContactNodeFields<dim> contact_fields(computation,
                                                scalar_dof_handler);

    const StressPostprocessor<dim> stress(computation.material());
    NamedDataOut<dim>              data_out; // (the cells this rank owns)
    const std::vector<DataComponentInterpretation::DataComponentInterpretation>
                     vector_part(dim,
                  DataComponentInterpretation::component_is_part_of_vector);
    const LA::Vector ghosted = with_ghosts(computation.displacement(),
                                           computation.locally_relevant_dofs());
    data_out.add_data_vector(dof_handler,
                             ghosted,
                             std::vector<std::string>(dim, "displacement"),
                             vector_part);
    data_out.add_data_vector(dof_handler, ghosted, stress);
    contact_fields.add_to(data_out, dof_handler, scalar_dof_handler);
    std::unique_ptr<CellDataPostprocessor<dim>> eps_E_field;
    if (eps_E != nullptr)
      {
        eps_E_field =
          std::make_unique<CellDataPostprocessor<dim>>("eps_E", *eps_E);
        data_out.add_data_vector(dof_handler, ghosted, *eps_E_field);
      }
    // the exact error per cell next to eps_E, and their ratio
    Vector<double>                              local_effectivity;
    std::unique_ptr<CellDataPostprocessor<dim>> eps_ex_E_field;
    std::unique_ptr<CellDataPostprocessor<dim>> effectivity_field;
    if (eps_ex_E != nullptr)
      {
        eps_ex_E_field =
          std::make_unique<CellDataPostprocessor<dim>>("eps_ex_E", *eps_ex_E);
        data_out.add_data_vector(dof_handler, ghosted, *eps_ex_E_field);
        if (eps_E != nullptr)
          {
            local_effectivity.reinit(eps_E->size());
            for (unsigned int E = 0; E < eps_E->size(); ++E)
              local_effectivity[E] = (*eps_ex_E)[E] > 0. ?
                                       (*eps_E)[E] / (*eps_ex_E)[E] :
                                       std::numeric_limits<double>::quiet_NaN();
            effectivity_field =
              std::make_unique<CellDataPostprocessor<dim>>("local_effectivity",
                                                           local_effectivity);
            data_out.add_data_vector(dof_handler, ghosted, *effectivity_field);
          }
      }
    return write_in_pieces(base,
                           what,
                           computation,
                           data_out,
                           cells_per_file,
                           output_files,
                           mpi_communicator);
  }



  template class ResultsOutput<2>;
  template class ResultsOutput<3>;
} // namespace Signorini
