#include <signorini/contact/active_set_solver.h>
#include <signorini/contact/frank_wolfe_solver.h>
#include <signorini/contact/solver.h>

namespace Signorini
{
  template <int dim>
  const Registry<ContactSolver<dim>> &
  ContactSolver<dim>::registry()
  {
    static const Registry<ContactSolver<dim>> solvers = [] {
      Registry<ContactSolver<dim>> family(
        "Contact", "Solver", "Algorithm for the discrete contact problem");
      family.template add<ActiveSetSolver<dim>>(
        "active set", "primal-dual active set method, doc/theory.md section 3");
      family.template add<FrankWolfeSolver<dim>>(
        "Frank-Wolfe",
        "on the dual problems [23], [24] as in the paper, doc/theory.md "
        "section 4");
      return family;
    }();
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
