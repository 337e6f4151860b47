#ifndef signorini_adaptation_size_predictor_h
#define signorini_adaptation_size_predictor_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/vector.h>

#include <memory>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * What the next mesh should look like, from the local contributions of the
   * current one (spec section 5): the data flow mesh -> solve -> estimate ->
   * size map -> new mesh passes through this interface only.
   */
  class SizePredictor
  {
  public:
    /// Local data of the current mesh, one entry per active cell.
    struct Input
    {
      /// eps_E [10], so that sum_E eps_E^2 = eps^2 [11]
      const Vector<double> &local_error;
      /// cells with a vertex at a singular point (see AdaptiveMesh)
      const std::vector<bool> &near_singularity;
    };

    struct Prediction
    {
      /// r_E = h*_E / h_E per active cell of the current mesh
      Vector<double> size_ratio;
      /// N* = sum_E r_E^-d: the element count of the predicted mesh
      double predicted_cells = 0.;
      /// (sum_E eps_E^2 r_E^(2 q_E))^(1/2): the error the predicted mesh
      /// should give
      double predicted_error = 0.;
    };

    virtual ~SizePredictor() = default;

    virtual std::string
    name() const = 0;

    virtual Prediction
    predict(const Input &input) const = 0;

    /// Does the prediction use eps_E (and so need the estimator)?
    virtual bool
    uses_estimate() const
    {
      return true;
    }

    /// Stop adapting once eps <= target * (1 + tolerance); 0: never.
    double target_error = 0.;
    double tolerance    = 0.05;

  protected:
    /// The prediction made of @p size_ratio: N* and the error it should
    /// give with the local rates @p rate (in dimension @p dim).
    static Prediction
    prediction_of(Vector<double>             size_ratio,
                  const Vector<double>      &local_error,
                  const std::vector<double> &rate,
                  const unsigned int         dim);
  };

  /// The "Mesh adaptation" section: strategy and target here, then the
  /// parameters each predictor declares.
  void
  declare_size_predictor_parameters(ParameterHandler &prm);

  /// The predictor the "Mesh adaptation" section asks for; throws
  /// InputError for inconsistent input.
  template <int dim>
  std::unique_ptr<SizePredictor>
  create_size_predictor(ParameterHandler &prm);
} // namespace Signorini

#endif
