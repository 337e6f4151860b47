#include <deal.II/base/parsed_function.h>

#include <signorini/contact/friction_law.h>
#include <signorini/input_error.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace Signorini
{
  template <int dim>
  void
  FrictionLaw<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    {
      prm.declare_entry("Friction",
                        "none",
                        Patterns::Selection("none|Tresca|Coulomb"),
                        "Friction on GC: none (frictionless), Tresca (the "
                        "tangential traction bounded by Friction threshold, "
                        "in contact or not: the classical convex problem) "
                        "or Coulomb (bounded by Friction coefficient times "
                        "the contact pressure); either condition, active set "
                        "method.");
      prm.declare_entry("Friction coefficient",
                        "0",
                        Patterns::Double(0.),
                        "Coulomb's mu >= 0.");
      prm.enter_subsection("Friction threshold");
      Functions::ParsedFunction<dim>::declare_parameters(prm, 1);
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }



  template <int dim>
  void
  FrictionLaw<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    {
      const std::string name = prm.get("Friction");
      law                    = (name == "Tresca")  ? Type::tresca :
                               (name == "Coulomb") ? Type::coulomb :
                                                     Type::none;
      mu                     = prm.get_double("Friction coefficient");
      if (!std::isfinite(mu))
        throw InputError("Contact/Friction coefficient must be finite");
      prm.enter_subsection("Friction threshold");
      threshold_function =
        parse_function<dim>(prm, 1, "Contact/Friction threshold");
      const std::string threshold = prm.get("Function expression");
      prm.leave_subsection();
      // a datum of another law is a mistake the run would not show
      if (law != Type::coulomb && mu != 0.)
        warn_once(
          "friction coefficient",
          "Contact/Friction coefficient = " + prm.get("Friction coefficient") +
            " is not used: it is Coulomb's, and Contact/Friction = " + name,
          MPI_COMM_WORLD);
      if (law != Type::tresca && threshold != "0")
        warn_once("friction threshold",
                  "Contact/Friction threshold is not used: it is Tresca's, "
                  "and Contact/Friction = " +
                    name,
                  MPI_COMM_WORLD);
    }
    prm.leave_subsection();
  }



  template <int dim>
  typename FrictionLaw<dim>::Type
  FrictionLaw<dim>::type() const
  {
    return law;
  }



  template <int dim>
  bool
  FrictionLaw<dim>::enabled() const
  {
    return law != Type::none;
  }



  template <int dim>
  std::string
  FrictionLaw<dim>::name() const
  {
    return law == Type::tresca  ? "Tresca" :
           law == Type::coulomb ? "Coulomb" :
                                  "none";
  }



  template <int dim>
  double
  FrictionLaw<dim>::coefficient() const
  {
    return mu;
  }



  template <int dim>
  const Function<dim> &
  FrictionLaw<dim>::threshold() const
  {
    return *threshold_function;
  }



  template <int dim>
  double
  FrictionLaw<dim>::threshold_at(const Point<dim> &x) const
  {
    const double s = threshold_function->value(x);
    if (!(s >= 0.) || !std::isfinite(s))
      {
        std::ostringstream text;
        text << "Contact/Friction threshold is " << s << " at (" << x
             << "): it must be finite and >= 0";
        throw InputError(text.str());
      }
    // (as a subnormal Friction coefficient is refused: no threshold is
    // that small, and the arithmetic of such numbers is slow and inexact)
    if (s > 0. && s < std::numeric_limits<double>::min())
      {
        std::ostringstream text;
        text << "Contact/Friction threshold is " << s << " at (" << x
             << "): too small for double precision (subnormal); change the "
                "units or make it 0";
        throw InputError(text.str());
      }
    return s;
  }



  template <int dim>
  void
  FrictionLaw<dim>::set_time(const double t)
  {
    threshold_function->set_time(t);
  }



  template class FrictionLaw<2>;
  template class FrictionLaw<3>;
} // namespace Signorini
