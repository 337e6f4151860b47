#ifndef signorini_adaptation_optimal_size_h
#define signorini_adaptation_optimal_size_h

#include <signorini/adaptation/size_predictor.h>

namespace Signorini
{
  /**
   * The optimal size map of [LAD 91]/[COO 94] (paper section 6, spec section
   * 5): with the a priori local behaviour eps_E(h*) = eps_E r_E^q_E, the
   * ratios r_E = h*_E / h_E minimise the element count N* = sum_E r_E^-d
   * subject to sum_E eps_E^2 r_E^(2 q_E) = eps_0^2. The Lagrange condition
   * gives
   *   r_E(lambda) = (d / (2 lambda q_E eps_E^2))^(1 / (2 q_E + d)),
   * and for a uniform rate q the closed form of spec section 5,
   *   r_E = eps_E^(-2/(2q+d)) (eps_0^2 / sum_E' eps_E'^(2d/(2q+d)))^(1/(2q)).
   * With a reduced rate near singular points, or when the limits on the
   * size change per step bind (r_E = clamp(r_E(lambda))), the constraint is
   * monotone in lambda and is solved by bisection in log(lambda).
   */
  class OptimalSizePredictor : public SizePredictor
  {
  public:
    /// Its entries of the "Mesh adaptation" section (entered by the caller).
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read from the "Mesh adaptation" section (entered by the caller).
    OptimalSizePredictor(const unsigned int dim,
                         const double       target_error,
                         ParameterHandler  &prm);

    OptimalSizePredictor(const unsigned int dim,
                         const double       target_error,
                         const double       rate,
                         const double       singular_rate,
                         const double       minimum_ratio,
                         const double       maximum_ratio);

    std::string
    name() const override;

    Prediction
    predict(const Input &input) const override;

  private:
    unsigned int dim;
    double       rate;
    double       singular_rate;
    double       minimum_ratio;
    double       maximum_ratio;
  };
} // namespace Signorini

#endif
