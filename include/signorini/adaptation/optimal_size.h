#ifndef signorini_adaptation_optimal_size_h
#define signorini_adaptation_optimal_size_h

#include <signorini/adaptation/size_predictor.h>

namespace Signorini
{
  /**
   * The optimal size map of [LAD 91]/[COO 94] (paper section 6,
   * doc/adaptation.md): with the a priori local behaviour eps_E(h*) = eps_E
   * r_E^q_E, the ratios r_E = h*_E / h_E minimise the element count N* =
   * sum_E r_E^-d subject to sum_E eps_E^2 r_E^(2 q_E) = eps_0^2. The
   * Lagrange condition gives
   *   r_E(lambda) = (d / (2 lambda q_E eps_E^2))^(1 / (2 q_E + d)),
   * and for a uniform rate q the closed form
   *   r_E = eps_E^(-2/(2q+d)) (eps_0^2 / sum_E' eps_E'^(2d/(2q+d)))^(1/(2q)).
   * With a reduced rate near singular points, or when the limits on the
   * size change per step bind (r_E = clamp(r_E(lambda))), the constraint is
   * monotone in lambda and is solved by bisection in log(lambda).
   */
  class OptimalSizePredictor : public SizePredictor
  {
  public:
    /// Convergence rate, Singular rate, Minimum/Maximum size ratio in
    /// section Mesh adaptation.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read them.
    void
    parse_parameters(ParameterHandler &prm);

    /// In dimension @p dim, with the default parameters.
    explicit OptimalSizePredictor(const unsigned int dim);

    /// In dimension @p dim with rate q (@p singular_rate near singular
    /// points) and the limits of r_E in one step.
    OptimalSizePredictor(const unsigned int dim,
                         const double       rate,
                         const double       singular_rate,
                         const double       minimum_ratio,
                         const double       maximum_ratio);

    /// The sizes for which the predicted error is @p target_error = eps_0
    /// (> 0), within the limits.
    Prediction
    predict(const Input &input, const double target_error) const override;

    /**
     * The optimal sizes in whole levels of size ratio s (1/2 for red
     * refinement), as few cells as the error model allows: rounding every
     * r_E down to a power of s meets eps_0 with up to s^-d times the cells
     * of N*. Instead start from the coarser rounding, k_E = floor(log r_E /
     * log s) within the limits per step, and add levels one at a time to the
     * cell whose error decrease per added cell, eps_E^2 s^(2 q_E k_E) (1 -
     * s^(2 q_E)) / (s^(-d (k_E + 1)) - s^(-d k_E)), is largest, until the
     * predicted error sum_E eps_E^2 s^(2 q_E k_E) reaches eps_0^2 (marginal
     * analysis: the ratio decreases with k_E, so each step takes the
     * cheapest error decrease left), then undo the levels the last steps
     * made unnecessary. The count sum_E s^(-d k_E) then lies close to N*
     * (doc/adaptation.md).
     */
    std::vector<int>
    level_changes(const Input      &input,
                  const Prediction &prediction,
                  const double      target_error) const override;

    /// Yes: eps_0 defines the optimal sizes.
    bool
    needs_target_error() const override;

  private:
    /// d
    unsigned int dim;
    /// q of the regular elements
    double rate;
    /// q of the elements near singular points
    double singular_rate;
    /// Lower limit of r_E in one step
    double minimum_ratio;
    /// Upper limit of r_E in one step
    double maximum_ratio;
  };
} // namespace Signorini

#endif
