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
    /// Refined fraction in section Mesh adaptation.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read it.
    void
    parse_parameters(ParameterHandler &prm);

    /// In dimension @p dim, with the default fraction.
    explicit FixedFractionPredictor(const unsigned int dim);

    /// In dimension @p dim, halving the elements holding @p fraction of
    /// eps^2.
    FixedFractionPredictor(const unsigned int dim, const double fraction);

    /// The marking; @p target_error is not used.
    Prediction
    predict(const Input &input, const double target_error) const override;

  private:
    /// d
    unsigned int dim;
    /// Share of eps^2 held by the halved elements.
    double fraction;
  };
} // namespace Signorini

#endif
