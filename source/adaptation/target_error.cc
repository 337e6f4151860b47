#include <signorini/adaptation/target_error.h>

namespace Signorini
{
  void
  AdaptationTarget::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    prm.declare_entry("Target error",
                      "0",
                      Patterns::Double(0., 1.),
                      "eps_0, the relative error to reach (0.02 = 2 %); "
                      "the computations stop once eps <= eps_0 (1 + "
                      "tolerance). 0: no target, run every cycle.");
    prm.declare_entry("Tolerance",
                      "0.05",
                      Patterns::Double(0., 1.),
                      "Relative tolerance on the target error.");
    prm.leave_subsection();
  }



  void
  AdaptationTarget::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    target_error = prm.get_double("Target error");
    tolerance    = prm.get_double("Tolerance");
    prm.leave_subsection();
  }



  bool
  AdaptationTarget::enabled() const
  {
    return target_error > 0.;
  }



  bool
  AdaptationTarget::reached(const double eps) const
  {
    return enabled() && eps <= target_error * (1. + tolerance);
  }
} // namespace Signorini
