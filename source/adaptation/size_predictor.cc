#include <signorini/adaptation/fixed_fraction.h>
#include <signorini/adaptation/optimal_size.h>
#include <signorini/adaptation/size_predictor.h>
#include <signorini/input_error.h>

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
      prm.declare_entry("Convergence rate",
                        "1",
                        Patterns::Double(0.05, 10.),
                        "q in eps_E(h) ~ h^q: the a priori rate of the "
                        "elements (p = 1 for P1).");
      prm.declare_entry("Singular rate",
                        "1",
                        Patterns::Double(0.05, 10.),
                        "Reduced rate for the elements with a vertex at a "
                        "singular point (a change of boundary condition or "
                        "a contact/separation point); equal to the "
                        "convergence rate: no reduction.");
      prm.declare_entry("Minimum size ratio",
                        "0.0625",
                        Patterns::Double(1e-3, 1.),
                        "Lower limit of h*_E / h_E in one step (1/16: at "
                        "most four halvings).");
      prm.declare_entry("Maximum size ratio",
                        "2",
                        Patterns::Double(1., 1e3),
                        "Upper limit of h*_E / h_E in one step (elements may "
                        "grow: each mesh is rebuilt from the initial one).");
      prm.declare_entry("Refined fraction",
                        "0.5",
                        Patterns::Double(0., 1.),
                        "Fixed fraction strategy: share of eps^2 held by the "
                        "halved elements.");
    }
    prm.leave_subsection();
  }



  std::unique_ptr<SizePredictor>
  create_size_predictor(ParameterHandler &prm)
  {
    const unsigned int dim = 2;
    prm.enter_subsection("Mesh adaptation");
    const std::string strategy = prm.get("Strategy");
    const double      target   = prm.get_double("Target error");
    const double      minimum  = prm.get_double("Minimum size ratio");
    const double      maximum  = prm.get_double("Maximum size ratio");
    std::unique_ptr<SizePredictor> predictor;
    if (strategy == "uniform")
      predictor = std::make_unique<UniformRefinement>(dim, target);
    else if (strategy == "fixed fraction")
      predictor = std::make_unique<FixedFractionPredictor>(
        dim, target, prm.get_double("Refined fraction"));
    else
      {
        if (target <= 0.)
          throw InputError("Mesh adaptation/Target error: the optimal size "
                           "strategy needs a target error > 0");
        predictor = std::make_unique<OptimalSizePredictor>(
          dim,
          target,
          prm.get_double("Convergence rate"),
          prm.get_double("Singular rate"),
          minimum,
          maximum);
      }
    predictor->tolerance = prm.get_double("Tolerance");
    prm.leave_subsection();
    return predictor;
  }
} // namespace Signorini
