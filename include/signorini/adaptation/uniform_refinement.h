#ifndef signorini_adaptation_uniform_refinement_h
#define signorini_adaptation_uniform_refinement_h

#include <signorini/adaptation/size_predictor.h>

namespace Signorini
{
  /// Halve every element: the uniform sequence of the convergence study.
  class UniformRefinement : public SizePredictor
  {
  public:
    UniformRefinement(const unsigned int dim, const double target_error);

    std::string
    name() const override;

    Prediction
    predict(const Input &input) const override;

    bool
    uses_estimate() const override;

  private:
    unsigned int dim;
  };
} // namespace Signorini

#endif
