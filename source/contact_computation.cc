#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_tools.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <deal.II/numerics/vector_tools.h>

#include <deal.II/distributed/shared_tria.h>

#include <signorini/coarse_domain_mesher.h>
#include <signorini/contact_computation.h>
#include <signorini/input_error.h>
#include <signorini/nodal_interpolation.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>

namespace Signorini
{
  template <int dim>
  void
  ContactComputation<dim>::declare_parameters(ParameterHandler &prm)
  {
    LinearElasticMaterial<dim>::declare_parameters(prm);
    BoundaryConditions<dim>::declare_parameters(prm);
    ContactBoundary<dim>::declare_parameters(prm);
    FrictionLaw<dim>::declare_parameters(prm);
    FrictionalActiveSetSolver<dim>::declare_parameters(prm);
    LoadPath::declare_parameters(prm);
    ContactCondition<dim>::registry().declare_parameters(prm);
    ContactSolver<dim>::registry().declare_parameters(prm);
    ElasticitySolver::declare_parameters(prm);
    prm.enter_subsection("Contact");
    prm.declare_entry("Initial active set from previous cycle",
                      "true",
                      Patterns::Bool(),
                      "Start the active set method of a cycle from the "
                      "active set of the previous (coarser) cycle.");
    prm.declare_entry("Check tolerance",
                      "1e-6",
                      Patterns::Double(1e-12, 1e-2),
                      "A computation whose relative solution checks "
                      "(feasibility, multiplier sign, complementarity, "
                      "residual, resultant) exceed this has failed (exit code "
                      "2), whatever its solver reports (at least 1e-12: the "
                      "checks of an exact solve are round-off; with friction "
                      "at least 1e-10; at most 1e-2: beyond, a body that "
                      "penetrates the foundation by a percent of its "
                      "displacements would pass).");
    prm.declare_entry("Nested start",
                      "true",
                      Patterns::Bool(),
                      "On the input mesh (the first cycle, a reference on the "
                      "initial mesh) and unless it starts from a previous "
                      "mesh, compute first on coarser meshes, each started "
                      "from the one before, and start the active set method "
                      "from the last (with friction its stick and slip sets "
                      "too; Frank-Wolfe, the fixed point and a load path: no "
                      "effect): the input mesh with fewer initial "
                      "refinements, or, without initial refinements, its "
                      "domain meshed again by Gmsh at coarser sizes.");
    prm.declare_entry("Nested start cells",
                      "2000",
                      Patterns::Integer(1),
                      "The first mesh of the nested start is the finest one "
                      "with at most this many cells (the input mesh itself "
                      "if it has more); a mesh with at most this many cells "
                      "starts cold, and so does a mesh without initial "
                      "refinements whose domain meshed at 4 times its size "
                      "would have fewer than a quarter of this many.");
    prm.leave_subsection();
  }



  template <int dim>
  ContactComputation<dim>::ContactComputation(ParameterHandler &prm,
                                              PhaseTimer       &timer)
    : ContactComputation(prm, timer, /*with_nested_start=*/true)
  {}



  template <int dim>
  ContactComputation<dim>::ContactComputation(ParameterHandler &prm,
                                              PhaseTimer       &timer,
                                              const bool with_nested_start)
    : timer(timer)
    , mpi_communicator(MPI_COMM_WORLD)
    , fe(FE_SimplexP<dim>(1), dim)
    , mapping_fe(FE_SimplexP<dim>(1))
  {
    material_law.parse_parameters(prm);
    boundary_data.parse_parameters(prm);
    gamma_c.parse_parameters(prm);
    prm.enter_subsection("Contact");
    guess_from_previous_cycle =
      prm.get_bool("Initial active set from previous cycle");
    check_tolerance    = prm.get_double("Check tolerance");
    nested_start_cells = prm.get_integer("Nested start cells");
    const bool nested  = with_nested_start && prm.get_bool("Nested start");
    parameters         = &prm;
    prm.leave_subsection();
    contact_condition = ContactCondition<dim>::registry().create(prm);
    contact_solver    = ContactSolver<dim>::registry().create(prm);
    elasticity_solver.parse_parameters(prm);
    friction_law_.parse_parameters(prm);
    load_path_.parse_parameters(prm);
    // the data of the end of the path unless a step is applied
    boundary_data.set_load_step(load_path_, load_path_.n_steps());
    friction_law_.set_time(1.);
    FrictionalActiveSetSolver<dim>::warn_unused_parameters(prm, friction_law_);
    if (friction_law_.enabled() && gamma_c.boundary_ids().empty())
      warn_once("friction without contact",
                "Contact/Friction = " + friction_law_.name() +
                  " is not used: Contact/Boundary ids is empty",
                mpi_communicator);
    if (friction_law_.enabled())
      {
        if (contact_solver->name() != "active set")
          throw InputError("Contact/Friction = " + friction_law_.name() +
                           " needs Contact/Solver = active set");
        prm.enter_subsection("Contact");
        const std::string check_tolerance_text = prm.get("Check tolerance");
        prm.enter_subsection("Active set");
        friction_max_iterations = prm.get_integer("Maximum iterations");
        friction_preconditioner_update =
          prm.get_double("Preconditioner update fraction");
        friction_inexact_tolerance = prm.get_double("Inexact tolerance");
        prm.leave_subsection();
        prm.leave_subsection();
        // (the friction iteration stops once its forces change by 1e-12 of
        // the problem's forces, which the checks of the friction bound and
        // the slip see relative to the contact forces: 3e-12 on the block)
        if (check_tolerance < 1e-10)
          throw InputError(
            "Contact/Check tolerance = " + check_tolerance_text +
            " is below what the friction iteration reaches (its checks are "
            "at 1e-12 of the forces and above): with Contact/Friction = " +
            friction_law_.name() + " at least 1e-10");
        friction_method = FrictionalActiveSetSolver<dim>::parse_method(prm);
        friction_uniqueness_steps =
          FrictionalActiveSetSolver<dim>::parse_uniqueness_check(prm);
      }

    for (const auto id : boundary_data.used_boundary_ids())
      if (gamma_c.boundary_ids().count(id) != 0)
        throw InputError("boundary id " + std::to_string(id) +
                         " is both a contact id and a Dirichlet/traction id");

    // (with friction the coarser meshes give the stick and slip sets too;
    // not the fixed point, which starts each Tresca problem afresh, nor a
    // load path, whose first step is a fraction of the load)
    nested_start =
      nested && contact_solver->uses_initial_active_set() &&
      load_path_.n_steps() == 1 &&
      (!friction_law_.enabled() ||
       friction_method ==
         FrictionalActiveSetSolver<dim>::Method::semismooth_newton);
  }



  template <int dim>
  void
  ContactComputation<dim>::check_boundary_ids(
    const Triangulation<dim> &mesh) const
  {
    std::set<types::boundary_id> present;
    for (const auto &face : mesh.active_face_iterators())
      if (face->at_boundary())
        present.insert(face->boundary_id());
    const auto check = [&](const std::set<types::boundary_id> &ids,
                           const std::string                  &where) {
      for (const auto id : ids)
        if (present.count(id) == 0)
          throw InputError(where + ": boundary id " + std::to_string(id) +
                           " does not exist in the mesh");
    };
    for (const auto &part : boundary_data.dirichlet)
      check(part.ids, "Boundary conditions/Dirichlet");
    for (const auto &part : boundary_data.tractions)
      check(part.ids, "Boundary conditions/Traction");
    check(gamma_c.boundary_ids(), "Contact/Boundary ids");
  }



  template <int dim>
  void
  ContactComputation<dim>::check_data_scale(
    const typename BoundaryConditions<dim>::DataMagnitudes &data) const
  {
    // the stress S the data impose (tractions, body force times the
    // diameter L, E times the prescribed displacements over L) and the
    // displacement S L / E it causes: the solve and its checks square
    // forces and displacements (norms, energies), so beyond 1e+-140 they
    // underflow or overflow although each datum may look harmless
    const double diameter = mesh_diameter;
    const double young    = std::abs(material_law.young_modulus);
    // (in decimal exponents: S itself may not be a double; log10(0) = -inf
    // drops a datum that is zero)
    const double log_diameter = std::log10(diameter);
    const double log_stress   = std::max(
      {std::log10(data.traction),
         std::log10(data.body_force) + log_diameter,
         std::log10(young) + std::log10(data.displacement) - log_diameter});
    if (log_stress == -std::numeric_limits<double>::infinity())
      return; // no load: the solution is zero, or a rigid motion
    const double log_displacement =
      log_stress + log_diameter - std::log10(young);
    const double limit = 140.;
    if (!(std::abs(log_stress) < limit && std::abs(log_displacement) < limit))
      {
        const bool         stress = !(std::abs(log_stress) < limit);
        std::ostringstream message;
        message << std::setprecision(2)
                << "Boundary conditions and Material/Young modulus: the data "
                   "give "
                << (stress ? "stresses" : "displacements") << " of order 1e"
                << std::lround(stress ? log_stress : log_displacement)
                << " (from the loads and prescribed displacements, Young "
                   "modulus "
                << young << ", diameter " << diameter
                << "), beyond what double precision resolves in their "
                   "squares: choose units (of stress, and of length) that "
                   "bring both within 1e-140 to 1e140";
        throw InputError(message.str());
      }
    check_friction_coefficient_scale(log_stress);
  }



  template <int dim>
  void
  ContactComputation<dim>::check_friction_coefficient_scale(
    const double log_stress) const
  {
    // Coulomb's bound mu |R_n| (and the friction term of e, mu |R_n| times
    // a slip) likewise: mu = 1e300 on stresses of 1e9 gave eps = NaN
    const double mu = friction_law_.type() == FrictionLaw<dim>::Type::coulomb ?
                        friction_law_.coefficient() :
                        0.;
    const double limit = 140.;
    if (mu > 0. && !(std::log10(mu) + log_stress < limit))
      {
        std::ostringstream message;
        message << std::setprecision(2)
                << "Contact/Friction coefficient = " << mu
                << " times the stresses of the data, of order 1e"
                << std::lround(log_stress)
                << ", is beyond what double precision resolves in their "
                   "squares: choose it below 1e"
                << std::lround(limit - log_stress)
                << " (the bonded limit is reached long before)";
        throw InputError(message.str());
      }
  }



  template <int dim>
  void
  ContactComputation<dim>::check_gap_scale() const
  {
    // a gap G_k < 0 moves the body by at least -G_k (a positive one, however
    // large, only keeps the foundation away)
    double penetration = 0.;
    for (const double g : gamma_c.nodal_gap())
      penetration = std::max(penetration, -g);
    if (penetration == 0.)
      return;
    const double log_displacement = std::log10(penetration);
    const double log_stress = std::log10(std::abs(material_law.young_modulus)) +
                              log_displacement - std::log10(mesh_diameter);
    const double limit = 140.;
    if (!(log_displacement < limit && log_stress < limit))
      {
        // (the larger of the two when both are out of range)
        const bool stress =
          !(log_displacement >= limit && log_displacement >= log_stress);
        std::ostringstream message;
        message << std::setprecision(2) << "Contact/Gap: its value "
                << -penetration << " on GC moves the body by as much, giving "
                << (stress ? "stresses" : "displacements") << " of order 1e"
                << std::lround(stress ? log_stress : log_displacement)
                << " (Young modulus " << material_law.young_modulus
                << ", diameter " << mesh_diameter
                << "), beyond what double precision resolves in their "
                   "squares: choose units (of length, and of stress) that "
                   "bring both below 1e140";
        throw InputError(message.str());
      }
    // (and Coulomb's bound on the stresses the gap alone gives)
    check_friction_coefficient_scale(log_stress);
  }



  template <int dim>
  void
  ContactComputation<dim>::setup(const Triangulation<dim> &mesh,
                                 const Function<dim>      *exact_solution)
  {
    PhaseTimer::Scope t(timer, "setup");
    nested_start_input.reset();
    check_boundary_ids(mesh);
    // (the bounding box's diagonal in one pass over the vertices, where
    // GridTools::diameter() compares the boundary vertices pairwise)
    const auto corners =
      GridTools::compute_bounding_box(mesh).get_boundary_points();
    mesh_diameter = corners.first.distance(corners.second);
    const auto magnitudes =
      boundary_data.check_finite(mapping_fe, mesh, exact_solution);
    try
      {
        check_data_scale(magnitudes);
      }
    catch (const InputError &error)
      {
        // (the data are those of the end of the load path: its factor may
        // be what is out of range)
        const unsigned int last = load_path_.n_steps();
        if (last > 1 || load_path_.factor(last) != 1.)
          throw InputError(step_context(last) + error.what());
        throw;
      }
    dofs.reinit(mesh);
    dofs.distribute_dofs(fe);
    locally_owned_dofs = dofs.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dofs, relevant_dofs);

    hanging_node_constraints.clear();
    DoFTools::make_hanging_node_constraints(dofs, hanging_node_constraints);
    hanging_node_constraints.close();

    make_constraints();

    rigid_motions.reinit(dofs, dirichlet_constraints, hanging_node_constraints);
    gamma_c.reinit(mapping_fe,
                   dofs,
                   dirichlet_constraints,
                   hanging_node_constraints);
    contact_condition->reinit(gamma_c);
    check_gap_scale();
    // (at the end of the path, which a path of several steps names)
    try
      {
        check_friction_threshold();
      }
    catch (const InputError &error)
      {
        if (load_path_.n_steps() == 1)
          throw;
        throw InputError(step_context(load_path_.n_steps()) + error.what());
      }

    // rows of the owned cells' dofs, sent to their owners
    DynamicSparsityPattern dsp(relevant_dofs);
    DoFTools::make_sparsity_pattern(dofs,
                                    dsp,
                                    constraints,
                                    /*keep_constrained_dofs=*/true);
    SparsityTools::distribute_sparsity_pattern(dsp,
                                               locally_owned_dofs,
                                               mpi_communicator,
                                               relevant_dofs);
    const IndexSet &owned = locally_owned_dofs;
    stiffness.reinit(owned, owned, dsp, mpi_communicator);
    load.reinit(owned, mpi_communicator);
    solution.reinit(owned, mpi_communicator);
  }



  template <int dim>
  void
  ContactComputation<dim>::make_constraints()
  {
    dirichlet_constraints.clear();
    AffineConstraints<double> homogeneous_dirichlet;
    for (const auto &part : boundary_data.dirichlet)
      for (const auto id : part.ids)
        {
          VectorTools::interpolate_boundary_values(mapping_fe,
                                                   dofs,
                                                   id,
                                                   *part.displacement,
                                                   dirichlet_constraints,
                                                   part.mask);
          VectorTools::interpolate_boundary_values(mapping_fe,
                                                   dofs,
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
  }



  template <int dim>
  bool
  ContactComputation<dim>::data_vanish() const
  {
    bool vanish = (load.linfty_norm() == 0.);
    for (const auto &line : dirichlet_constraints.get_lines())
      vanish = vanish && (line.inhomogeneity == 0.);
    return vanish;
  }



  template <int dim>
  void
  ContactComputation<dim>::check_load_path()
  {
    for (unsigned int step = 1; step < load_path_.n_steps(); ++step)
      check_step_data(step);
    // (the end of the path: what setup() checked)
    boundary_data.set_load_step(load_path_, load_path_.n_steps());
    friction_law_.set_time(1.);
  }



  template <int dim>
  void
  ContactComputation<dim>::apply_load_step(const unsigned int step)
  {
    check_step_data(step);
    make_constraints();
    try
      {
        gamma_c.check_prescribed_nodes(dirichlet_constraints);
      }
    catch (const InputError &error)
      {
        throw InputError(step_context(step) + error.what());
      }
    assemble(/*with_matrix=*/false);
  }



  template <int dim>
  void
  ContactComputation<dim>::check_step_data(const unsigned int step)
  {
    boundary_data.set_load_step(load_path_, step);
    friction_law_.set_time(load_path_.time(step));
    // (the data of a step may be what is not finite: at the step's time)
    try
      {
        // (a factor that brings the step's data out of the range of
        // doubles, 1e-200 at one step, failed the step's checks at residual
        // 1 with exit 2)
        check_data_scale(
          boundary_data.check_finite(mapping_fe, dofs.get_triangulation()));
        check_friction_threshold();
      }
    catch (const InputError &error)
      {
        throw InputError(step_context(step) + error.what());
      }
  }



  template <int dim>
  std::string
  ContactComputation<dim>::step_context(const unsigned int step) const
  {
    std::ostringstream where;
    where << "Contact/Load steps: at step " << step
          << " (t = " << load_path_.time(step) << ", Load factor "
          << load_path_.factor(step) << "): ";
    return where.str();
  }



  template <int dim>
  void
  ContactComputation<dim>::check_friction_threshold() const
  {
    if (friction_law_.type() != FrictionLaw<dim>::Type::tresca)
      return;
    // the law reads the threshold at the nodes; between them, a threshold
    // that is negative (or not finite) is as wrong, and a finer mesh would
    // meet it: sampled on every face of GC, in the same order on every rank
    for (const auto k : gamma_c.multiplier_nodes())
      friction_law_.threshold_at(gamma_c.node(k).position);
    const FE_SimplexP<dim>       scalar_fe(1);
    const QGaussSimplex<dim - 1> face_quadrature(4);
    FEFaceValues<dim>            fe_face_values(mapping_fe,
                                     scalar_fe,
                                     face_quadrature,
                                     update_quadrature_points);
    for (const auto &cell : dofs.get_triangulation().active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            gamma_c.boundary_ids().count(cell->face(f)->boundary_id()) != 0)
          {
            fe_face_values.reinit(cell, f);
            for (const Point<dim> &x : fe_face_values.get_quadrature_points())
              friction_law_.threshold_at(x);
          }
  }



  template <int dim>
  void
  ContactComputation<dim>::assemble()
  {
    assemble(/*with_matrix=*/true);
  }



  template <int dim>
  void
  ContactComputation<dim>::assemble(const bool with_matrix)
  {
    PhaseTimer::Scope            t(timer, "assembly");
    const QGaussSimplex<dim>     quadrature(3);
    const QGaussSimplex<dim - 1> face_quadrature(3);
    FEValues<dim>                fe_values(mapping_fe,
                            fe,
                            quadrature,
                            update_values | update_quadrature_points |
                              update_JxW_values);
    FEFaceValues<dim>            fe_face_values(mapping_fe,
                                     fe,
                                     face_quadrature,
                                     update_values | update_quadrature_points |
                                       update_JxW_values);
    const unsigned int           dofs_per_cell = fe.n_dofs_per_cell();
    FullMatrix<double>           cell_matrix(dofs_per_cell, dofs_per_cell);
    Vector<double>               cell_rhs(dofs_per_cell);
    std::vector<types::global_dof_index> dof_indices(dofs_per_cell);
    std::vector<SymmetricTensor<2, dim>> eps(dofs_per_cell),
      sigma(dofs_per_cell);
    std::vector<Vector<double>> force_values(quadrature.size(),
                                             Vector<double>(dim));
    std::vector<Vector<double>> traction_values(face_quadrature.size(),
                                                Vector<double>(dim));

    if (with_matrix)
      stiffness = 0.;
    load = 0.;
    for (const auto &cell : dofs.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        cell_matrix = 0.;
        cell_rhs    = 0.;
        if (with_matrix)
          {
            // P1: the strains are constant on the cell, and the gradients of
            // the shape functions (the barycentric coordinates, in deal.II's
            // vertex order) follow from the vertices. Without FEValues and its
            // mapping at every quadrature point, the 3D assembly is several
            // times faster; the matrix is the same to round-off.
            Tensor<2, dim> jacobian;
            for (unsigned int k = 0; k < dim; ++k)
              for (unsigned int d = 0; d < dim; ++d)
                jacobian[d][k] = cell->vertex(k + 1)[d] - cell->vertex(0)[d];
            const Tensor<2, dim>                inverse = invert(jacobian);
            std::array<Tensor<1, dim>, dim + 1> gradients;
            for (unsigned int k = 0; k < dim; ++k)
              {
                gradients[k + 1] = inverse[k];
                gradients[0] -= inverse[k];
              }
            const double measure =
              std::abs(determinant(jacobian)) / (dim == 2 ? 2. : 6.);
            for (unsigned int i = 0; i < dofs_per_cell; ++i)
              {
                const auto [component, vertex] =
                  fe.system_to_component_index(i);
                eps[i] = 0;
                for (unsigned int d = 0; d < dim; ++d)
                  eps[i][component][d] +=
                    (d == component ? 1. : 0.5) * gradients[vertex][d];
                sigma[i] = material_law.stress(eps[i]);
              }
            for (unsigned int i = 0; i < dofs_per_cell; ++i)
              for (unsigned int j = 0; j < dofs_per_cell; ++j)
                cell_matrix(i, j) = (sigma[i] * eps[j]) * measure;
          }
        if (!boundary_data.body_force_zero)
          {
            fe_values.reinit(cell);
            boundary_data.body_force->vector_value_list(
              fe_values.get_quadrature_points(), force_values);
            for (const unsigned int q : fe_values.quadrature_point_indices())
              for (unsigned int i = 0; i < dofs_per_cell; ++i)
                cell_rhs(i) +=
                  force_values[q][fe.system_to_component_index(i).first] *
                  fe_values.shape_value(i, q) * fe_values.JxW(q);
          }
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            for (const auto &part : boundary_data.tractions)
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
        if (with_matrix)
          stiffness.add(dof_indices, cell_matrix);
        load.add(dof_indices, cell_rhs);
      }
    if (with_matrix)
      stiffness.compress(VectorOperation::add);
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
  DiscreteContactProblem<dim>
  ContactComputation<dim>::contact_problem()
  {
    return DiscreteContactProblem<dim>(stiffness,
                                       load,
                                       constraints,
                                       homogeneous_constraints,
                                       hanging_node_constraints,
                                       gamma_c,
                                       *contact_condition,
                                       rigid_motions,
                                       elasticity_solver);
  }



  template <int dim>
  void
  ContactComputation<dim>::solve()
  {
    last_summary.nested = {};
    solution            = 0.;
    bool from_state = guess_from_previous_cycle && !last_contact_state.empty();
    if (!from_state && nested_start && nested_start_input &&
        gamma_c.n_nodes() > 0)
      {
        start_from_coarser_meshes();
        from_state = (last_summary.nested.meshes > 0);
      }

    Timer setup_timer;
    {
      PhaseTimer::Scope              t(timer, "linear solver setup");
      std::vector<std::vector<bool>> constant_modes;
      DoFTools::extract_constant_modes(dofs,
                                       ComponentMask(dim, true),
                                       constant_modes);
      elasticity_solver.initialize(stiffness,
                                   constraints,
                                   constant_modes,
                                   rigid_motions.all_motions(),
                                   rigid_motions.support_dofs(),
                                   contact_solver->prefers_direct_solver(
                                     dofs.n_dofs()));
    }
    setup_timer.stop();

    const unsigned int n_steps = load_path_.n_steps();
    if (n_steps == 1)
      solve_step(from_state ? initial_guess() : InitialGuess(), nullptr);
    else
      {
        // each step from the state of the one before; the summary counts
        // the whole path
        typename ContactSolver<dim>::Report path;
        double                              path_seconds = 0.;
        FrictionState<dim>                  previous;
        for (unsigned int step = 1; step <= n_steps; ++step)
          {
            apply_load_step(step);
            // (step 1 starts cold: a previous mesh's state is that of the
            // end of the path; so does a step without data, as a static
            // problem without load: its first iterate, u = 0, is then the
            // answer wherever the gap allows it, exactly, where the warm
            // start left round-off that the checks measured against a zero
            // scale)
            const bool cold = (step == 1 || data_vanish());
            if (cold)
              solution = 0.;
            try
              {
                solve_step(cold ? InitialGuess() :
                                  InitialGuess{active_rows, {}},
                           step > 1 && friction_law_.enabled() ? &previous :
                                                                 nullptr);
              }
            catch (const InputError &error)
              {
                std::ostringstream where;
                where << "Contact/Load steps: at step " << step
                      << " (t = " << load_path_.time(step) << ", Load factor "
                      << load_path_.factor(step) << "): " << error.what();
                throw InputError(where.str());
              }
            path.add_counts(last_summary.report);
            path_seconds += last_summary.solve_seconds;
            if (load_step_observer)
              load_step_observer(step);
            if (!last_solve_converged)
              {
                solve_failure = step_context(step) + solve_failure;
                break;
              }
            previous = friction_state;
          }
        path.converged             = last_summary.report.converged;
        path.residual              = last_summary.report.residual;
        path.failure               = last_summary.report.failure;
        last_summary.report        = path;
        last_summary.solve_seconds = path_seconds;
      }
    last_summary.setup_seconds = setup_timer.wall_time();
    last_summary.solve_seconds += last_summary.nested.seconds;
    // the estimate that follows needs the memory more than the rare solve
    // after it (the pointwise condition's admissible displacement), which
    // builds a preconditioner again
    elasticity_solver.release_preconditioner();
  }



  template <int dim>
  void
  ContactComputation<dim>::solve_step(
    const InitialGuess       &guess,
    const FrictionState<dim> *previous_friction)
  {
    const DiscreteContactProblem<dim> problem = contact_problem();
    problem.check_rigid_motions();
    Timer solve_timer;
    {
      PhaseTimer::Scope t(timer, "contact solve");
      if (friction_law_.enabled())
        last_summary.report =
          FrictionalActiveSetSolver<dim>(friction_law_,
                                         friction_max_iterations,
                                         friction_method,
                                         friction_preconditioner_update,
                                         friction_uniqueness_steps,
                                         friction_inexact_tolerance)
            .solve(problem,
                   solution,
                   dual_solution,
                   friction_state,
                   guess.active,
                   previous_friction,
                   &guess.friction);
      else
        last_summary.report =
          contact_solver->solve(problem, solution, dual_solution, guess.active);
    }
    solve_timer.stop();

    // A row is active when its multiplier is positive beyond round-off (the
    // same rule for both solvers, so that their active sets compare).
    const double threshold = 1e-8 * max_norm(dual_solution);
    active_rows.assign(dual_solution.size(), false);
    last_summary.n_active = 0;
    last_contact_state.assign(dual_solution.size(), {});
    // (a row's tangential multiplier as a traction, comparable across
    // meshes: times the row sum of W, over the node's area)
    const Vector<double> areas =
      friction_law_.enabled() ? gamma_c.nodal_areas() : Vector<double>();
    for (unsigned int i = 0; i < dual_solution.size(); ++i)
      {
        active_rows[i] = dual_solution[i] > threshold;
        last_summary.n_active += active_rows[i] ? 1 : 0;
        const unsigned int node = gamma_c.multiplier_nodes()[i];
        auto              &row  = last_contact_state[i];
        row.position            = gamma_c.node(node).position;
        row.in_contact          = active_rows[i];
        if (friction_law_.enabled() && areas[node] > 0.)
          {
            row.sticks =
              (friction_state.status[i] != FrictionState<dim>::Status::slip);
            row.tangential_traction = friction_state.force[i] *
                                      contact_condition->row_sum(i) /
                                      areas[node];
          }
      }
    last_summary.contact_force = 0.;
    for (const double f : contact_condition->nodal_forces(dual_solution))
      last_summary.contact_force += f;

    // (P1: the support point of a dof is its vertex; every rank sees all
    // cells)
    std::vector<Point<dim>>   support_points(dofs.n_dofs());
    std::vector<unsigned int> dof_component(dofs.n_dofs());
    {
      std::vector<types::global_dof_index> cell_dofs(fe.n_dofs_per_cell());
      for (const auto &cell : dofs.active_cell_iterators())
        {
          cell->get_dof_indices(cell_dofs);
          for (unsigned int i = 0; i < cell_dofs.size(); ++i)
            {
              const auto [component, vertex] = fe.system_to_component_index(i);
              dof_component[cell_dofs[i]]    = component;
              support_points[cell_dofs[i]]   = cell->vertex(vertex);
            }
        }
    }
    // the friction forces on the body, at the tangential dofs
    std::vector<std::pair<types::global_dof_index, double>> friction_forces;
    for (unsigned int k = 0; k < friction_state.nodal_force.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        if (friction_state.nodal_force[k][c] != 0.)
          friction_forces.emplace_back(gamma_c.node(k).dofs[c],
                                       friction_state.nodal_force[k][c]);
    last_summary.checks = check_solution(problem,
                                         solution,
                                         dual_solution,
                                         dirichlet_constraints,
                                         support_points,
                                         dof_component,
                                         friction_forces);
    if (friction_law_.enabled())
      check_friction(friction_state,
                     problem.constraint_scale(solution),
                     max_norm(dual_solution),
                     last_summary.checks);
    last_summary.energy        = problem.energy(solution);
    last_summary.solve_seconds = solve_timer.wall_time();
    judge_solution();
  }



  template <int dim>
  void
  ContactComputation<dim>::judge_solution()
  {
    // the solver's word is not enough: the checks decide
    const auto &report                    = last_summary.report;
    const auto [worst_check, worst_value] = last_summary.checks.largest();
    last_solve_converged = report.converged && worst_value <= check_tolerance;
    const auto brief     = [](const double x) {
      std::ostringstream text;
      text << std::setprecision(3) << x;
      return text.str();
    };
    solve_failure.clear();
    const std::string solver_name =
      friction_law_.enabled() ?
        FrictionalActiveSetSolver<dim>::name(friction_method) :
        contact_solver->name();
    // (the KKT residual leaves out the friction checks: the largest check
    // says what failed)
    if (!report.converged)
      solve_failure =
        "the " + solver_name + " solver did not converge (" +
        (report.failure.empty() ?
           "in " + std::to_string(report.iterations) +
             " iterations: KKT residual " + brief(report.residual) +
             ", largest check " + worst_check + " " + brief(worst_value) :
           report.failure) +
        ")";
    else if (!last_solve_converged)
      solve_failure = "the solution checks fail: " + worst_check + " " +
                      brief(worst_value) +
                      " > Contact/Check tolerance = " + brief(check_tolerance);
  }



  template <int dim>
  typename ContactComputation<dim>::InitialGuess
  ContactComputation<dim>::initial_guess() const
  {
    const ContactState &previous = last_contact_state;
    if (previous.empty())
      return {};
    // A node of the new mesh that is a node of the previous one keeps its
    // state.
    const auto  &nodes = gamma_c.multiplier_nodes();
    InitialGuess guess;
    guess.active.assign(nodes.size(), false);
    Point<dim> lower = previous[0].position, upper = lower;
    for (const auto &state : previous)
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d] = std::min(lower[d], state.position[d]);
          upper[d] = std::max(upper[d], state.position[d]);
        }
    const double tolerance = 1e-10 * lower.distance(upper);
    std::vector<std::array<unsigned int, 2>> nearest(nodes.size());
    unsigned int                             n_kept = 0;
    for (unsigned int i = 0; i < nodes.size(); ++i)
      {
        const Point<dim> &x = gamma_c.node(nodes[i]).position;
        std::vector<std::pair<double, unsigned int>> by_distance;
        for (unsigned int j = 0; j < previous.size(); ++j)
          by_distance.emplace_back(x.distance(previous[j].position), j);
        const unsigned int n_nearest =
          std::min<std::size_t>(2, by_distance.size());
        std::partial_sort(by_distance.begin(),
                          by_distance.begin() + n_nearest,
                          by_distance.end());
        nearest[i] = {
          {by_distance[0].second, by_distance[n_nearest - 1].second}};
        n_kept += (by_distance[0].first < tolerance) ? 1 : 0;
      }
    // A refined mesh keeps every node of the previous one: there a new
    // node lies between two (active if both were). On a mesh made anew the
    // nearest decides.
    const bool        refined = (n_kept == previous.size());
    std::vector<bool> kept(nodes.size());
    for (unsigned int i = 0; i < nodes.size(); ++i)
      {
        const bool active0 = previous[nearest[i][0]].in_contact;
        const bool active1 = previous[nearest[i][1]].in_contact;
        kept[i]            = gamma_c.node(nodes[i]).position.distance(
                    previous[nearest[i][0]].position) < tolerance;
        guess.active[i] = active0 && (kept[i] || !refined || active1);
      }
    if (!friction_law_.enabled())
      return guess;

    // With friction, a node in contact slides if its nearest did (a new
    // node between two of a refined mesh: if either did), under their
    // tangential traction (the mean of the two) times its area.
    const Vector<double> areas = gamma_c.nodal_areas();
    guess.friction.stick.assign(nodes.size(), true);
    guess.friction.slip_force.assign(nodes.size(), Tensor<1, dim>());
    for (unsigned int i = 0; i < nodes.size(); ++i)
      {
        const auto &state0 = previous[nearest[i][0]];
        const auto &state1 =
          (kept[i] || !refined) ? state0 : previous[nearest[i][1]];
        if (state0.sticks && state1.sticks)
          continue;
        guess.friction.stick[i] = false;
        guess.friction.slip_force[i] =
          0.5 * (state0.tangential_traction + state1.tangential_traction) *
          areas[nodes[i]] / contact_condition->row_sum(i);
      }
    return guess;
  }



  template <int dim>
  void
  ContactComputation<dim>::enable_nested_start(const MeshInput<dim> &input)
  {
    nested_start_input = input;
  }



  template <int dim>
  void
  ContactComputation<dim>::start_from_coarser_meshes()
  {
    Timer nested_timer;
    // The coarser meshes, coarsest first, each about 2^dim times fewer
    // cells than the next, the first with at most Nested start cells: the
    // input with fewer refinements, or, for a mesh without coarser levels
    // (a mesh file or a .geo not refined), its domain meshed again by Gmsh.
    const MeshInput<dim> &input      = *nested_start_input;
    const unsigned int    fine_level = input.initial_refinements;
    const double fine_cells = dofs.get_triangulation().n_global_active_cells();
    const auto   n_cells    = [&](const unsigned int coarsening) {
      return fine_cells / Utilities::fixed_power<dim>(std::pow(2., coarsening));
    };
    std::vector<std::function<void(Triangulation<dim> &)>> coarser_meshes;
    if (fine_level > 0)
      {
        unsigned int first_level = fine_level;
        while (first_level > 0 &&
               n_cells(fine_level - first_level) > nested_start_cells)
          --first_level;
        for (unsigned int level = first_level; level < fine_level; ++level)
          coarser_meshes.emplace_back([&input, level](Triangulation<dim> &t) {
            MeshInput<dim> coarser      = input;
            coarser.initial_refinements = level;
            coarser.create(t);
          });
      }
    else if (n_cells(2) >= nested_start_cells / 4.)
      {
        // Down to 4 times the fine size: measured on Gmsh meshes of the
        // block, in 2D and 3D, the mesh at twice the size costs more time
        // than it saves. And only if that mesh has at least a quarter of
        // Nested start cells: a coarser one predicts too little to pay for
        // Gmsh (a 3D cube of 4 964 tetrahedra: 0.16 s instead of 0.07 s).
        const unsigned int last       = 2;
        unsigned int       coarsening = last;
        while (n_cells(coarsening) > nested_start_cells)
          ++coarsening;
        std::vector<double> relative_sizes;
        for (; coarsening >= last; --coarsening)
          relative_sizes.push_back(std::pow(2., coarsening));
        const auto mesher =
          std::make_shared<CoarseDomainMesher<dim>>(dofs.get_triangulation(),
                                                    relative_sizes);
        for (unsigned int i = 0; i < relative_sizes.size(); ++i)
          coarser_meshes.emplace_back(
            [mesher, i](Triangulation<dim> &t) { mesher->create(i, t); });
      }
    if (coarser_meshes.empty())
      return;

    // The meshes are declared before the computation on them, so that its
    // DoFHandler is gone before they are (also when a step throws); they
    // are distributed as the current mesh.
    const auto *shared =
      dynamic_cast<const parallel::shared::Triangulation<dim> *>(
        &dofs.get_triangulation());
    std::vector<std::unique_ptr<Triangulation<dim>>> meshes;
    std::unique_ptr<ContactComputation<dim>>         coarse;
    try
      {
        coarse.reset(new ContactComputation<dim>(*parameters,
                                                 timer,
                                                 /*with_nested_start=*/false));
        // (the chain of coarser meshes is the point; their solutions are
        // guesses, whose uniqueness the fine one's check shows)
        coarse->guess_from_previous_cycle = true;
        coarse->friction_uniqueness_steps = 0;
        for (const auto &create_coarser_mesh : coarser_meshes)
          {
            if (shared != nullptr)
              meshes.push_back(
                std::make_unique<parallel::shared::Triangulation<dim>>(
                  shared->get_communicator(),
                  shared->get_mesh_smoothing(),
                  shared->with_artificial_cells(),
                  parallel::shared::Triangulation<dim>::partition_metis));
            else
              meshes.push_back(std::make_unique<Triangulation<dim>>());
            create_coarser_mesh(*meshes.back());
            coarse->setup(*meshes.back());
            coarse->assemble();
            coarse->solve();
            ++last_summary.nested.meshes;
            last_summary.nested.iterations +=
              coarse->summary().report.iterations;
          }
        last_contact_state = coarse->contact_state();
        // the displacement too: the first solves start closer
        const Vector<double> fine =
          interpolate_at_vertices(coarse->dof_handler(),
                                  replicate(coarse->displacement()),
                                  dofs);
        for (const auto i : locally_owned_dofs)
          solution[i] = fine[i];
        solution.compress(VectorOperation::insert);
      }
    catch (const std::runtime_error &exc)
      {
        // Input errors and solver failures happen on every rank alike (the
        // same data, the same algorithm): a cold start still solves the
        // problem, and a real input error reappears there. (Anything else,
        // e.g. an allocation failure on one rank, is not caught: the other
        // ranks would wait for this one.)
        last_summary.nested         = {};
        last_summary.nested.failure = exc.what();
        last_contact_state.clear();
        solution = 0.;
      }
    coarse.reset();
    meshes.clear();
    last_summary.nested.seconds = nested_timer.wall_time();
  }



  template <int dim>
  void
  ContactComputation<dim>::set_initial_contact_state(const ContactState &state)
  {
    last_contact_state = state;
  }



  template <int dim>
  std::vector<unsigned int>
  ContactComputation<dim>::contact_transition_vertices() const
  {
    // state of every node of GC: -1 no multiplier, 0 separated, 1 active
    std::vector<int> state(gamma_c.n_nodes(), -1);
    const auto      &multiplier_nodes = gamma_c.multiplier_nodes();
    for (unsigned int i = 0; i < multiplier_nodes.size(); ++i)
      state[multiplier_nodes[i]] = active_rows[i] ? 1 : 0;
    std::vector<unsigned int> vertices;
    for (const auto &cell : dofs.get_triangulation().active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() &&
            gamma_c.boundary_ids().count(face->boundary_id()) != 0)
          {
            // a face with nodes in both states: all its vertices
            bool contact = false, separated = false;
            for (const unsigned int v : face->vertex_indices())
              {
                const int s = state[gamma_c.node_index(face->vertex_index(v))];
                contact |= (s == 1);
                separated |= (s == 0);
              }
            if (contact && separated)
              for (const unsigned int v : face->vertex_indices())
                vertices.push_back(face->vertex_index(v));
          }
    return vertices;
  }



  template <int dim>
  const typename ContactComputation<dim>::ContactState &
  ContactComputation<dim>::contact_state() const
  {
    return last_contact_state;
  }



  template <int dim>
  bool
  ContactComputation<dim>::converged() const
  {
    return last_solve_converged;
  }



  template <int dim>
  const std::string &
  ContactComputation<dim>::failure() const
  {
    return solve_failure;
  }



  template <int dim>
  const typename ContactComputation<dim>::Summary &
  ContactComputation<dim>::summary() const
  {
    return last_summary;
  }



  template <int dim>
  const FESystem<dim> &
  ContactComputation<dim>::finite_element() const
  {
    return fe;
  }



  template <int dim>
  const Mapping<dim> &
  ContactComputation<dim>::mapping() const
  {
    return mapping_fe;
  }



  template <int dim>
  const DoFHandler<dim> &
  ContactComputation<dim>::dof_handler() const
  {
    return dofs;
  }



  template <int dim>
  double
  ContactComputation<dim>::domain_diameter() const
  {
    return mesh_diameter;
  }



  template <int dim>
  const IndexSet &
  ContactComputation<dim>::locally_relevant_dofs() const
  {
    return relevant_dofs;
  }



  template <int dim>
  const LA::SparseMatrix &
  ContactComputation<dim>::stiffness_matrix() const
  {
    return stiffness;
  }



  template <int dim>
  const LA::Vector &
  ContactComputation<dim>::displacement() const
  {
    return solution;
  }



  template <int dim>
  const Vector<double> &
  ContactComputation<dim>::dual() const
  {
    return dual_solution;
  }



  template <int dim>
  const std::vector<bool> &
  ContactComputation<dim>::active_set() const
  {
    return active_rows;
  }



  template <int dim>
  const LinearElasticMaterial<dim> &
  ContactComputation<dim>::material() const
  {
    return material_law;
  }



  template <int dim>
  const BoundaryConditions<dim> &
  ContactComputation<dim>::boundary_conditions() const
  {
    return boundary_data;
  }



  template <int dim>
  const ContactBoundary<dim> &
  ContactComputation<dim>::contact_boundary() const
  {
    return gamma_c;
  }



  template <int dim>
  const ContactCondition<dim> &
  ContactComputation<dim>::condition() const
  {
    return *contact_condition;
  }



  template <int dim>
  const ContactSolver<dim> &
  ContactComputation<dim>::solver() const
  {
    return *contact_solver;
  }



  template <int dim>
  const FrictionLaw<dim> &
  ContactComputation<dim>::friction_law() const
  {
    return friction_law_;
  }



  template <int dim>
  void
  ContactComputation<dim>::set_load_step_observer(
    std::function<void(unsigned int)> observer)
  {
    load_step_observer = std::move(observer);
  }



  template <int dim>
  const LoadPath &
  ContactComputation<dim>::load_path() const
  {
    return load_path_;
  }



  template <int dim>
  const FrictionState<dim> &
  ContactComputation<dim>::friction() const
  {
    return friction_state;
  }



  template <int dim>
  const ElasticitySolver &
  ContactComputation<dim>::linear_solver() const
  {
    return elasticity_solver;
  }

  template class ContactComputation<2>;
  template class ContactComputation<3>;
} // namespace Signorini
