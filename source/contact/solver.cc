#include <signorini/contact/active_set_solver.h>
#include <signorini/contact/frank_wolfe_solver.h>
#include <signorini/contact/solver.h>
#include <signorini/input_error.h>

namespace Signorini
{
  template <int dim>
  void
  declare_contact_solver_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.declare_entry("Solver",
                      "active set",
                      Patterns::Selection("active set|Frank-Wolfe"),
                      "Algorithm for the discrete contact problem: primal-"
                      "dual active set, or Frank-Wolfe on the dual QP as in "
                      "the paper.");
    prm.leave_subsection();
    ActiveSetSolver<dim>::declare_parameters(prm);
    FrankWolfeSolver<dim>::declare_parameters(prm);
  }



  template <int dim>
  std::unique_ptr<ContactSolver<dim>>
  create_contact_solver(const std::string &name, ParameterHandler &prm)
  {
    if (name == "active set")
      {
        auto solver = std::make_unique<ActiveSetSolver<dim>>();
        solver->parse_parameters(prm);
        return solver;
      }
    if (name == "Frank-Wolfe")
      {
        auto solver = std::make_unique<FrankWolfeSolver<dim>>();
        solver->parse_parameters(prm);
        return solver;
      }
    throw InputError("Contact/Solver: unknown solver <" + name + ">");
  }



  template <int dim>
  std::unique_ptr<ContactSolver<dim>>
  create_contact_solver(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    const std::string name = prm.get("Solver");
    prm.leave_subsection();
    return create_contact_solver<dim>(name, prm);
  }

  template void
  declare_contact_solver_parameters<2>(ParameterHandler &);
  template std::unique_ptr<ContactSolver<2>>
  create_contact_solver<2>(ParameterHandler &);
  template std::unique_ptr<ContactSolver<2>>
  create_contact_solver<2>(const std::string &, ParameterHandler &);
} // namespace Signorini
