// A deal.II elasticity program of one's own -- its mesh, its finite element,
// its assembly loop, its output -- that hands its stiffness matrix and load
// to signorini's contact solver and asks signorini's estimator how accurate
// the result is (doc/library.md).
//
// The problem is the paper's block (prm/block.prm): the unit square clamped
// on the left, pressed by p = 0.1 on the left half of its top and the upper
// half of its right side, resting on a rigid foundation along its bottom.
// It prints the figures the signorini executable prints for prm/block.prm,
// which the test installed_package compares.

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <signorini/boundary_conditions.h>
#include <signorini/contact/condition.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/contact/discrete_problem.h>
#include <signorini/contact/rigid_motions.h>
#include <signorini/contact/solution_checks.h>
#include <signorini/contact/solver.h>
#include <signorini/estimator/constitutive_relation_error.h>
#include <signorini/linear_solver.h>
#include <signorini/material.h>

#include <fstream>
#include <iomanip>
#include <iostream>

using namespace dealii;

namespace
{
  constexpr int dim = 2;

  // The data, in signorini's parameter sections: the contact solver reads
  // its sections, the estimator the material and the boundary conditions
  // (it must know where displacements are prescribed and where tractions
  // act), and this program builds its constraints and assembles from the
  // same material and boundary conditions.
  const char *const parameters = R"(
subsection Material
  set Young modulus = 1
  set Poisson ratio = 0.3
end
subsection Boundary conditions
  subsection Dirichlet 1
    set Boundary ids        = 1
    set Components          = x, y
    set Function expression = 0; 0
  end
  subsection Traction 1
    set Boundary ids        = 3
    set Function expression = 0; -0.1
  end
  subsection Traction 2
    set Boundary ids        = 4
    set Function expression = -0.1; 0
  end
end
subsection Contact
  set Boundary ids = 2
  set Direction    = 0, -1
  set Condition    = integral
  set Solver       = active set
end
)";

  // The paper's block: 4 x 3 rectangles of 8 triangles, refined twice;
  // boundary ids 1 left, 2 bottom, 3 and 5 top, 4 and 6 right (upper and
  // lower halves).
  void
  make_block(Triangulation<dim> &triangulation)
  {
    Triangulation<dim> rectangles;
    GridGenerator::subdivided_hyper_rectangle(rectangles,
                                              {4, 3},
                                              Point<dim>(),
                                              Point<dim>(1., 1.));
    GridGenerator::convert_hypercube_to_simplex_mesh(rectangles, triangulation);
    for (const auto &face : triangulation.active_face_iterators())
      if (face->at_boundary())
        {
          const Point<dim> c = face->center();
          if (std::abs(c[0]) < 1e-10)
            face->set_boundary_id(1);
          else if (std::abs(c[1]) < 1e-10)
            face->set_boundary_id(2);
          else if (std::abs(c[1] - 1.) < 1e-10)
            face->set_boundary_id(c[0] < 0.5 ? 3 : 5);
          else
            face->set_boundary_id(c[1] > 0.5 ? 4 : 6);
        }
    triangulation.refine_global(2);
  }
} // namespace



int
main(int argc, char **argv)
{
  try
    {
      Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
      const MPI_Comm                   communicator = MPI_COMM_WORLD;
      // (a serial Triangulation: every rank would own every dof; on several
      // ranks, use a parallel::shared::Triangulation, doc/library.md)
      if (Utilities::MPI::n_mpi_processes(communicator) > 1)
        {
          std::cerr << "error: this example runs on one rank" << std::endl;
          return 1;
        }

      // signorini's parts declare and read their own sections
      ParameterHandler prm;
      Signorini::LinearElasticMaterial<dim>::declare_parameters(prm);
      Signorini::BoundaryConditions<dim>::declare_parameters(prm);
      Signorini::ContactBoundary<dim>::declare_parameters(prm);
      Signorini::ContactCondition<dim>::registry().declare_parameters(prm);
      Signorini::ContactSolver<dim>::registry().declare_parameters(prm);
      Signorini::ElasticitySolver::declare_parameters(prm);
      Signorini::ConstitutiveRelationError<dim>::declare_parameters(prm);
      prm.parse_input_from_string(parameters);
      Signorini::LinearElasticMaterial<dim> material;
      material.parse_parameters(prm);
      Signorini::BoundaryConditions<dim> loads;
      loads.parse_parameters(prm);

      // 1. this program's discretisation: P1 on triangles
      Triangulation<dim> triangulation;
      make_block(triangulation);
      const FESystem<dim>  fe(FE_SimplexP<dim>(1), dim);
      const MappingFE<dim> mapping(FE_SimplexP<dim>(1));
      DoFHandler<dim>      dof_handler(triangulation);
      dof_handler.distribute_dofs(fe);
      const IndexSet owned = dof_handler.locally_owned_dofs();

      // the prescribed displacements (no hanging nodes on this mesh)
      AffineConstraints<double> hanging, dirichlet, homogeneous;
      hanging.close();
      for (const auto &part : loads.dirichlet)
        for (const types::boundary_id id : part.ids)
          {
            VectorTools::interpolate_boundary_values(mapping,
                                                     dof_handler,
                                                     id,
                                                     *part.displacement,
                                                     dirichlet,
                                                     part.mask);
            VectorTools::interpolate_boundary_values(
              mapping,
              dof_handler,
              id,
              Functions::ZeroFunction<dim>(dim),
              homogeneous,
              part.mask);
          }
      dirichlet.close();
      homogeneous.close();

      // 2. this program's assembly: the raw K and F (the contact solver
      //    applies the constraints itself, and its residuals are forces)
      DynamicSparsityPattern dsp(dof_handler.n_dofs());
      DoFTools::make_sparsity_pattern(dof_handler, dsp, dirichlet, true);
      Signorini::LA::SparseMatrix stiffness;
      stiffness.reinit(owned, owned, dsp, communicator);
      Signorini::LA::Vector                load(owned, communicator);
      const QGaussSimplex<dim>             quadrature(2);
      const QGaussSimplex<dim - 1>         face_quadrature(2);
      FEValues<dim>                        fe_values(mapping,
                              fe,
                              quadrature,
                              update_gradients | update_JxW_values);
      FEFaceValues<dim>                    face_values(mapping,
                                    fe,
                                    face_quadrature,
                                    update_values | update_quadrature_points |
                                      update_JxW_values);
      const FEValuesExtractors::Vector     displacement(0);
      const unsigned int                   n = fe.n_dofs_per_cell();
      FullMatrix<double>                   cell_matrix(n, n);
      Vector<double>                       cell_load(n);
      std::vector<types::global_dof_index> indices(n);
      std::vector<Vector<double>>          traction(face_quadrature.size(),
                                           Vector<double>(dim));
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          fe_values.reinit(cell);
          cell_matrix = 0.;
          cell_load   = 0.;
          for (const unsigned int q : fe_values.quadrature_point_indices())
            for (unsigned int i = 0; i < n; ++i)
              {
                const auto sigma_i = material.stress(
                  fe_values[displacement].symmetric_gradient(i, q));
                for (unsigned int j = 0; j < n; ++j)
                  cell_matrix(i, j) +=
                    sigma_i * fe_values[displacement].symmetric_gradient(j, q) *
                    fe_values.JxW(q);
              }
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() &&
                loads.has_traction(cell->face(f)->boundary_id()))
              {
                face_values.reinit(cell, f);
                loads.traction_values(cell->face(f)->boundary_id(),
                                      face_values.get_quadrature_points(),
                                      traction);
                for (const unsigned int q :
                     face_values.quadrature_point_indices())
                  for (unsigned int i = 0; i < n; ++i)
                    cell_load(i) +=
                      traction[q][fe.system_to_component_index(i).first] *
                      face_values.shape_value(i, q) * face_values.JxW(q);
              }
          cell->get_dof_indices(indices);
          stiffness.add(indices, cell_matrix);
          load.add(indices, cell_load);
        }
      stiffness.compress(VectorOperation::add);
      load.compress(VectorOperation::add);

      // 3. signorini's contact solve: the foundation's boundary, the
      //    condition and the solver the parameters chose, the linear solver
      Signorini::ContactBoundary<dim> contact_boundary;
      contact_boundary.parse_parameters(prm);
      contact_boundary.reinit(mapping, dof_handler, dirichlet, hanging);
      const auto condition =
        Signorini::ContactCondition<dim>::registry().create(prm);
      condition->reinit(contact_boundary);
      const auto solver = Signorini::ContactSolver<dim>::registry().create(prm);
      Signorini::RigidMotions<dim> rigid_motions;
      rigid_motions.reinit(dof_handler, dirichlet, hanging);
      Signorini::ElasticitySolver linear_solver;
      linear_solver.parse_parameters(prm);
      std::vector<std::vector<bool>> constant_modes;
      DoFTools::extract_constant_modes(dof_handler,
                                       ComponentMask(dim, true),
                                       constant_modes);
      linear_solver.initialize(stiffness,
                               dirichlet,
                               constant_modes,
                               rigid_motions.all_motions(),
                               rigid_motions.support_dofs());
      const Signorini::DiscreteContactProblem<dim> problem(stiffness,
                                                           load,
                                                           dirichlet,
                                                           homogeneous,
                                                           hanging,
                                                           contact_boundary,
                                                           *condition,
                                                           rigid_motions,
                                                           linear_solver);
      problem.check_rigid_motions();
      Signorini::LA::Vector u(owned, communicator);
      Vector<double>        y;
      const auto            report = solver->solve(problem, u, y);

      // its independent checks: feasibility, sign, complementarity,
      // equilibrium (support points and components of the P1 dofs)
      std::vector<Point<dim>>   support_points(dof_handler.n_dofs());
      std::vector<unsigned int> component(dof_handler.n_dofs());
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          cell->get_dof_indices(indices);
          for (unsigned int i = 0; i < n; ++i)
            {
              const auto [c, vertex]     = fe.system_to_component_index(i);
              component[indices[i]]      = c;
              support_points[indices[i]] = cell->vertex(vertex);
            }
        }
      const Signorini::SolutionChecks checks = Signorini::check_solution(
        problem, u, y, dirichlet, support_points, component);
      const auto [worst_check, worst_value] = checks.largest();
      if (!report.converged || !(worst_value < 1e-6))
        {
          std::cerr << "the contact solve failed: " << worst_check << " "
                    << worst_value << std::endl;
          return 2;
        }

      // 4. signorini's estimate: eps and eps_E, from (u, y)
      Signorini::ConstitutiveRelationError<dim> estimator;
      estimator.parse_parameters(prm);
      Signorini::LA::Vector admissible(owned, communicator);
      const auto            estimate = estimator.estimate(
        problem, mapping, dof_handler, material, loads, u, y, admissible);

      double contact_force = 0.;
      for (const double f : condition->nodal_forces(y))
        contact_force += f;
      std::cout << std::setprecision(10) << "cells "
                << triangulation.n_active_cells() << "\ndofs "
                << dof_handler.n_dofs() << "\nactive set iterations "
                << report.iterations << "\nenergy " << problem.energy(u)
                << "\ncontact_force " << contact_force << "\neps "
                << estimate.eps << "\nlargest check " << worst_check << " "
                << worst_value << std::endl;

      // 5. this program's output: u and eps_E for ParaView
      DataOut<dim> data_out;
      data_out.attach_dof_handler(dof_handler);
      const Vector<double> u_local(u);
      data_out.add_data_vector(
        u_local,
        std::vector<std::string>(dim, "u"),
        DataOut<dim>::type_dof_data,
        std::vector<DataComponentInterpretation::DataComponentInterpretation>(
          dim, DataComponentInterpretation::component_is_part_of_vector));
      data_out.add_data_vector(estimate.local, "eps_E");
      data_out.build_patches(mapping);
      std::ofstream vtu("contact_in_your_program.vtu");
      data_out.write_vtu(vtu);
    }
  catch (const std::exception &e)
    {
      std::cerr << "error: " << e.what() << std::endl;
      return 1;
    }
  return 0;
}
