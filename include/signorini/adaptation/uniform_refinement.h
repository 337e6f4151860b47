#ifndef signorini_adaptation_uniform_refinement_h
#define signorini_adaptation_uniform_refinement_h

#include <signorini/adaptation/size_predictor.h>

namespace Signorini
{
  /// Halve every element: the uniform sequence of the convergence study.
  class UniformRefinement : public SizePredictor
  {
  public:
    /// In dimension @p dim.
    explicit UniformRefinement(const unsigned int dim);

    /// r_E = 1/2 everywhere; @p target_error is not used.
    Prediction
    predict(const Input &input, const double target_error) const override;

    /// No: every element is halved.
    bool
    uses_estimate() const override;

    /// Yes.
    bool
    refines_uniformly() const override;

  private:
    /// d
    unsigned int dim;
  };
} // namespace Signorini

#endif
