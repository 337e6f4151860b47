#include <signorini/contact/solver.h>

namespace Signorini
{
  template <int dim>
  Registry<ContactSolver<dim>> &
  ContactSolver<dim>::registry()
  {
    // the solvers register themselves in their own files
    static Registry<ContactSolver<dim>> solvers(
      "Contact", "Solver", "Algorithm for the discrete contact problem");
    return solvers;
  }



  template <int dim>
  const std::string &
  ContactSolver<dim>::name() const
  {
    return registry().name_of(*this);
  }



  template <int dim>
  bool
  ContactSolver<dim>::uses_initial_active_set() const
  {
    return false;
  }



  template <int dim>
  bool
  ContactSolver<dim>::prefers_direct_solver(
    const types::global_dof_index /*n_dofs*/) const
  {
    return false;
  }

  template class ContactSolver<2>;
  template class ContactSolver<3>;
} // namespace Signorini
