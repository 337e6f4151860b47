#include <signorini/adaptation/uniform_refinement.h>

#include <cmath>

namespace Signorini
{
  UniformRefinement::UniformRefinement(const unsigned int dim,
                                       const double       target_error)
    : dim(dim)
  {
    this->target_error = target_error;
  }



  std::string
  UniformRefinement::name() const
  {
    return "uniform";
  }



  SizePredictor::Prediction
  UniformRefinement::predict(const Input &input) const
  {
    Prediction         prediction;
    const unsigned int n = input.local_error.size();
    prediction.size_ratio.reinit(n);
    prediction.size_ratio      = 0.5;
    prediction.predicted_cells = n * std::pow(2., dim);
    // with the P1 rate q = 1 every contribution halves
    prediction.predicted_error = 0.5 * input.local_error.l2_norm();
    return prediction;
  }
} // namespace Signorini
