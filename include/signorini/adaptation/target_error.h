#ifndef signorini_adaptation_target_error_h
#define signorini_adaptation_target_error_h

#include <deal.II/base/parameter_handler.h>

namespace Signorini
{
  using namespace dealii;

  /**
   * The stop rule of the computations (paper section 6: compute, estimate,
   * predict the optimal mesh, compute again, until eps reaches the error
   * eps_0 the user asked for): entries Target error and Tolerance of
   * section Mesh adaptation. It belongs to the driver; the driver passes
   * eps_0 to the size predictor, whose optimal sizes aim at it.
   */
  struct AdaptationTarget
  {
    /// Target error and Tolerance in section Mesh adaptation.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read them.
    void
    parse_parameters(ParameterHandler &prm);

    /// Is there a target (eps_0 > 0)?
    bool
    enabled() const;

    /// Has an estimate @p eps reached the target: eps <= eps_0 (1 +
    /// tolerance)? Never without a target.
    bool
    reached(const double eps) const;

    /// eps_0, the relative error to reach; 0: none (run every cycle).
    double target_error = 0.;
    /// Relative tolerance on eps_0.
    double tolerance = 0.05;
  };
} // namespace Signorini

#endif
