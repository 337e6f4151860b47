#include <signorini/adaptation/size_predictor.h>

#include <cmath>

namespace Signorini
{
  SizePredictor::Prediction
  SizePredictor::prediction_of(Vector<double>             size_ratio,
                               const Vector<double>      &local_error,
                               const std::vector<double> &rate,
                               const unsigned int         dim)
  {
    Prediction prediction;
    double     error_squared = 0.;
    for (unsigned int c = 0; c < size_ratio.size(); ++c)
      {
        prediction.predicted_cells += std::pow(size_ratio[c], -double(dim));
        error_squared += local_error[c] * local_error[c] *
                         std::pow(size_ratio[c], 2. * rate[c]);
      }
    prediction.predicted_error = std::sqrt(error_squared);
    prediction.size_ratio      = std::move(size_ratio);
    return prediction;
  }



  std::vector<int>
  SizePredictor::level_changes(const Input      &input,
                               const Prediction &prediction,
                               const double) const
  {
    const Vector<double> &r        = prediction.size_ratio;
    const double          log_step = std::log(input.level_size_ratio);
    std::vector<int>      changes(r.size());
    for (unsigned int c = 0; c < r.size(); ++c)
      changes[c] =
        static_cast<int>(std::ceil(std::log(r[c]) / log_step - 1e-10));
    return changes;
  }



  Registry<SizePredictor, unsigned int> &
  SizePredictor::registry()
  {
    // the predictors register themselves in their own files
    static Registry<SizePredictor, unsigned int> predictors(
      "Mesh adaptation",
      "Strategy",
      "How the next mesh follows from eps_E (doc/adaptation.md)");
    return predictors;
  }



  const std::string &
  SizePredictor::name() const
  {
    return registry().name_of(*this);
  }
} // namespace Signorini
