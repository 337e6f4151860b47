// The library used by a program of its own (doc/library.md), misused as a
// hostile round did: each misuse must end in an exception that says what is
// wrong, not in memory corruption, a crash or a quiet wrong answer. The
// discretisation (ContactBoundary::reinit(), ConstitutiveRelationError::
// estimate()): a mesh of quadrilaterals, a P2 element, hanging nodes
// without their constraints, a contact boundary id on no face. The order of
// the calls: a condition not rebuilt for its boundary, a boundary never
// reinitialised, a linear solver not initialised, an estimator not parsed.
// The data of DiscreteContactProblem: constraints with values passed as
// the homogeneous ones, a stiffness matrix with the constraints condensed.
// Last, the same set-up used correctly, which solves and estimates.

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/fe/mapping_q.h>

#include <deal.II/grid/grid_generator.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <deal.II/numerics/vector_tools.h>

#include <signorini/boundary_conditions.h>
#include <signorini/contact/condition.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/contact/discrete_problem.h>
#include <signorini/contact/rigid_motions.h>
#include <signorini/contact/solver.h>
#include <signorini/estimator/constitutive_relation_error.h>
#include <signorini/linear_solver.h>
#include <signorini/material.h>

#include "tests.h"

namespace
{
  using namespace SignoriniTests;
  constexpr int dim = 2;

  const char *const parameters = R"(
subsection Boundary conditions
  subsection Dirichlet 1
    set Boundary ids        = 1
    set Components          = x, y
    set Function expression = 0; 0.01
  end
  subsection Traction 1
    set Boundary ids        = 3
    set Function expression = 0; -0.1
  end
end
subsection Contact
  set Boundary ids = 2
  set Direction    = 0, -1
end
)";

  /// What can go wrong, one at a time.
  struct Misuse
  {
    bool        quadrilaterals        = false;
    bool        quadratic             = false;
    bool        forgotten_hanging     = false;
    bool        no_condition_reinit   = false;
    bool        no_boundary_reinit    = false;
    bool        no_solver_initialize  = false;
    bool        no_estimator_parse    = false;
    bool        values_as_homogeneous = false;
    bool        condensed             = false;
    std::string contact_ids           = "2";
  };

  /// The example's sequence (examples/contact_in_your_program) on the unit
  /// square, the contact on y = 0, with @p misuse; logs eps at the end.
  void
  run(const Misuse &misuse)
  {
    ParameterHandler prm;
    LinearElasticMaterial<dim>::declare_parameters(prm);
    BoundaryConditions<dim>::declare_parameters(prm);
    ContactBoundary<dim>::declare_parameters(prm);
    ContactCondition<dim>::registry().declare_parameters(prm);
    ContactSolver<dim>::registry().declare_parameters(prm);
    ElasticitySolver::declare_parameters(prm);
    ConstitutiveRelationError<dim>::declare_parameters(prm);
    prm.parse_input_from_string(parameters);
    prm.enter_subsection("Contact");
    prm.set("Boundary ids", misuse.contact_ids);
    prm.leave_subsection();
    LinearElasticMaterial<dim> material;
    material.parse_parameters(prm);
    BoundaryConditions<dim> loads;
    loads.parse_parameters(prm);

    Triangulation<dim> triangulation;
    {
      Triangulation<dim> squares;
      GridGenerator::subdivided_hyper_cube(squares, 4);
      if (misuse.quadrilaterals)
        triangulation.copy_triangulation(squares);
      else
        GridGenerator::convert_hypercube_to_simplex_mesh(squares,
                                                         triangulation);
      for (const auto &face : triangulation.active_face_iterators())
        if (face->at_boundary())
          face->set_boundary_id(std::abs(face->center()[0]) < 1e-10 ? 1 :
                                std::abs(face->center()[1]) < 1e-10 ? 2 :
                                                                      3);
      if (misuse.forgotten_hanging)
        {
          triangulation.begin_active()->set_refine_flag();
          triangulation.execute_coarsening_and_refinement();
        }
    }
    const auto fe = misuse.quadrilaterals ?
                      std::make_unique<FESystem<dim>>(FE_Q<dim>(1), dim) :
                      std::make_unique<FESystem<dim>>(
                        FE_SimplexP<dim>(misuse.quadratic ? 2 : 1), dim);
    const auto mapping_pointer =
      misuse.quadrilaterals ?
        std::unique_ptr<Mapping<dim>>(new MappingQ<dim>(1)) :
        std::unique_ptr<Mapping<dim>>(new MappingFE<dim>(FE_SimplexP<dim>(1)));
    const Mapping<dim> &mapping = *mapping_pointer;
    DoFHandler<dim>     dof_handler(triangulation);
    dof_handler.distribute_dofs(*fe);
    const IndexSet owned = dof_handler.locally_owned_dofs();

    AffineConstraints<double> hanging, dirichlet, homogeneous;
    hanging.close();
    for (const auto &part : loads.dirichlet)
      for (const types::boundary_id id : part.ids)
        {
          VectorTools::interpolate_boundary_values(
            mapping, dof_handler, id, *part.displacement, dirichlet, part.mask);
          VectorTools::interpolate_boundary_values(mapping,
                                                   dof_handler,
                                                   id,
                                                   Functions::ZeroFunction<dim>(
                                                     dim),
                                                   homogeneous,
                                                   part.mask);
        }
    dirichlet.close();
    homogeneous.close();

    DynamicSparsityPattern dsp(dof_handler.n_dofs());
    DoFTools::make_sparsity_pattern(dof_handler, dsp, dirichlet, true);
    LA::SparseMatrix stiffness;
    stiffness.reinit(owned, owned, dsp, MPI_COMM_WORLD);
    LA::Vector                           load(owned, MPI_COMM_WORLD);
    const auto                           quadrature = QGaussSimplex<dim>(2);
    const auto                           n          = fe->n_dofs_per_cell();
    FullMatrix<double>                   cell_matrix(n, n);
    Vector<double>                       cell_load(n);
    std::vector<types::global_dof_index> indices(n);
    if (!misuse.quadrilaterals)
      {
        FEValues<dim>                    fe_values(mapping,
                                *fe,
                                quadrature,
                                update_gradients | update_JxW_values);
        const FEValuesExtractors::Vector u(0);
        for (const auto &cell : dof_handler.active_cell_iterators())
          {
            fe_values.reinit(cell);
            cell_matrix = 0.;
            cell_load   = 0.;
            for (const unsigned int q : fe_values.quadrature_point_indices())
              for (unsigned int i = 0; i < n; ++i)
                for (unsigned int j = 0; j < n; ++j)
                  cell_matrix(i, j) +=
                    material.stress(fe_values[u].symmetric_gradient(i, q)) *
                    fe_values[u].symmetric_gradient(j, q) * fe_values.JxW(q);
            // (a uniform weight: the load only has to press)
            for (unsigned int i = 0; i < n; ++i)
              if (fe->system_to_component_index(i).first == 1)
                cell_load(i) = -1e-3;
            cell->get_dof_indices(indices);
            if (misuse.condensed)
              dirichlet.distribute_local_to_global(
                cell_matrix, cell_load, indices, stiffness, load);
            else
              {
                stiffness.add(indices, cell_matrix);
                load.add(indices, cell_load);
              }
          }
      }
    stiffness.compress(VectorOperation::add);
    load.compress(VectorOperation::add);

    ContactBoundary<dim> contact_boundary;
    contact_boundary.parse_parameters(prm);
    if (!misuse.no_boundary_reinit)
      contact_boundary.reinit(mapping, dof_handler, dirichlet, hanging);
    const auto condition = ContactCondition<dim>::registry().create(prm);
    if (!misuse.no_condition_reinit)
      condition->reinit(contact_boundary);
    const auto        solver = ContactSolver<dim>::registry().create(prm);
    RigidMotions<dim> rigid_motions;
    rigid_motions.reinit(dof_handler, dirichlet, hanging);
    ElasticitySolver linear_solver;
    linear_solver.parse_parameters(prm);
    std::vector<std::vector<bool>> constant_modes;
    DoFTools::extract_constant_modes(dof_handler,
                                     ComponentMask(dim, true),
                                     constant_modes);
    LA::Vector u(owned, MPI_COMM_WORLD);
    if (misuse.no_solver_initialize)
      linear_solver.solve(dirichlet, load, u);
    linear_solver.initialize(stiffness,
                             dirichlet,
                             constant_modes,
                             rigid_motions.all_motions(),
                             rigid_motions.support_dofs());
    const DiscreteContactProblem<dim> problem(stiffness,
                                              load,
                                              dirichlet,
                                              misuse.values_as_homogeneous ?
                                                dirichlet :
                                                homogeneous,
                                              hanging,
                                              contact_boundary,
                                              *condition,
                                              rigid_motions,
                                              linear_solver);
    Vector<double>                    y;
    const auto                        report = solver->solve(problem, u, y);
    ConstitutiveRelationError<dim>    estimator;
    if (!misuse.no_estimator_parse)
      estimator.parse_parameters(prm);
    LA::Vector admissible;
    const auto result = estimator.estimate(
      problem, mapping, dof_handler, material, loads, u, y, admissible);
    deallog << "converged " << report.converged << ", eps "
            << std::setprecision(4) << result.eps << std::endl;
  }
} // namespace



int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const auto with = [](const auto &change) {
    Misuse misuse;
    change(misuse);
    return misuse;
  };
  const std::vector<std::pair<std::string, Misuse>> cases = {
    {"quadrilaterals", with([](Misuse &m) { m.quadrilaterals = true; })},
    {"P2 element", with([](Misuse &m) { m.quadratic = true; })},
    {"hanging nodes without constraints",
     with([](Misuse &m) { m.forgotten_hanging = true; })},
    {"contact id on no face", with([](Misuse &m) { m.contact_ids = "2, 7"; })},
    {"condition not rebuilt",
     with([](Misuse &m) { m.no_condition_reinit = true; })},
    {"boundary not reinitialised",
     with([](Misuse &m) { m.no_boundary_reinit = true; })},
    {"linear solver not initialised",
     with([](Misuse &m) { m.no_solver_initialize = true; })},
    {"estimator not parsed",
     with([](Misuse &m) { m.no_estimator_parse = true; })},
    {"values in the homogeneous constraints",
     with([](Misuse &m) { m.values_as_homogeneous = true; })},
    {"condensed stiffness matrix", with([](Misuse &m) { m.condensed = true; })},
    {"used correctly", Misuse()}};
  for (const auto &[name, misuse] : cases)
    {
      deallog << "--- " << name << std::endl;
      try
        {
          run(misuse);
        }
      catch (const std::exception &exc)
        {
          deallog << "refused: " << exc.what() << std::endl;
        }
    }
}
