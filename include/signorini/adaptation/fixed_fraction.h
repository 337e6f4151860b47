#ifndef signorini_adaptation_fixed_fraction_h
#define signorini_adaptation_fixed_fraction_h

#include <signorini/adaptation/size_predictor.h>

namespace Signorini
{
  /**
   * The usual alternative to a size prediction, for comparison: halve the
   * smallest set of elements that holds the given share of eps^2 (the
   * "fixed fraction" or bulk criterion of GridRefinement), keep the others.
   */
  class FixedFractionPredictor : public SizePredictor
  {
  public:
    /// Its entries of the "Mesh adaptation" section (entered by the caller).
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read from the "Mesh adaptation" section (entered by the caller).
    FixedFractionPredictor(const unsigned int dim,
                           const double       target_error,
                           ParameterHandler  &prm);

    FixedFractionPredictor(const unsigned int dim,
                           const double       target_error,
                           const double       fraction);

    std::string
    name() const override;

    Prediction
    predict(const Input &input) const override;

  private:
    unsigned int dim;
    double       fraction;
  };
} // namespace Signorini

#endif
