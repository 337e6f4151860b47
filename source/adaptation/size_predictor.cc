#include <signorini/adaptation/fixed_fraction.h>
#include <signorini/adaptation/optimal_size.h>
#include <signorini/adaptation/size_predictor.h>
#include <signorini/adaptation/uniform_refinement.h>
#include <signorini/input_error.h>

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



  void
  declare_size_predictor_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    {
      prm.declare_entry("Strategy",
                        "uniform",
                        Patterns::Selection(
                          "uniform|optimal size|fixed fraction"),
                        "How the next mesh follows from eps_E: halve every "
                        "element, the optimal size map of spec section 5, or "
                        "halve the elements holding a fixed share of eps^2.");
      prm.declare_entry("Target error",
                        "0",
                        Patterns::Double(0., 1.),
                        "eps_0, the relative error to reach (0.02 = 2 %); "
                        "the computations stop once eps <= eps_0 (1 + "
                        "tolerance). 0: no target, run every cycle.");
      prm.declare_entry("Tolerance",
                        "0.05",
                        Patterns::Double(0., 1.),
                        "Relative tolerance on the target error.");
      OptimalSizePredictor::declare_parameters(prm);
      FixedFractionPredictor::declare_parameters(prm);
    }
    prm.leave_subsection();
  }



  template <int dim>
  std::unique_ptr<SizePredictor>
  create_size_predictor(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    const std::string              strategy = prm.get("Strategy");
    const double                   target   = prm.get_double("Target error");
    std::unique_ptr<SizePredictor> predictor;
    if (strategy == "uniform")
      predictor = std::make_unique<UniformRefinement>(dim, target);
    else if (strategy == "fixed fraction")
      predictor = std::make_unique<FixedFractionPredictor>(dim, target, prm);
    else
      {
        if (target <= 0.)
          throw InputError("Mesh adaptation/Target error: the optimal size "
                           "strategy needs a target error > 0");
        predictor = std::make_unique<OptimalSizePredictor>(dim, target, prm);
      }
    predictor->tolerance = prm.get_double("Tolerance");
    prm.leave_subsection();
    return predictor;
  }

  template std::unique_ptr<SizePredictor>
  create_size_predictor<2>(ParameterHandler &);
} // namespace Signorini
