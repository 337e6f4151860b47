#include <signorini/adaptation/fixed_fraction.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace Signorini
{
  FixedFractionPredictor::FixedFractionPredictor(const unsigned int dim,
                                                 const double target_error,
                                                 const double fraction)
    : dim(dim)
    , fraction(fraction)
  {
    this->target_error = target_error;
  }



  void
  FixedFractionPredictor::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Refined fraction",
                      "0.5",
                      Patterns::Double(0., 1.),
                      "Fixed fraction strategy: share of eps^2 held by the "
                      "halved elements.");
  }



  FixedFractionPredictor::FixedFractionPredictor(const unsigned int dim,
                                                 const double      target_error,
                                                 ParameterHandler &prm)
    : FixedFractionPredictor(dim,
                             target_error,
                             prm.get_double("Refined fraction"))
  {}



  std::string
  FixedFractionPredictor::name() const
  {
    return "fixed fraction";
  }



  SizePredictor::Prediction
  FixedFractionPredictor::predict(const Input &input) const
  {
    const Vector<double>     &eps_E = input.local_error;
    const unsigned int        n     = eps_E.size();
    std::vector<unsigned int> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](unsigned int a, unsigned int b) {
      return eps_E[a] > eps_E[b];
    });

    Vector<double> size_ratio(n);
    size_ratio         = 1.;
    const double total = eps_E.norm_sqr();
    double       held  = 0.;
    for (const unsigned int c : order)
      {
        if (held >= fraction * total)
          break;
        held += eps_E[c] * eps_E[c];
        size_ratio[c] = 0.5;
      }
    // the P1 rate q = 1 for the predicted error
    return prediction_of(std::move(size_ratio),
                         eps_E,
                         std::vector<double>(n, 1.),
                         dim);
  }
} // namespace Signorini
