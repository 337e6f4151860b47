#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <signorini/adaptation/mesh_quality.h>
#include <signorini/cell_data_postprocessor.h>
#include <signorini/input_error.h>
#include <signorini/nodal_interpolation.h>
#include <signorini/signorini_problem.h>
#include <signorini/stress_postprocessor.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace Signorini
{
  template <int dim>
  void
  SignoriniProblem<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Output directory",
                      "output",
                      Patterns::DirectoryName(),
                      "Where the VTU/PVD files, the CSV tables and the "
                      "parameters used are written (created if needed). A "
                      "run first deletes the files of the previous run there, "
                      "as listed in .signorini-manifest, and nothing else.");
    prm.declare_entry("Number of cycles",
                      "1",
                      Patterns::Integer(1, 100),
                      "Number of computations (meshes); with a target error "
                      "(Mesh adaptation) the largest number.");
    prm.declare_entry("Maximum cells",
                      "4e6",
                      Patterns::Double(1.),
                      "No mesh of more triangles is built: refused at input "
                      "when its size is known (Initial refinements, uniform "
                      "cycles, a reference on the initial mesh), before it is "
                      "built for an adapted mesh. P1 triangles carry about 1 "
                      "DoF each and the contact solve needs about 1.5 GB per "
                      "million DoFs: 4e6 takes 6 GB, a quarter of a 24 GiB "
                      "machine, leaving room for the estimator, the mesh "
                      "every MPI rank holds and a reference solution.");
    prm.enter_subsection("Output");
    {
      prm.declare_entry("Write vtu",
                        "true",
                        Patterns::Bool(),
                        "Write solution-CC.vtu and solution.pvd for ParaView.");
      prm.declare_entry("Print timing",
                        "true",
                        Patterns::Bool(),
                        "Print the TimerOutput summary and the solve time on "
                        "screen (off in regression tests: times vary).");
    }
    prm.leave_subsection();
    prm.enter_subsection("Exact solution");
    {
      prm.declare_entry("Enable",
                        "false",
                        Patterns::Bool(),
                        "Compare with a known displacement (manufactured "
                        "solution): adds energy_error to the statistics.");
      Functions::ParsedFunction<dim>::declare_parameters(prm, dim);
    }
    prm.leave_subsection();

    prm.enter_subsection("Contact");
    prm.declare_entry("Initial active set from previous cycle",
                      "true",
                      Patterns::Bool(),
                      "Start the active set method of a cycle from the "
                      "active set of the previous (coarser) cycle.");
    prm.declare_entry("Check tolerance",
                      "1e-6",
                      Patterns::Double(0., 1.),
                      "A computation whose relative solution checks "
                      "(feasibility, multiplier sign, complementarity, "
                      "residual, resultant) exceed this has failed (exit code "
                      "2), whatever its solver reports.");
    prm.leave_subsection();

    prm.enter_subsection("Reference solution");
    prm.declare_entry("Extra refinements",
                      "0",
                      Patterns::Integer(0, 6),
                      "If > 0, solve once on a finer mesh with the same "
                      "condition (see Mesh: the initial mesh refined this many "
                      "levels beyond Number of cycles - 1, or the last mesh "
                      "refined this many times) and report eps_ex, the "
                      "effectivity and the Prager-Synge check against it.");
    prm.declare_entry("Mesh",
                      "initial mesh",
                      Patterns::Selection("initial mesh|final mesh"),
                      "Refine the initial mesh uniformly (solved first; "
                      "nested in uniform cycles), or the last mesh of the "
                      "computations (solved last; for adapted meshes, which "
                      "are locally finer than any affordable uniform mesh).");
    prm.leave_subsection();

    MeshInput<dim>::declare_parameters(prm);
    SizePredictor::registry().declare_parameters(prm);
    AdaptationTarget::declare_parameters(prm);
    LinearElasticMaterial<dim>::declare_parameters(prm);
    ConstitutiveRelationError<dim>::declare_parameters(prm);
    BoundaryConditions<dim>::declare_parameters(prm);
    ContactBoundary<dim>::declare_parameters(prm);
    ContactCondition<dim>::registry().declare_parameters(prm);
    ContactSolver<dim>::registry().declare_parameters(prm);
    ElasticitySolver::declare_parameters(prm);
  }



  template <int dim>
  SignoriniProblem<dim>::SignoriniProblem(ParameterHandler  &prm,
                                          const std::string &input_directory)
    : prm(prm)
    , mpi_communicator(MPI_COMM_WORLD)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    , triangulation(MPI_COMM_WORLD,
                    Triangulation<dim>::none,
                    /*allow_artificial_cells=*/false,
                    parallel::shared::Triangulation<dim>::partition_metis)
    , fe(FE_SimplexP<dim>(1), dim)
    , mapping(FE_SimplexP<dim>(1))
    , scalar_fe(1)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
  {
    output_directory = prm.get("Output directory");
    n_cycles         = prm.get_integer("Number of cycles");
    max_cells        = prm.get_double("Maximum cells");
    prm.enter_subsection("Output");
    write_vtu    = prm.get_bool("Write vtu");
    print_timing = prm.get_bool("Print timing");
    prm.leave_subsection();
    prm.enter_subsection("Exact solution");
    if (prm.get_bool("Enable"))
      exact_solution = parse_function<dim>(prm, dim, "Exact solution");
    prm.leave_subsection();

    mesh_input.parse_parameters(prm);
    mesh_input.set_input_directory(input_directory);
    material.parse_parameters(prm);
    boundary_conditions.parse_parameters(prm);
    contact_boundary.parse_parameters(prm);
    prm.enter_subsection("Contact");
    guess_from_previous_cycle =
      prm.get_bool("Initial active set from previous cycle");
    check_tolerance = prm.get_double("Check tolerance");
    prm.leave_subsection();
    contact_condition = ContactCondition<dim>::registry().create(prm);
    contact_solver    = ContactSolver<dim>::registry().create(prm);
    linear_solver.parse_parameters(prm);
    estimator.parse_parameters(prm);
    size_predictor = SizePredictor::registry().create(prm, dim);
    adaptation_target.parse_parameters(prm);
    if (size_predictor->needs_target_error() && !adaptation_target.enabled())
      throw InputError("Mesh adaptation/Target error: the " +
                       size_predictor->name() +
                       " strategy needs a target error > 0");
    if (size_predictor->uses_estimate() && !estimator.enabled())
      throw InputError("Mesh adaptation/Strategy: <" + size_predictor->name() +
                       "> needs the error estimator (Error estimator/Enable)");
    if (adaptation_target.enabled() && !estimator.enabled())
      throw InputError("Mesh adaptation/Target error: needs the error "
                       "estimator (Error estimator/Enable)");
    prm.enter_subsection("Reference solution");
    reference_extra_levels    = prm.get_integer("Extra refinements");
    reference_from_final_mesh = prm.get("Mesh") == "final mesh";
    prm.leave_subsection();

    for (const auto id : boundary_conditions.used_boundary_ids())
      if (contact_boundary.boundary_ids().count(id) != 0)
        throw InputError("boundary id " + std::to_string(id) +
                         " is both a contact id and a Dirichlet/traction id");

    // last: the directory is created only for otherwise valid input
    check_mesh_sizes();
    output_files.initialize(output_directory, mpi_communicator);
  }



  namespace
  {
    /// A number of cells for a message: exact, or rounded when huge.
    std::string
    cell_count(const double n)
    {
      if (n < 1e15)
        return std::to_string(static_cast<long long>(std::round(n)));
      std::ostringstream text;
      text << std::setprecision(3) << n;
      return text.str();
    }
  } // namespace



  template <int dim>
  void
  SignoriniProblem<dim>::check_mesh_sizes() const
  {
    // The block's cells are counted without building it; a file's coarse
    // mesh is bounded by the file size, so it is built. Every uniform
    // refinement multiplies the triangles by 4.
    const std::string limit =
      ", more than Maximum cells = " + cell_count(max_cells);
    double n_coarse = 0;
    if (mesh_input.source == "block")
      {
        n_coarse = mesh_input.n_block_cells();
        if (n_coarse > max_cells)
          throw InputError(
            "Mesh/Block subdivisions: " +
            std::to_string(mesh_input.block_subdivisions[0]) + " x " +
            std::to_string(mesh_input.block_subdivisions[1]) +
            " rectangles give " + cell_count(n_coarse) + " triangles" + limit);
      }
    else
      {
        MeshInput<dim> coarse_input      = mesh_input;
        coarse_input.initial_refinements = 0;
        Triangulation<dim> coarse;
        coarse_input.create(coarse);
        n_coarse = coarse.n_active_cells();
      }
    const auto cells = [&](const unsigned int levels) {
      return n_coarse * std::pow(4., levels);
    };
    const unsigned int initial = mesh_input.initial_refinements;
    if (cells(initial) > max_cells)
      throw InputError("Mesh/Initial refinements: " + std::to_string(initial) +
                       " refinements of the " + cell_count(n_coarse) +
                       " initial cells give " + cell_count(cells(initial)) +
                       " cells" + limit);
    // Without a target error uniform cycles run to the last one; with one,
    // or with adapted meshes, adapt_mesh() checks each mesh before building
    const bool all_uniform_cycles =
      size_predictor->refines_uniformly() && !adaptation_target.enabled();
    if (all_uniform_cycles && cells(initial + n_cycles - 1) > max_cells)
      {
        unsigned int possible = 1;
        while (cells(initial + possible) <= max_cells)
          ++possible;
        throw InputError("Number of cycles: " + std::to_string(n_cycles) +
                         " uniform cycles need " +
                         cell_count(cells(initial + n_cycles - 1)) +
                         " cells in the last one" + limit + " (at most " +
                         std::to_string(possible) + " cycles)");
      }
    if (reference_extra_levels == 0)
      return;
    const unsigned int reference_levels =
      initial + n_cycles - 1 + reference_extra_levels;
    if ((!reference_from_final_mesh || all_uniform_cycles) &&
        cells(reference_levels) > max_cells)
      throw InputError("Reference solution/Extra refinements: " +
                       std::to_string(reference_extra_levels) +
                       " extra refinements give a reference mesh of " +
                       cell_count(cells(reference_levels)) + " cells" + limit);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::make_grid()
  {
    TimerOutput::Scope t(timer, "make grid");
    adaptive_mesh.initialize(mesh_input, triangulation);

    std::set<types::boundary_id> present;
    for (const auto &face : triangulation.active_face_iterators())
      if (face->at_boundary())
        present.insert(face->boundary_id());
    const auto check = [&](const std::set<types::boundary_id> &ids,
                           const std::string                  &where) {
      for (const auto id : ids)
        if (present.count(id) == 0)
          throw InputError(where + ": boundary id " + std::to_string(id) +
                           " does not exist in the mesh");
    };
    for (unsigned int p = 0; p < boundary_conditions.dirichlet.size(); ++p)
      check(boundary_conditions.dirichlet[p].ids,
            "Boundary conditions/Dirichlet");
    for (unsigned int p = 0; p < boundary_conditions.tractions.size(); ++p)
      check(boundary_conditions.tractions[p].ids,
            "Boundary conditions/Traction");
    check(contact_boundary.boundary_ids(), "Contact/Boundary ids");
  }



  template <int dim>
  void
  SignoriniProblem<dim>::setup_system()
  {
    TimerOutput::Scope t(timer, "setup");
    boundary_conditions.check_finite(mapping,
                                     triangulation,
                                     exact_solution.get());
    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(fe);
    locally_owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);
    scalar_dof_handler.reinit(triangulation);
    scalar_dof_handler.distribute_dofs(scalar_fe);

    hanging_node_constraints.clear();
    DoFTools::make_hanging_node_constraints(dof_handler,
                                            hanging_node_constraints);
    hanging_node_constraints.close();

    dirichlet_constraints.clear();
    AffineConstraints<double> homogeneous_dirichlet;
    for (const auto &part : boundary_conditions.dirichlet)
      for (const auto id : part.ids)
        {
          VectorTools::interpolate_boundary_values(mapping,
                                                   dof_handler,
                                                   id,
                                                   *part.displacement,
                                                   dirichlet_constraints,
                                                   part.mask);
          VectorTools::interpolate_boundary_values(mapping,
                                                   dof_handler,
                                                   id,
                                                   Functions::ZeroFunction<dim>(
                                                     dim),
                                                   homogeneous_dirichlet,
                                                   part.mask);
        }
    dirichlet_constraints.close();
    homogeneous_dirichlet.close();

    constraints.clear();
    constraints.merge(hanging_node_constraints);
    constraints.merge(dirichlet_constraints);
    constraints.close();
    homogeneous_constraints.clear();
    homogeneous_constraints.merge(hanging_node_constraints);
    homogeneous_constraints.merge(homogeneous_dirichlet);
    homogeneous_constraints.close();

    rigid_motions.reinit(dof_handler,
                         dirichlet_constraints,
                         hanging_node_constraints);
    contact_boundary.reinit(mapping,
                            dof_handler,
                            dirichlet_constraints,
                            hanging_node_constraints);
    contact_condition->reinit(contact_boundary);

    // rows of the owned cells' dofs, sent to their owners
    DynamicSparsityPattern dsp(locally_relevant_dofs);
    DoFTools::make_sparsity_pattern(dof_handler,
                                    dsp,
                                    constraints,
                                    /*keep_constrained_dofs=*/true);
    SparsityTools::distribute_sparsity_pattern(dsp,
                                               locally_owned_dofs,
                                               mpi_communicator,
                                               locally_relevant_dofs);
    const IndexSet &owned = locally_owned_dofs;
    stiffness.reinit(owned, owned, dsp, mpi_communicator);
    condensed_stiffness.reinit(owned, owned, dsp, mpi_communicator);
    load.reinit(owned, mpi_communicator);
    solution.reinit(owned, mpi_communicator);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::assemble_system()
  {
    TimerOutput::Scope               t(timer, "assembly");
    const QGaussSimplex<dim>         quadrature(3);
    const QGaussSimplex<dim - 1>     face_quadrature(3);
    FEValues<dim>                    fe_values(mapping,
                            fe,
                            quadrature,
                            update_values | update_gradients |
                              update_quadrature_points | update_JxW_values);
    FEFaceValues<dim>                fe_face_values(mapping,
                                     fe,
                                     face_quadrature,
                                     update_values | update_quadrature_points |
                                       update_JxW_values);
    const FEValuesExtractors::Vector displacement(0);
    const unsigned int               dofs_per_cell = fe.n_dofs_per_cell();
    FullMatrix<double>               cell_matrix(dofs_per_cell, dofs_per_cell);
    Vector<double>                   cell_rhs(dofs_per_cell);
    std::vector<types::global_dof_index> dof_indices(dofs_per_cell);
    std::vector<SymmetricTensor<2, dim>> eps(dofs_per_cell);
    std::vector<Vector<double>>          force_values(quadrature.size(),
                                             Vector<double>(dim));
    std::vector<Vector<double>>          traction_values(face_quadrature.size(),
                                                Vector<double>(dim));

    stiffness           = 0.;
    condensed_stiffness = 0.;
    load                = 0.;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        cell_matrix = 0.;
        cell_rhs    = 0.;
        boundary_conditions.body_force->vector_value_list(
          fe_values.get_quadrature_points(), force_values);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            for (unsigned int i = 0; i < dofs_per_cell; ++i)
              eps[i] = fe_values[displacement].symmetric_gradient(i, q);
            for (unsigned int i = 0; i < dofs_per_cell; ++i)
              {
                const SymmetricTensor<2, dim> sigma_i = material.stress(eps[i]);
                for (unsigned int j = 0; j < dofs_per_cell; ++j)
                  cell_matrix(i, j) += (sigma_i * eps[j]) * fe_values.JxW(q);
                const unsigned int c = fe.system_to_component_index(i).first;
                cell_rhs(i) += force_values[q][c] *
                               fe_values.shape_value(i, q) * fe_values.JxW(q);
              }
          }
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            for (const auto &part : boundary_conditions.tractions)
              if (part.ids.count(cell->face(f)->boundary_id()) != 0)
                {
                  fe_face_values.reinit(cell, f);
                  part.traction->vector_value_list(
                    fe_face_values.get_quadrature_points(), traction_values);
                  for (const unsigned int q :
                       fe_face_values.quadrature_point_indices())
                    for (unsigned int i = 0; i < dofs_per_cell; ++i)
                      {
                        const unsigned int c =
                          fe.system_to_component_index(i).first;
                        cell_rhs(i) += traction_values[q][c] *
                                       fe_face_values.shape_value(i, q) *
                                       fe_face_values.JxW(q);
                      }
                }
        cell->get_dof_indices(dof_indices);
        stiffness.add(dof_indices, cell_matrix);
        load.add(dof_indices, cell_rhs);
        constraints.distribute_local_to_global(cell_matrix,
                                               dof_indices,
                                               condensed_stiffness);
      }
    stiffness.compress(VectorOperation::add);
    condensed_stiffness.compress(VectorOperation::add);
    load.compress(VectorOperation::add);

    // Finite data can still overflow in the products of the solve (|F|^2,
    // K times the prescribed displacements): refuse them as input.
    if (!std::isfinite(load.l2_norm()))
      throw InputError("Boundary conditions: the loads (tractions, body "
                       "force) are too large to compute with (their norm "
                       "overflows); change the units");
    LA::Vector prescribed(load), reaction(load);
    prescribed = 0.;
    for (const auto i : locally_owned_dofs)
      if (dirichlet_constraints.is_inhomogeneously_constrained(i))
        prescribed[i] = dirichlet_constraints.get_inhomogeneity(i);
    prescribed.compress(VectorOperation::insert);
    stiffness.vmult(reaction, prescribed);
    if (!std::isfinite(reaction.l2_norm()))
      throw InputError("Boundary conditions/Dirichlet: the prescribed "
                       "displacements are too large to compute with (the "
                       "forces they need overflow); change the units");
  }



  template <int dim>
  void
  SignoriniProblem<dim>::solve_contact()
  {
    Timer setup_timer;
    {
      TimerOutput::Scope             t(timer, "linear solver setup");
      std::vector<std::vector<bool>> constant_modes;
      DoFTools::extract_constant_modes(dof_handler,
                                       ComponentMask(dim, true),
                                       constant_modes);
      linear_solver.initialize(stiffness,
                               condensed_stiffness,
                               constant_modes,
                               rigid_motions.support_dofs());
    }
    setup_timer.stop();

    const DiscreteContactProblem<dim> problem = contact_problem();
    problem.check_rigid_motions();
    Timer                                solve_timer;
    typename ContactSolver<dim>::Report &report = contact_summary.report;
    {
      TimerOutput::Scope t(timer, "contact solve");
      solution = 0.;
      report   = contact_solver->solve(problem,
                                     solution,
                                     dual_solution,
                                     initial_active_set_guess());
    }
    solve_timer.stop();

    // A row is active when its multiplier is positive beyond round-off (the
    // same rule for both solvers, so that their active sets compare).
    const double threshold = 1e-8 * max_norm(dual_solution);
    active_rows.assign(dual_solution.size(), false);
    unsigned int &n_active = contact_summary.n_active;
    n_active               = 0;
    previous_contact_state.clear();
    for (unsigned int i = 0; i < dual_solution.size(); ++i)
      {
        active_rows[i] = dual_solution[i] > threshold;
        n_active += active_rows[i] ? 1 : 0;
        previous_contact_state.emplace_back(
          contact_boundary.node(contact_boundary.multiplier_nodes()[i])
            .position,
          active_rows[i]);
      }
    const Vector<double> nodal_forces =
      contact_condition->nodal_forces(dual_solution);
    double &contact_force = contact_summary.contact_force;
    contact_force         = 0.;
    for (const double f : nodal_forces)
      contact_force += f;

    // (P1: the support point of a dof is its vertex; every rank sees all
    // cells)
    std::vector<Point<dim>>   support_points(dof_handler.n_dofs());
    std::vector<unsigned int> dof_component(dof_handler.n_dofs());
    {
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              const auto [component, vertex] = fe.system_to_component_index(i);
              dof_component[dofs[i]]         = component;
              support_points[dofs[i]]        = cell->vertex(vertex);
            }
        }
    }
    const SolutionChecks &checks = contact_summary.checks =
      check_solution(problem,
                     solution,
                     dual_solution,
                     dirichlet_constraints,
                     support_points,
                     dof_component);
    const double energy = contact_summary.energy = problem.energy(solution);
    contact_summary.setup_seconds                = setup_timer.wall_time();
    contact_summary.solve_seconds                = solve_timer.wall_time();
    // the solver's word is not enough: the checks decide
    const auto [worst_check, worst_value] = checks.largest();
    last_solve_converged = report.converged && worst_value <= check_tolerance;
    const auto brief     = [](const double x) {
      std::ostringstream text;
      text << std::setprecision(3) << x;
      return text.str();
    };
    if (!report.converged)
      solve_failure = "the " + contact_solver->name() +
                      " solver did not converge (KKT residual " +
                      brief(report.residual) + ")";
    else if (!last_solve_converged)
      solve_failure = "the solution checks fail: " + worst_check + " " +
                      brief(worst_value) +
                      " > Contact/Check tolerance = " + brief(check_tolerance);

    pcout << "   " << contact_condition->name() << " condition, "
          << contact_solver->name() << ": " << report.iterations
          << " iterations, " << report.linear_solves << " linear solves ("
          << report.linear_iterations << " CG iterations, "
          << linear_solver.method() << ")" << std::endl
          << "   active nodes " << n_active << " of "
          << contact_condition->n_constraints() << ", energy "
          << std::setprecision(10) << energy << ", contact force "
          << std::setprecision(6) << contact_force << std::endl
          << std::setprecision(2) << std::scientific
          << "   checks: feasibility " << checks.feasibility
          << ", multiplier sign " << checks.multiplier_sign
          << ", complementarity " << checks.complementarity << ", residual "
          << checks.residual << ", resultant " << checks.resultant
          << std::defaultfloat << std::setprecision(6) << std::endl;
    if (print_timing)
      pcout << "   contact solve " << solve_timer.wall_time() << " s"
            << std::endl;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::estimate_error()
  {
    estimated = false;
    if (!estimator.enabled() || !last_solve_converged)
      return;
    const DiscreteContactProblem<dim> problem = contact_problem();
    TimerOutput::Scope                t(timer, "error estimate");
    Timer                             estimate_timer;
    admissible_displacement.reinit(solution);
    estimate         = estimator.estimate(problem,
                                  mapping,
                                  dof_handler,
                                  material,
                                  boundary_conditions,
                                  solution,
                                  dual_solution,
                                  admissible_displacement);
    estimate_seconds = estimate_timer.wall_time();
    estimated        = true;
    pcout << "   error in constitutive relation: eps = " << std::setprecision(4)
          << 100. * estimate.eps << " % (contact term "
          << 100. * estimate.eps_contact << " % of e^2)" << std::setprecision(6)
          << std::endl;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::record_statistics(const unsigned int cycle)
  {
    statistics_table.add_value("cycle", cycle);
    statistics_table.add_value("cells", triangulation.n_active_cells());
    statistics_table.add_value("dofs", dof_handler.n_dofs());
    statistics_table.add_value("nodes", triangulation.n_used_vertices());
    statistics_table.add_value("predicted_cells", predicted_cells);
    statistics_table.add_value("green_cells", adaptive_mesh.n_green_cells());
    statistics_table.add_value("min_angle", minimum_angle(triangulation));
    statistics_table.add_value("contact_nodes",
                               contact_condition->n_constraints());
    statistics_table.add_value("active_nodes", contact_summary.n_active);
    statistics_table.add_value("condition", contact_condition->name());
    statistics_table.add_value("solver", contact_solver->name());
    statistics_table.add_value("linear_solver", linear_solver.method());
    statistics_table.add_value("iterations", contact_summary.report.iterations);
    statistics_table.add_value("linear_solves",
                               contact_summary.report.linear_solves);
    statistics_table.add_value("cg_iterations",
                               contact_summary.report.linear_iterations);
    statistics_table.add_value("converged", last_solve_converged ? 1u : 0u);
    statistics_table.add_value("kkt_residual", contact_summary.report.residual);
    statistics_table.add_value("energy", contact_summary.energy);
    statistics_table.add_value("contact_force", contact_summary.contact_force);
    statistics_table.add_value("setup_seconds", contact_summary.setup_seconds);
    statistics_table.add_value("solve_seconds", contact_summary.solve_seconds);
    statistics_table.add_value("feasibility",
                               contact_summary.checks.feasibility);
    statistics_table.add_value("multiplier_sign",
                               contact_summary.checks.multiplier_sign);
    statistics_table.add_value("complementarity",
                               contact_summary.checks.complementarity);
    statistics_table.add_value("residual", contact_summary.checks.residual);
    statistics_table.add_value("resultant", contact_summary.checks.resultant);
    statistics_table.add_value("contact_cells",
                               contact_boundary.n_contact_cells());
    if (estimated)
      {
        statistics_table.add_value("e", std::sqrt(estimate.e_squared));
        statistics_table.add_value("eps", estimate.eps);
        statistics_table.add_value("eps_contact", estimate.eps_contact);
        statistics_table.add_value("estimate_seconds", estimate_seconds);
        statistics_table.add_value("equilibrium_defect",
                                   estimate.equilibrium_defect);
        statistics_table.add_value("prolongation_defect",
                                   estimate.condition_defect);
      }
  }



  template <int dim>
  std::vector<unsigned int>
  SignoriniProblem<dim>::contact_transition_vertices() const
  {
    // state of every node of GC: -1 no multiplier, 0 separated, 1 active
    std::vector<int> state(contact_boundary.n_nodes(), -1);
    const auto      &multiplier_nodes = contact_boundary.multiplier_nodes();
    for (unsigned int i = 0; i < multiplier_nodes.size(); ++i)
      state[multiplier_nodes[i]] = active_rows[i] ? 1 : 0;
    std::vector<unsigned int> vertices;
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() &&
            contact_boundary.boundary_ids().count(face->boundary_id()) != 0)
          {
            const unsigned int a =
              contact_boundary.node_index(face->vertex_index(0));
            const unsigned int b =
              contact_boundary.node_index(face->vertex_index(1));
            if (state[a] >= 0 && state[b] >= 0 && state[a] != state[b])
              {
                vertices.push_back(face->vertex_index(0));
                vertices.push_back(face->vertex_index(1));
              }
          }
    return vertices;
  }



  template <int dim>
  bool
  SignoriniProblem<dim>::target_reached() const
  {
    return estimator.enabled() && adaptation_target.reached(estimate.eps);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::adapt_mesh(const unsigned int cycle)
  {
    TimerOutput::Scope   t(timer, "mesh adaptation");
    const unsigned int   n_cells = triangulation.n_active_cells();
    const Vector<double> local_error =
      estimator.enabled() ? estimate.local : Vector<double>(n_cells);
    const std::vector<bool> near_singularity =
      cells_near_singular_points(triangulation, contact_transition_vertices());
    const SizePredictor::Prediction prediction =
      size_predictor->predict({local_error, near_singularity},
                              adaptation_target.target_error);

    // h*_E = r_E h_E: the region of E is refined ceil(log2(1 / r_E)) times
    // beyond the level of E (fewer than its level if r_E > 1)
    std::vector<int> level_change(n_cells);
    for (unsigned int c = 0; c < n_cells; ++c)
      level_change[c] = static_cast<int>(
        std::ceil(std::log2(1. / prediction.size_ratio[c]) - 1e-10));
    predicted_cells = prediction.predicted_cells;
    if (size_predictor->uses_estimate())
      pcout << "   " << size_predictor->name() << " prediction: N* = "
            << static_cast<unsigned long>(std::round(predicted_cells))
            << " elements for eps* = " << std::setprecision(4)
            << 100. * prediction.predicted_error << " %" << std::setprecision(6)
            << std::endl;

    // Refuse a mesh beyond Maximum cells before building it. A cell refined
    // k levels becomes 4^k cells (the halves of a green cell count as whole
    // cells, a coarsened cell as one); where the new levels of two
    // neighbours differ, the closure (2:1 balance, green cells) adds about
    // one cell per finest edge of their face. This bounded the built mesh
    // within 20 % on the block (optimal size, fixed fraction); the check
    // after the build is exact.
    const auto &levels          = adaptive_mesh.levels();
    double      requested_cells = 0.;
    for (const int change : level_change)
      requested_cells += std::pow(4., std::max(change, 0));
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (!cell->at_boundary(f) &&
            cell->active_cell_index() < cell->neighbor(f)->active_cell_index())
          {
            const unsigned int a = cell->active_cell_index();
            const unsigned int b = cell->neighbor(f)->active_cell_index();
            const int new_a = int(levels[a]) + std::max(level_change[a], 0);
            const int new_b = int(levels[b]) + std::max(level_change[b], 0);
            if (new_a != new_b)
              requested_cells +=
                std::pow(2.,
                         std::max(new_a, new_b) -
                           int(std::min(levels[a], levels[b])));
          }
    const auto refuse = [&](const std::string &size) {
      return std::runtime_error(
        "Maximum cells: the adapted mesh of cycle " + std::to_string(cycle) +
        " would have " + size + " cells, more than Maximum cells = " +
        cell_count(max_cells) + " (outputs of " +
        (cycle == 1 ? "cycle 0" : "cycles 0 to " + std::to_string(cycle - 1)) +
        " written)");
    };
    if (requested_cells > max_cells)
      throw refuse("about " + cell_count(requested_cells));
    adaptive_mesh.remesh(mesh_input, level_change, triangulation);
    if (triangulation.n_active_cells() > max_cells)
      throw refuse(cell_count(triangulation.n_active_cells()));
  }



  template <int dim>
  std::vector<bool>
  SignoriniProblem<dim>::initial_active_set_guess() const
  {
    if (!guess_from_previous_cycle || previous_contact_state.empty())
      return {};
    // A node of the new mesh is either a node of the previous one (keep its
    // state) or lies between two of them (active if both were).
    const auto       &nodes = contact_boundary.multiplier_nodes();
    std::vector<bool> guess(nodes.size(), false);
    Point<dim>        lower = previous_contact_state[0].first, upper = lower;
    for (const auto &state : previous_contact_state)
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d] = std::min(lower[d], state.first[d]);
          upper[d] = std::max(upper[d], state.first[d]);
        }
    const double tolerance = 1e-10 * lower.distance(upper);
    for (unsigned int i = 0; i < nodes.size(); ++i)
      {
        const Point<dim> &x = contact_boundary.node(nodes[i]).position;
        std::vector<std::pair<double, bool>> by_distance;
        for (const auto &[position, active] : previous_contact_state)
          by_distance.emplace_back(x.distance(position), active);
        const unsigned int n_nearest =
          std::min<std::size_t>(2, by_distance.size());
        std::partial_sort(by_distance.begin(),
                          by_distance.begin() + n_nearest,
                          by_distance.end());
        guess[i] =
          (by_distance[0].first < tolerance) ?
            by_distance[0].second :
            (by_distance[0].second && by_distance[n_nearest - 1].second);
      }
    return guess;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::compute_exact_error()
  {
    // ||u - u_h||_u^2 = int eps(u - u_h) : K : eps(u - u_h)
    const QGaussSimplex<dim>         quadrature(4);
    FEValues<dim>                    fe_values(mapping,
                            fe,
                            quadrature,
                            update_gradients | update_quadrature_points |
                              update_JxW_values);
    const FEValuesExtractors::Vector displacement(0);
    const LA::Vector ghosted = with_ghosts(solution, locally_relevant_dofs);
    std::vector<Tensor<2, dim>>              grad_h(quadrature.size());
    std::vector<std::vector<Tensor<1, dim>>> grad(
      quadrature.size(), std::vector<Tensor<1, dim>>(dim));
    double error_sq = 0., norm_sq = 0.;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        fe_values[displacement].get_function_gradients(ghosted, grad_h);
        exact_solution->vector_gradient_list(fe_values.get_quadrature_points(),
                                             grad);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            Tensor<2, dim> g;
            for (unsigned int c = 0; c < dim; ++c)
              g[c] = grad[q][c];
            const SymmetricTensor<2, dim> e  = symmetrize(g - grad_h[q]);
            const SymmetricTensor<2, dim> ex = symmetrize(g);
            error_sq += (material.stress(e) * e) * fe_values.JxW(q);
            norm_sq += (material.stress(ex) * ex) * fe_values.JxW(q);
          }
      }
    error_sq = Utilities::MPI::sum(error_sq, mpi_communicator);
    norm_sq  = Utilities::MPI::sum(norm_sq, mpi_communicator);
    pcout << "   energy-norm error " << std::sqrt(error_sq);
    statistics_table.add_value("energy_error", std::sqrt(error_sq));
    // (undefined for a zero exact solution: left empty)
    if (norm_sq > 0.)
      {
        pcout << " (relative " << std::sqrt(error_sq / norm_sq) << ")";
        statistics_table.add_value("relative_energy_error",
                                   std::sqrt(error_sq / norm_sq));
      }
    pcout << std::endl;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::write_contact_table(const unsigned int cycle)
  {
    // One row per node of GC, sorted by position.
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

    const Vector<double> q_n    = contact_boundary.normal_components(solution);
    const Vector<double> lambda = contact_condition->multiplier(dual_solution);
    const Vector<double> forces =
      contact_condition->nodal_forces(dual_solution);
    if (!pcout.is_active())
      return;

    output_files.write(
      "contact-" + Utilities::int_to_string(cycle, 2) + ".csv",
      [&](std::ostream &out) {
        out << "x,y,multiplier_node,normal_displacement,gap,Lambda,"
               "nodal_force,active\n"
            << std::setprecision(12);
        for (const unsigned int k : order)
          {
            const auto &node = contact_boundary.node(k);
            const int   i    = row_of_node[k];
            out << node.position[0] << ',' << node.position[1] << ','
                << (i >= 0 ? 1 : 0) << ',' << q_n[k] << ','
                << contact_boundary.nodal_gap()[k] << ','
                << (i >= 0 ? lambda[i] : 0.) << ',' << forces[k] << ','
                << ((i >= 0 && active_rows[i]) ? 1 : 0) << '\n';
          }
      });
  }



  template <int dim>
  void
  SignoriniProblem<dim>::output_results(const unsigned int cycle)
  {
    TimerOutput::Scope t(timer, "output");
    const bool         root = pcout.is_active();
    write_contact_table(cycle);
    statistics_table.end_row();
    if (root)
      output_files.write("statistics.csv", [&](std::ostream &out) {
        statistics_table.write(out);
      });
    if (!write_vtu)
      return;

    // contact fields as P1 functions that vanish away from GC
    Vector<double> pressure(scalar_dof_handler.n_dofs());
    Vector<double> active(scalar_dof_handler.n_dofs());
    {
      std::map<unsigned int, types::global_dof_index> dof_of_vertex;
      for (const auto &cell : scalar_dof_handler.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          dof_of_vertex[cell->vertex_index(v)] = cell->vertex_dof_index(v, 0);
      const Vector<double> lambda =
        contact_condition->multiplier(dual_solution);
      const auto &multiplier_nodes = contact_boundary.multiplier_nodes();
      for (unsigned int i = 0; i < multiplier_nodes.size(); ++i)
        {
          const auto dof =
            dof_of_vertex[contact_boundary.node(multiplier_nodes[i]).vertex];
          pressure[dof] = -lambda[i];
          active[dof]   = active_rows[i] ? 1. : 0.;
        }
    }

    const StressPostprocessor<dim> stress(material);
    DataOut<dim>                   data_out; // (the cells this rank owns)
    const std::vector<DataComponentInterpretation::DataComponentInterpretation>
                     vector_part(dim,
                  DataComponentInterpretation::component_is_part_of_vector);
    const LA::Vector ghosted = with_ghosts(solution, locally_relevant_dofs);
    data_out.add_data_vector(dof_handler,
                             ghosted,
                             std::vector<std::string>(dim, "displacement"),
                             vector_part);
    data_out.add_data_vector(dof_handler, ghosted, stress);
    data_out.add_data_vector(scalar_dof_handler, pressure, "contact_pressure");
    data_out.add_data_vector(scalar_dof_handler, active, "contact_active");
    const CellDataPostprocessor<dim> eps_E("eps_E", estimate.local);
    if (estimated)
      data_out.add_data_vector(dof_handler, ghosted, eps_E);
    data_out.build_patches(mapping);
    // one file serially; with N ranks a piece per rank and a .pvtu record
    const std::string  base = "solution-" + Utilities::int_to_string(cycle, 2);
    const unsigned int n_ranks =
      Utilities::MPI::n_mpi_processes(mpi_communicator);
    std::string name = base + ".vtu";
    if (n_ranks > 1)
      {
        const unsigned int rank =
          Utilities::MPI::this_mpi_process(mpi_communicator);
        const auto piece = [&](const unsigned int r) {
          return base + "." + Utilities::int_to_string(r, 3) + ".vtu";
        };
        std::vector<std::string> pieces;
        for (unsigned int r = 0; r < n_ranks; ++r)
          pieces.push_back(piece(r));
        // rank 0 lists every piece before any is written, so that a run
        // stopped in between leaves no unlisted file
        if (root)
          for (const auto &file : pieces)
            output_files.record(file);
        MPI_Barrier(mpi_communicator);
        output_files.write(piece(rank),
                           [&](std::ostream &out) { data_out.write_vtu(out); });
        name = base + ".pvtu";
        if (root)
          output_files.write(name, [&](std::ostream &out) {
            data_out.write_pvtu_record(out, pieces);
          });
      }
    else
      output_files.write(name,
                         [&](std::ostream &out) { data_out.write_vtu(out); });
    vtu_files.emplace_back(cycle, name);
    if (root)
      output_files.write("solution.pvd", [&](std::ostream &out) {
        DataOutBase::write_pvd_record(out, vtu_files);
      });
  }



  template <int dim>
  typename SignoriniProblem<dim>::ExactError
  SignoriniProblem<dim>::exact_error(const DoFHandler<dim> &computation_dofs,
                                     const Vector<double>  &u_h,
                                     const Vector<double>  &u_hat,
                                     const double           eps,
                                     const double           e) const
  {
    // the fields on the reference mesh: exact where it refines the mesh of
    // the computation (uniform cycles), nodal interpolation across the green
    // edges of an adapted mesh
    const auto on_reference = [&](const Vector<double> &u) {
      const Vector<double> fine =
        interpolate_at_vertices(computation_dofs,
                                u,
                                reference->get_dof_handler());
      LA::Vector result(reference->displacement());
      for (const auto i : result.locally_owned_elements())
        result[i] = fine[i];
      result.compress(VectorOperation::insert);
      return result;
    };
    const LA::Vector &u_ref = reference->displacement();
    const auto        norm  = [&](const LA::Vector &v) {
      return std::sqrt(reference->stiffness_matrix().matrix_norm_square(v));
    };
    const LA::Vector u_h_fine = on_reference(u_h);
    LA::Vector       difference(u_ref), sum(u_ref);
    difference -= u_h_fine;
    sum += u_h_fine;
    ExactError result;
    result.eps_ex = norm(difference) / norm(sum);
    if (u_hat.size() > 0)
      {
        LA::Vector error_hat(u_ref);
        error_hat -= on_reference(u_hat);
        result.effectivity        = eps / result.eps_ex;
        result.prager_synge_ratio = norm(error_hat) / e;
      }
    return result;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::compare_with_reference()
  {
    TimerOutput::Scope t(timer, "reference comparison");
    const ExactError   error =
      exact_error(dof_handler,
                  replicate(solution),
                  estimator.enabled() ? replicate(admissible_displacement) :
                                        Vector<double>(),
                  estimate.eps,
                  std::sqrt(estimate.e_squared));
    statistics_table.add_value("eps_ex", error.eps_ex);
    pcout << "   exact error (reference "
          << reference->get_dof_handler().n_dofs()
          << " DoFs): eps_ex = " << std::setprecision(4) << 100. * error.eps_ex
          << " %";
    const auto &levels = adaptive_mesh.levels();
    if (*std::max_element(levels.begin(), levels.end()) >=
        reference->adaptive_mesh.levels()[0])
      pcout << " (the reference is not finer than this mesh everywhere: "
               "eps_ex is underestimated; see Reference solution/Mesh)";
    if (estimator.enabled())
      {
        statistics_table.add_value("effectivity", error.effectivity);
        statistics_table.add_value("prager_synge_ratio",
                                   error.prager_synge_ratio);
        pcout << ", effectivity " << error.effectivity
              << ", ||U_ref - U^|| / e = " << error.prager_synge_ratio;
      }
    pcout << std::setprecision(6) << std::endl;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::keep_computation()
  {
    auto computation = std::make_unique<Computation>();
    computation->mesh.copy_triangulation(triangulation);
    computation->dof_handler.reinit(computation->mesh);
    computation->dof_handler.distribute_dofs(fe);
    computation->displacement.reinit(dof_handler.n_dofs());
    if (estimator.enabled())
      computation->admissible_displacement.reinit(dof_handler.n_dofs());
    // the copy has the same cells in the same order: match them by vertex
    const Vector<double> u_h   = replicate(solution);
    const Vector<double> u_hat = estimator.enabled() ?
                                   replicate(admissible_displacement) :
                                   Vector<double>();
    auto                 copy  = computation->dof_handler.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int c = 0; c < dim; ++c)
            {
              const auto from               = cell->vertex_dof_index(v, c);
              const auto to                 = copy->vertex_dof_index(v, c);
              computation->displacement[to] = u_h[from];
              if (estimator.enabled())
                computation->admissible_displacement[to] = u_hat[from];
            }
        ++copy;
      }
    computation->eps = estimate.eps;
    computation->e   = std::sqrt(estimate.e_squared);
    computations.push_back(std::move(computation));
  }



  template <int dim>
  void
  SignoriniProblem<dim>::compare_computations_with_final_reference()
  {
    // the last computational mesh refined uniformly: nested in it, so that
    // the last computation compares exactly (earlier ones across green
    // edges and where their mesh was finer)
    const double n_reference_cells =
      triangulation.n_active_cells() * std::pow(4., reference_extra_levels);
    if (n_reference_cells > max_cells)
      throw std::runtime_error(
        "Reference solution/Extra refinements: the reference mesh would have " +
        cell_count(n_reference_cells) + " cells, more than Maximum cells = " +
        cell_count(max_cells) + "; lower it (computations written)");
    Triangulation<dim> reference_mesh;
    reference_mesh.copy_triangulation(triangulation);
    reference_mesh.refine_global(reference_extra_levels);
    pcout << "Reference solution: the last mesh refined uniformly, "
          << reference_extra_levels << " extra level(s)" << std::endl;
    {
      TimerOutput::Scope t(timer, "reference solution");
      reference = solve_reference(0, &reference_mesh);
    }
    TimerOutput::Scope t(timer, "reference comparison");
    for (unsigned int k = 0; k < computations.size(); ++k)
      {
        const Computation &computation = *computations[k];
        const ExactError   error =
          exact_error(computation.dof_handler,
                      computation.displacement,
                      computation.admissible_displacement,
                      computation.eps,
                      computation.e);
        statistics_table.set_value(k, "eps_ex", error.eps_ex);
        pcout << "   computation " << k << ": eps_ex = " << std::setprecision(4)
              << 100. * error.eps_ex << " %";
        if (estimator.enabled())
          {
            statistics_table.set_value(k, "effectivity", error.effectivity);
            statistics_table.set_value(k,
                                       "prager_synge_ratio",
                                       error.prager_synge_ratio);
            pcout << ", effectivity " << error.effectivity
                  << ", ||U_ref - U^|| / e = " << error.prager_synge_ratio;
          }
        pcout << std::setprecision(6) << std::endl;
      }
    if (pcout.is_active())
      output_files.write("statistics.csv", [&](std::ostream &out) {
        statistics_table.write(out);
      });
  }



  template <int dim>
  const typename ConstitutiveRelationError<dim>::Result &
  SignoriniProblem<dim>::error_estimate() const
  {
    return estimate;
  }



  template <int dim>
  const LA::SparseMatrix &
  SignoriniProblem<dim>::stiffness_matrix() const
  {
    return stiffness;
  }



  template <int dim>
  std::unique_ptr<SignoriniProblem<dim>>
  SignoriniProblem<dim>::solve_reference(const unsigned int        levels,
                                         const Triangulation<dim> *mesh)
  {
    // Same input, finer mesh, one solve, no estimate, adaptation or output
    std::ostringstream parameters;
    prm.print_parameters(parameters, ParameterHandler::ShortPRM);
    reference_parameters            = std::make_unique<ParameterHandler>();
    ParameterHandler &reference_prm = *reference_parameters;
    SignoriniProblem<dim>::declare_parameters(reference_prm);
    reference_prm.parse_input_from_string(parameters.str());
    reference_prm.enter_subsection("Mesh");
    reference_prm.set("Initial refinements", static_cast<long int>(levels));
    reference_prm.leave_subsection();
    reference_prm.enter_subsection("Error estimator");
    reference_prm.set("Enable", false);
    reference_prm.leave_subsection();
    reference_prm.enter_subsection("Mesh adaptation");
    reference_prm.set("Strategy", "uniform");
    reference_prm.set("Target error", 0.);
    reference_prm.leave_subsection();
    reference_prm.enter_subsection("Reference solution");
    reference_prm.set("Extra refinements", 0l);
    reference_prm.leave_subsection();
    // one solve: its mesh alone is checked against Maximum cells
    reference_prm.set("Number of cycles", 1l);
    auto reference_problem =
      std::make_unique<SignoriniProblem<dim>>(reference_prm,
                                              mesh_input.input_directory);
    // on the final mesh refined, start from the last active set
    if (mesh != nullptr)
      reference_problem->previous_contact_state = previous_contact_state;
    reference_problem->solve_once(mesh);
    if (!reference_problem->last_solve_converged)
      throw std::runtime_error("reference solution: " +
                               reference_problem->solve_failure);
    return reference_problem;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::solve_once(const Triangulation<dim> *mesh)
  {
    if (mesh != nullptr)
      {
        triangulation.clear();
        triangulation.copy_triangulation(*mesh);
      }
    else
      make_grid();
    setup_system();
    assemble_system();
    solve_contact();
  }



  template <int dim>
  void
  SignoriniProblem<dim>::validate()
  {
    make_grid();
    // also evaluates every function where it is used on this mesh (NaN or
    // inf: an input error) and warns about questionable contact data
    setup_system();
    // a body held by the contact alone: is there an equilibrium? (needs
    // the load)
    assemble_system();
    contact_problem().check_rigid_motions();
  }



  template <int dim>
  DiscreteContactProblem<dim>
  SignoriniProblem<dim>::contact_problem()
  {
    return DiscreteContactProblem<dim>(stiffness,
                                       load,
                                       constraints,
                                       homogeneous_constraints,
                                       hanging_node_constraints,
                                       contact_boundary,
                                       *contact_condition,
                                       rigid_motions,
                                       linear_solver);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::run()
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
    if (reference_extra_levels > 0 && !reference_from_final_mesh)
      {
        pcout << "Reference solution" << std::endl;
        TimerOutput::Scope t(timer, "reference solution");
        reference = solve_reference(mesh_input.initial_refinements + n_cycles -
                                      1 + reference_extra_levels,
                                    nullptr);
      }
    for (unsigned int cycle = 0; cycle < n_cycles; ++cycle)
      {
        if (cycle == 0)
          make_grid();
        else
          adapt_mesh(cycle);
        setup_system();
        pcout << "Cycle " << cycle << ": " << triangulation.n_active_cells()
              << " cells, " << dof_handler.n_dofs() << " DoFs, "
              << contact_boundary.n_nodes() << " nodes on GC ("
              << contact_condition->n_constraints() << " with a multiplier)"
              << std::endl;
        if (size_predictor->uses_estimate())
          {
            pcout << "   mesh: " << triangulation.n_active_cells() << " cells";
            if (cycle > 0)
              pcout << " (predicted N* = "
                    << static_cast<unsigned long>(std::round(predicted_cells))
                    << ")";
            pcout << ", " << triangulation.n_used_vertices() << " nodes, "
                  << adaptive_mesh.n_green_cells()
                  << " green cells, minimum angle " << std::setprecision(4)
                  << minimum_angle(triangulation) << " degrees"
                  << std::setprecision(6) << std::endl;
          }
        assemble_system();
        solve_contact();
        estimate_error();
        record_statistics(cycle);
        // a failed computation is written as it is, with nothing built on it
        if (last_solve_converged)
          {
            if (exact_solution)
              compute_exact_error();
            if (reference)
              compare_with_reference();
            if (reference_extra_levels > 0 && reference_from_final_mesh)
              keep_computation();
          }
        output_results(cycle);
        if (!last_solve_converged)
          throw std::runtime_error("cycle " + std::to_string(cycle) + ": " +
                                   solve_failure + " (outputs written)");
        if (target_reached())
          {
            pcout << "Target error " << 100. * adaptation_target.target_error
                  << " % reached" << std::endl;
            break;
          }
        if (adaptation_target.enabled() && cycle + 1 == n_cycles)
          pcout << "Target error " << 100. * adaptation_target.target_error
                << " % not reached in " << n_cycles << " computations"
                << std::endl;
      }
    if (reference_extra_levels > 0 && reference_from_final_mesh)
      compare_computations_with_final_reference();
    if (print_timing)
      timer.print_summary();
  }



  template <int dim>
  const CsvTable &
  SignoriniProblem<dim>::statistics() const
  {
    return statistics_table;
  }



  template <int dim>
  const LA::Vector &
  SignoriniProblem<dim>::displacement() const
  {
    return solution;
  }



  template <int dim>
  const std::vector<bool> &
  SignoriniProblem<dim>::active_set() const
  {
    return active_rows;
  }



  template <int dim>
  const Vector<double> &
  SignoriniProblem<dim>::dual() const
  {
    return dual_solution;
  }



  template <int dim>
  const DoFHandler<dim> &
  SignoriniProblem<dim>::get_dof_handler() const
  {
    return dof_handler;
  }

  template class SignoriniProblem<2>;
} // namespace Signorini
