#include <signorini/adaptation/fixed_fraction.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace Signorini
{
  FixedFractionPredictor::FixedFractionPredictor(const unsigned int dim,
                                                 const double       fraction)
    : dim(dim)
    , fraction(fraction)
  {}



  FixedFractionPredictor::FixedFractionPredictor(const unsigned int dim)
    : FixedFractionPredictor(dim, 0.5)
  {}



  void
  FixedFractionPredictor::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    prm.declare_entry("Refined fraction",
                      "0.5",
                      Patterns::Double(0., 1.),
                      "Fixed fraction strategy: share of eps^2 held by the "
                      "halved elements.");
    prm.leave_subsection();
  }



  void
  FixedFractionPredictor::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    fraction = prm.get_double("Refined fraction");
    prm.leave_subsection();
  }



  SizePredictor::Prediction
  FixedFractionPredictor::predict(const Input &input,
                                  const double /*target_error*/) const
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



  SIGNORINI_REGISTER(SizePredictor,
                     FixedFractionPredictor,
                     2,
                     "fixed fraction",
                     "halve the elements holding a fixed share of eps^2");
} // namespace Signorini
