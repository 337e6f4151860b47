#include <signorini/adaptation/uniform_refinement.h>

#include <cmath>

namespace Signorini
{
  UniformRefinement::UniformRefinement(const unsigned int dim)
    : dim(dim)
  {}



  bool
  UniformRefinement::uses_estimate() const
  {
    return false;
  }



  bool
  UniformRefinement::refines_uniformly() const
  {
    return true;
  }



  SizePredictor::Prediction
  UniformRefinement::predict(const Input &input,
                             const double /*target_error*/) const
  {
    const unsigned int n = input.local_error.size();
    Vector<double>     size_ratio(n);
    size_ratio = 0.5;
    // the P1 rate q = 1 for the predicted error
    return prediction_of(std::move(size_ratio),
                         input.local_error,
                         std::vector<double>(n, 1.),
                         dim);
  }



  SIGNORINI_REGISTER(SizePredictor,
                     UniformRefinement,
                     0,
                     "uniform",
                     "halve every element");
} // namespace Signorini
