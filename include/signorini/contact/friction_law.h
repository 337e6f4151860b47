#ifndef signorini_contact_friction_law_h
#define signorini_contact_friction_law_h

#include <deal.II/base/function.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <memory>
#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * The friction law on the contact part GC (doc/theory.md section 8):
   * none (today's frictionless Signorini problem), Tresca (the tangential
   * reaction bounded by a given threshold s, a traction) or Coulomb (bounded
   * by mu times the normal pressure). On a sliding node the tangential
   * reaction is at the bound and opposes the slip; elsewhere the node sticks.
   * The static problem starts from the unloaded state, so the tangential
   * displacement of a node in contact is its slip.
   */
  template <int dim>
  class FrictionLaw
  {
  public:
    enum class Type
    {
      none,
      tresca,
      coulomb
    };

    /// Friction, Friction coefficient and Friction threshold in section
    /// Contact.
    static void
    declare_parameters(ParameterHandler &prm);

    void
    parse_parameters(ParameterHandler &prm);

    Type
    type() const;

    /// Whether there is friction at all.
    bool
    enabled() const;

    /// The name of the law, as Contact/Friction spells it.
    std::string
    name() const;

    /// mu (Coulomb).
    double
    coefficient() const;

    /// The Tresca threshold s(x) >= 0 (a traction).
    const Function<dim> &
    threshold() const;

    /// s(@p x), or an InputError naming Contact/Friction threshold where it
    /// is negative or not finite.
    double
    threshold_at(const Point<dim> &x) const;

    /// The time of the load path at which threshold() is evaluated (its
    /// variable t; not scaled by the Load factor: it is not a load).
    void
    set_time(const double t);

  private:
    Type                           law = Type::none;
    double                         mu  = 0.;
    std::unique_ptr<Function<dim>> threshold_function;
  };
} // namespace Signorini

#endif
