#include <deal.II/base/mpi.h>

#include <signorini/estimator/lagrange_star_patch.h>
#include <signorini/estimator/star_patch_equilibration.h>

namespace Signorini
{
  template <int dim>
  void
  StarPatchEquilibration<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    prm.enter_subsection("Star patch");
    prm.declare_entry("Local degree",
                      "2",
                      Patterns::Integer(2, 3),
                      "Polynomial degree of the vertex-patch problems (p + 1 "
                      "= 2 by default; higher degrees approach the exact "
                      "patch solutions and a larger effectivity, see "
                      "doc/estimator.md); at most 3 on triangles and 2 on "
                      "tetrahedra.");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  void
  StarPatchEquilibration<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    prm.enter_subsection("Star patch");
    local_degree = prm.get_integer("Local degree");
    prm.leave_subsection();
    prm.leave_subsection();

    // deal.II 9.4's FE_SimplexP fails on tetrahedra beyond degree 2 (the
    // pattern holds triangles to 3)
    if (dim == 3 && local_degree > 2)
      throw InputError("Error estimator/Star patch/Local degree = " +
                       std::to_string(local_degree) +
                       ": at most 2 on tetrahedra");
  }



  template <int dim>
  std::string
  StarPatchEquilibration<dim>::condition() const
  {
    return "the finite element equilibrium R(phi_i e_c) = 0 of the patch data";
  }



  template <int dim>
  void
  StarPatchEquilibration<dim>::compute(
    const EquilibrationInput<dim> &input,
    const LA::Vector              &admissible_displacement,
    Vector<double>                &error_squared,
    Vector<double>                &sum_squared)
  {
    const StarPatchDefects defects = compute_lagrange_star_patch(
      input, admissible_displacement, local_degree, error_squared, sum_squared);
    const MPI_Comm communicator =
      input.dof_handler.get_triangulation().get_communicator();
    this->max_equilibrium_defect =
      Utilities::MPI::max(defects.equilibrium, communicator);
    this->max_condition_defect =
      Utilities::MPI::max(defects.galerkin, communicator);
  }



  template class StarPatchEquilibration<2>;
  template class StarPatchEquilibration<3>;

  SIGNORINI_REGISTER_TEMPLATE(StressReconstruction,
                              StarPatchEquilibration,
                              1,
                              "star patch",
                              "flux-free vertex-patch problems");
} // namespace Signorini
