#include <deal.II/base/mpi.h>

#include <signorini/adaptation/mesh_quality.h>
#include <signorini/input_error.h>
#include <signorini/signorini_problem.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace Signorini
{
  void
  declare_dimension(ParameterHandler &prm, const unsigned int default_dimension)
  {
    prm.declare_entry("Dimension",
                      std::to_string(default_dimension),
                      Patterns::Integer(2, 3),
                      "Space dimension of the problem. In 3D: the generated "
                      "block (extruded) or Gmsh meshes of tetrahedra, the "
                      "contact with both conditions and solvers, the "
                      "estimate (element equilibration with displacement "
                      "element fields, or star patch), uniform cycles or "
                      "adapted meshes by remeshing; the Johnson-Mercier "
                      "element fields and the refinement and bisection of "
                      "adapted meshes are 2D only and refuse 3 by name.");
  }



  template <int dim>
  void
  SignoriniProblem<dim>::declare_parameters(ParameterHandler &prm)
  {
    declare_dimension(prm, dim);
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
    ResultsOutput<dim>::declare_parameters(prm);
    ExactSolution<dim>::declare_parameters(prm);
    MeshInput<dim>::declare_parameters(prm);
    SizePredictor::registry().declare_parameters(prm);
    AdaptiveMesh<dim>::declare_parameters(prm);
    AdaptationTarget::declare_parameters(prm);
    ErrorDensitySmoothing::declare_parameters(prm);
    ContactComputation<dim>::declare_parameters(prm);
    ConstitutiveRelationError<dim>::declare_parameters(prm);
    ReferenceSolution<dim>::declare_parameters(prm);
  }



  template <int dim>
  SignoriniProblem<dim>::SignoriniProblem(ParameterHandler  &prm,
                                          const std::string &input_directory)
    : prm(prm)
    , timer(results.screen())
    , triangulation(MPI_COMM_WORLD,
                    Triangulation<dim>::none,
                    /*allow_artificial_cells=*/false,
                    parallel::shared::Triangulation<dim>::partition_metis)
    , computation(prm, timer) // parses the model's sections first
  {
    n_cycles  = prm.get_integer("Number of cycles");
    max_cells = prm.get_double("Maximum cells");
    results.parse_parameters(prm);
    exact_solution.parse_parameters(prm);
    mesh_input.parse_parameters(prm);
    mesh_input.set_input_directory(input_directory);
    mesh_input.set_maximum_cells(max_cells);
    estimator.parse_parameters(prm);
    size_predictor = SizePredictor::registry().create(prm, dim);
    adaptation_target.parse_parameters(prm);
    error_density_smoothing.parse_parameters(prm);
    adaptive_mesh.parse_parameters(prm);
    if (dim == 3 && !size_predictor->refines_uniformly() && !remeshing())
      throw InputError("Mesh adaptation/Realisation: adapted meshes of "
                       "tetrahedra are made by remeshing (Realisation = "
                       "remeshing); refinement is uniform only in 3D");
    if (remeshing())
      {
        std::set<types::boundary_id> boundary_ids =
          computation.boundary_conditions().used_boundary_ids();
        for (const auto id : computation.contact_boundary().boundary_ids())
          boundary_ids.insert(id);
        remesher.check_geometry(mesh_input, boundary_ids);
      }
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
    reference.parse_parameters(prm);

    // last: the directory is created only for otherwise valid input
    check_mesh_sizes();
    results.initialize();
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
    // mesh is bounded by the file size, so it is read (once: creating the
    // mesh reuses it). Every uniform refinement multiplies the cells by
    // 2^dim.
    const std::string limit =
      ", more than Maximum cells = " + cell_count(max_cells);
    double n_coarse = 0;
    if (mesh_input.source == MeshInput<dim>::Source::block)
      {
        n_coarse = mesh_input.n_block_cells();
        if (n_coarse > max_cells)
          throw InputError(
            "Mesh/Block subdivisions: " + mesh_input.block_subdivisions_text() +
            " give " + cell_count(n_coarse) +
            (dim == 2 ? " triangles" : " tetrahedra") + limit);
      }
    else
      n_coarse = mesh_input.n_coarse_cells();
    const auto cells = [&](const unsigned int levels) {
      return n_coarse * std::pow(2., dim * levels);
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
        throw InputError(
          "Number of cycles: " + std::to_string(n_cycles) +
          " uniform cycles need " + cell_count(cells(initial + n_cycles - 1)) +
          " cells in the last one" + limit + " (at most " +
          std::to_string(possible) + (possible == 1 ? " cycle)" : " cycles)"));
      }
    if (!reference.enabled())
      return;
    const unsigned int reference_levels =
      initial + n_cycles - 1 + reference.extra_refinements();
    if ((reference.mesh() == ReferenceSolution<dim>::Mesh::initial_mesh ||
         all_uniform_cycles) &&
        cells(reference_levels) > max_cells)
      throw InputError("Reference solution/Extra refinements: " +
                       std::to_string(reference.extra_refinements()) +
                       " extra refinements give a reference mesh of " +
                       cell_count(cells(reference_levels)) + " cells" + limit);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::adapt_mesh(const unsigned int cycle)
  {
    PhaseTimer::Scope    t(timer, "mesh adaptation");
    const unsigned int   n_cells = triangulation.n_active_cells();
    const Vector<double> local_error =
      estimator.enabled() ?
        error_density_smoothing.apply(triangulation, estimate.local) :
        Vector<double>(n_cells);
    const std::vector<bool> near_singularity =
      cells_near_singular_points(triangulation,
                                 computation.contact_transition_vertices());
    const SizePredictor::Prediction prediction =
      size_predictor->predict({local_error, near_singularity},
                              adaptation_target.target_error);
    predicted_cells = prediction.predicted_cells;
    if (size_predictor->uses_estimate())
      results.size_prediction(size_predictor->name(), prediction);
    const auto refuse = [&](const std::string &size) {
      return std::runtime_error(
        "Maximum cells: the " +
        std::string(size_predictor->refines_uniformly() ? "uniformly refined" :
                                                          "adapted") +
        " mesh of cycle " + std::to_string(cycle) + " would have " + size +
        " cells, more than Maximum cells = " + cell_count(max_cells) +
        " (outputs of " +
        (cycle == 1 ? "cycle 0" : "cycles 0 to " + std::to_string(cycle - 1)) +
        " written)");
    };

    if (remeshing())
      {
        // continuous sizes: the new mesh has about N* cells
        if (predicted_cells > max_cells)
          throw refuse("about " + cell_count(predicted_cells));
        remesher.remesh(mesh_input, prediction.size_ratio, triangulation);
        adaptive_mesh.adopt(triangulation);
        if (triangulation.n_active_cells() > max_cells)
          throw refuse(cell_count(triangulation.n_active_cells()));
        return;
      }

    // h*_E = r_E h_E in whole levels: the region of E is refined k_E times
    // beyond the level of E (fewer than its level if k_E < 0)
    const double level_ratio = adaptive_mesh.level_size_ratio();
    // cells of the refined cells alone, before any closure
    const auto cells_asked = [level_ratio](const std::vector<int> &change) {
      double cells = 0.;
      for (const int k : change)
        cells += std::pow(level_ratio, -double(dim) * std::max(k, 0));
      return cells;
    };
    SizePredictor::Input input{local_error,
                               near_singularity,
                               &adaptive_mesh.levels(),
                               level_ratio};
    if (adaptive_mesh.realisation() ==
        AdaptiveMesh<dim>::Realisation::bisection)
      input.realised = [&](const std::vector<int> &change) {
        // a request beyond Maximum cells is not tried (it is refused below)
        const double requested = cells_asked(change);
        if (requested > max_cells)
          return SizePredictor::Realised{
            change, static_cast<unsigned int>(std::min(requested, 4e9))};
        const auto [realised, n_cells] = adaptive_mesh.trial_remesh(change);
        return SizePredictor::Realised{realised, n_cells};
      };
    const std::vector<int> level_change =
      size_predictor->level_changes(input,
                                    prediction,
                                    adaptation_target.target_error);

    // Refuse a mesh beyond Maximum cells before building it. A cell refined
    // k levels becomes level_ratio^(-dim k) cells (the halves of a green
    // cell count as whole cells, a coarsened cell as one); where the new
    // levels of two neighbours differ, the closure (2:1 balance, green
    // cells, bisection) adds about one cell per finest edge of their face.
    // This bounded the built mesh within 20 % on the block (optimal size,
    // fixed fraction); the check after the build is exact.
    const auto &levels          = adaptive_mesh.levels();
    double      requested_cells = cells_asked(level_change);
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
              requested_cells += std::pow(level_ratio,
                                          int(std::min(levels[a], levels[b])) -
                                            std::max(new_a, new_b));
          }
    if (requested_cells > max_cells)
      throw refuse("about " + cell_count(requested_cells));
    // (Refined fraction = 0, or equal size ratio bounds of 1: every cycle
    // recomputed the same mesh, silently)
    if (std::all_of(level_change.begin(), level_change.end(), [](int k) {
          return k == 0;
        }))
      warn_once("unchanged mesh",
                "Mesh adaptation: the strategy changes no cell of the mesh of "
                "cycle " +
                  std::to_string(cycle - 1) +
                  ": the next cycles compute on the same mesh",
                MPI_COMM_WORLD);
    adaptive_mesh.remesh(mesh_input, level_change, triangulation);
    if (triangulation.n_active_cells() > max_cells)
      throw refuse(cell_count(triangulation.n_active_cells()));
  }



  template <int dim>
  void
  SignoriniProblem<dim>::make_grid()
  {
    PhaseTimer::Scope t(timer, "make grid");
    adaptive_mesh.initialize(mesh_input, triangulation);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::setup_system(const unsigned int cycle)
  {
    computation.setup(triangulation, exact_solution.function());
    if (cycle == 0) // (the input's mesh: its coarser versions are known)
      computation.enable_nested_start(mesh_input);
    results.mesh(cycle,
                 adaptive_mesh,
                 computation,
                 predicted_cells,
                 /*with_prediction=*/size_predictor->uses_estimate());
  }



  template <int dim>
  void
  SignoriniProblem<dim>::assemble_system()
  {
    computation.assemble();
  }



  template <int dim>
  void
  SignoriniProblem<dim>::solve_contact(const unsigned int cycle)
  {
    // (the steps of a load path write their outputs as they are solved)
    computation.set_load_step_observer([this, cycle](const unsigned int step) {
      PhaseTimer::Scope t(timer, "output");
      results.load_step(cycle, step, computation);
    });
    computation.solve();
    results.contact_solve(computation);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::estimate_error()
  {
    estimated = false;
    if (!estimator.enabled() || !computation.converged())
      return;
    const DiscreteContactProblem<dim> problem = computation.contact_problem();
    PhaseTimer::Scope                 t(timer, "error estimate");
    Timer                             estimate_timer;
    admissible_displacement.reinit(computation.displacement());
    estimate  = estimator.estimate(problem,
                                  computation.mapping(),
                                  computation.dof_handler(),
                                  computation.material(),
                                  computation.boundary_conditions(),
                                  computation.displacement(),
                                  computation.dual(),
                                  admissible_displacement,
                                  &computation.friction_law(),
                                  &computation.friction());
    estimated = true;
    results.error_estimate(estimate, estimate_timer.wall_time());
  }



  template <int dim>
  void
  SignoriniProblem<dim>::compare_with_known_solutions()
  {
    // a failed computation is written as it is, with nothing built on it
    if (!computation.converged())
      return;
    if (exact_solution.enabled())
      results.exact_error(exact_solution.error(computation),
                          estimated ? &estimate : nullptr);
    if (!reference.enabled())
      return;
    const Vector<double> u_hat = estimator.enabled() ?
                                   replicate(admissible_displacement) :
                                   Vector<double>();
    if (reference.solved())
      {
        PhaseTimer::Scope t(timer, "reference comparison");
        results.reference_comparison(
          reference.compare(computation.dof_handler(),
                            replicate(computation.displacement()),
                            u_hat,
                            estimate.eps,
                            std::sqrt(estimate.e_squared)),
          reference.computation().dof_handler().n_dofs(),
          reference_not_finer(),
          estimator.enabled());
      }
    if (reference.mesh() == ReferenceSolution<dim>::Mesh::final_mesh)
      reference.keep(computation,
                     u_hat,
                     estimate.eps,
                     std::sqrt(estimate.e_squared));
  }



  template <int dim>
  bool
  SignoriniProblem<dim>::reference_not_finer() const
  {
    // refined meshes compare by level in the same hierarchy; a remeshed
    // mesh by its smallest cell against the reference's largest
    if (remeshing())
      {
        double smallest = std::numeric_limits<double>::max(), largest = 0.;
        for (const auto &cell : triangulation.active_cell_iterators())
          smallest = std::min(smallest, cell->diameter());
        for (const auto &cell : reference.computation()
                                  .dof_handler()
                                  .get_triangulation()
                                  .active_cell_iterators())
          largest = std::max(largest, cell->diameter());
        return smallest < largest;
      }
    return adaptive_mesh.finest_halvings() >= reference.level();
  }



  template <int dim>
  bool
  SignoriniProblem<dim>::remeshing() const
  {
    return adaptive_mesh.realisation() ==
           AdaptiveMesh<dim>::Realisation::remeshing;
  }



  template <int dim>
  void
  SignoriniProblem<dim>::output_results(const unsigned int cycle)
  {
    PhaseTimer::Scope t(timer, "output");
    results.write(cycle, computation, estimated ? &estimate.local : nullptr);
  }



  template <int dim>
  bool
  SignoriniProblem<dim>::target_reached() const
  {
    return estimator.enabled() && adaptation_target.reached(estimate.eps);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::check_reference()
  {
    results.print_contact_solve(reference.computation());
    if (!reference.computation().converged())
      throw std::runtime_error("reference solution: " +
                               reference.computation().failure());
  }



  template <int dim>
  void
  SignoriniProblem<dim>::solve_reference_on_initial_mesh()
  {
    results.message("Reference solution");
    PhaseTimer::Scope t(timer, "reference solution");
    reference.solve_on_initial_mesh(mesh_input,
                                    mesh_input.initial_refinements + n_cycles -
                                      1 + reference.extra_refinements());
    check_reference();
  }



  template <int dim>
  void
  SignoriniProblem<dim>::compare_computations_with_final_reference()
  {
    // the last computational mesh refined uniformly: nested in it, so that
    // the last computation compares exactly (earlier ones across green
    // edges and where their mesh was finer)
    const unsigned int extra_levels = reference.extra_refinements();
    const double       n_reference_cells =
      triangulation.n_active_cells() * std::pow(2., dim * extra_levels);
    if (n_reference_cells > max_cells)
      throw std::runtime_error(
        "Reference solution/Extra refinements: the reference mesh would have " +
        cell_count(n_reference_cells) + " cells, more than Maximum cells = " +
        cell_count(max_cells) + "; lower it (computations written)");
    Triangulation<dim> reference_mesh;
    reference_mesh.copy_triangulation(triangulation);
    reference_mesh.refine_global(extra_levels);
    results.message("Reference solution: the last mesh refined uniformly, " +
                    std::to_string(extra_levels) + " extra level(s)");
    {
      PhaseTimer::Scope t(timer, "reference solution");
      reference.solve_on(reference_mesh, computation.contact_state());
      check_reference();
    }
    PhaseTimer::Scope t(timer, "reference comparison");
    results.final_reference_comparison(reference.compare_kept(),
                                       estimator.enabled());
  }



  template <int dim>
  void
  SignoriniProblem<dim>::validate()
  {
    make_grid();
    // also evaluates every function where it is used on this mesh (NaN or
    // inf: an input error) and warns about questionable contact data
    computation.setup(triangulation, exact_solution.function());
    computation.check_load_path();
    // a body held by the contact alone: is there an equilibrium? (needs
    // the load)
    computation.assemble();
    const DiscreteContactProblem<dim> problem = computation.contact_problem();
    problem.check_rigid_motions();
    if (computation.friction_law().enabled())
      FrictionalActiveSetSolver<dim>::check_applicable(problem);
  }



  template <int dim>
  void
  SignoriniProblem<dim>::run()
  {
    results.start_run(prm);
    if (reference.enabled() &&
        reference.mesh() == ReferenceSolution<dim>::Mesh::initial_mesh)
      solve_reference_on_initial_mesh();
    for (unsigned int cycle = 0; cycle < n_cycles; ++cycle)
      {
        try
          {
            if (cycle == 0)
              make_grid();
            else
              adapt_mesh(cycle);
            if (cycle + 1 == n_cycles) // (no mesh after this one)
              adaptive_mesh.release_hierarchy();
            setup_system(cycle);
            assemble_system();
            solve_contact(cycle);
            estimate_error();
            compare_with_known_solutions();
          }
        catch (const InputError &error)
          {
            // (data refused on a later mesh, e.g. at a new node: say which)
            if (cycle == 0)
              throw;
            throw InputError("cycle " + std::to_string(cycle) + ": " +
                             error.what());
          }
        output_results(cycle);
        if (!computation.converged())
          {
            // (where the time of the failed run went; the decision is the
            // same on every rank, and the summary gathers over them)
            if (results.print_timing())
              timer.print_summary(MPI_COMM_WORLD);
            throw std::runtime_error("cycle " + std::to_string(cycle) + ": " +
                                     computation.failure() +
                                     " (outputs written)");
          }
        std::ostringstream target;
        target << "Target error " << 100. * adaptation_target.target_error
               << " %";
        if (target_reached())
          {
            results.message(target.str() + " reached");
            break;
          }
        if (adaptation_target.enabled() && cycle + 1 == n_cycles)
          results.message(target.str() + " not reached in " +
                          std::to_string(n_cycles) + " computations");
      }
    if (reference.enabled() &&
        reference.mesh() == ReferenceSolution<dim>::Mesh::final_mesh)
      compare_computations_with_final_reference();
    if (results.print_timing())
      timer.print_summary(MPI_COMM_WORLD);
  }



  template <int dim>
  const CsvTable &
  SignoriniProblem<dim>::statistics() const
  {
    return results.statistics();
  }



  template <int dim>
  const std::vector<bool> &
  SignoriniProblem<dim>::active_set() const
  {
    return computation.active_set();
  }



  template <int dim>
  const Vector<double> &
  SignoriniProblem<dim>::dual() const
  {
    return computation.dual();
  }



  template <int dim>
  const typename ConstitutiveRelationError<dim>::Result &
  SignoriniProblem<dim>::error_estimate() const
  {
    return estimate;
  }

  template class SignoriniProblem<2>;
  template class SignoriniProblem<3>;
} // namespace Signorini
