#include <deal.II/base/mpi.h>

#include <deal.II/fe/fe.h>

#include <signorini/discretisation_check.h>

#include <stdexcept>

namespace Signorini
{
  template <int dim>
  void
  check_discretisation(
    const DoFHandler<dim>           &dof_handler,
    const std::string               &caller,
    const AffineConstraints<double> *hanging_node_constraints)
  {
    const auto &mesh = dof_handler.get_triangulation();
    std::string problem;
    if (!mesh.all_reference_cells_are_simplex())
      problem = "the mesh has cells that are not " +
                std::string(dim == 2 ? "triangles" : "tetrahedra") +
                " (convert it with "
                "GridGenerator::convert_hypercube_to_simplex_mesh())";
    else if (dof_handler.has_active_dofs() == false)
      problem = "the DoFHandler has no dofs (call distribute_dofs() first)";
    else
      {
        const auto &fe = dof_handler.get_fe();
        if (fe.n_components() != dim || fe.n_dofs_per_vertex() != dim ||
            fe.n_dofs_per_cell() != dim * (dim + 1) || fe.degree != 1)
          problem = "the finite element is " + fe.get_name() +
                    ", not the vector P1 element FESystem<" +
                    std::to_string(dim) + ">(FE_SimplexP<" +
                    std::to_string(dim) + ">(1), " + std::to_string(dim) + ")";
      }
    if (problem.empty())
      for (const auto &cell : mesh.active_cell_iterators())
        if (cell->is_artificial())
          {
            problem = "rank " +
                      std::to_string(Utilities::MPI::this_mpi_process(
                        mesh.get_communicator())) +
                      " does not hold the whole mesh (it has artificial "
                      "cells): use a serial Triangulation on one rank, or a "
                      "parallel::shared::Triangulation without artificial "
                      "cells";
            break;
          }
    if (problem.empty() && hanging_node_constraints != nullptr &&
        mesh.has_hanging_nodes() &&
        hanging_node_constraints->n_constraints() == 0)
      problem = "the mesh has hanging nodes but the hanging node constraints "
                "are empty (DoFTools::make_hanging_node_constraints())";
    // (the first rank's reason on every rank: a rank alone throwing would
    // leave the others waiting in a collective call)
    const MPI_Comm     communicator = mesh.get_communicator();
    const unsigned int failing =
      Utilities::MPI::min(problem.empty() ?
                            numbers::invalid_unsigned_int :
                            Utilities::MPI::this_mpi_process(communicator),
                          communicator);
    if (failing == numbers::invalid_unsigned_int)
      return;
    problem = Utilities::MPI::broadcast(communicator, problem, failing);
    throw std::invalid_argument(caller + ": " + problem);
  }

  template void
  check_discretisation<2>(const DoFHandler<2> &,
                          const std::string &,
                          const AffineConstraints<double> *);
  template void
  check_discretisation<3>(const DoFHandler<3> &,
                          const std::string &,
                          const AffineConstraints<double> *);
} // namespace Signorini
