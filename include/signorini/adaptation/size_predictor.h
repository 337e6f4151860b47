#ifndef signorini_adaptation_size_predictor_h
#define signorini_adaptation_size_predictor_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/vector.h>

#include <signorini/registry.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * What the next mesh should look like, from the local contributions of the
   * current one (paper section 6, doc/adaptation.md): the data flow mesh ->
   * solve -> estimate -> size map -> new mesh passes through this interface
   * only. The predictors form a family chosen by Mesh adaptation/Strategy
   * (registry()); when to stop adapting is not theirs to decide (see
   * AdaptationTarget).
   */
  class SizePredictor
  {
  public:
    /// A mesh a request of level changes would give.
    struct Realised
    {
      /// per cell of the current mesh, the smallest level change within its
      /// region
      std::vector<int> level_change;
      /// its number of cells
      unsigned int n_cells;
    };

    /// Local data of the current mesh, one entry per active cell.
    struct Input
    {
      /// eps_E [10], so that sum_E eps_E^2 = eps^2 [11]
      const Vector<double> &local_error;
      /// cells with a vertex at a singular point (see AdaptiveMesh)
      const std::vector<bool> &near_singularity;
      /// the level of each cell in the refinement hierarchy (AdaptiveMesh):
      /// no cell becomes coarser than level 0 (none given: no such bound)
      const std::vector<unsigned int> *levels = nullptr;
      /// h_child / h_parent of one level of the hierarchy: 1/2 for red
      /// refinement, 2^(-1/d) for bisection
      double level_size_ratio = 0.5;
      /// What the realisation makes of a request of level changes, closure
      /// included (empty: not known)
      std::function<Realised(const std::vector<int> &)> realised = {};
    };

    /// The predicted mesh.
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

    /// The predictors, chosen by Mesh adaptation/Strategy; each is
    /// constructed from the space dimension and registers itself
    /// (SIGNORINI_REGISTER()).
    static Registry<SizePredictor, unsigned int> &
    registry();

    /// The name the predictor is chosen by.
    const std::string &
    name() const;

    /**
     * The size ratios of the next mesh from @p input. @p target_error is
     * eps_0, the error the computations aim at (0: none); a predictor that
     * aims at it (needs_target_error()) is only used with eps_0 > 0.
     */
    virtual Prediction
    predict(const Input &input, const double target_error) const = 0;

    /**
     * The prediction realised in whole refinement levels: per cell of the
     * current mesh, how many levels more (or, negative, fewer) its region is
     * refined, r_E ~ s^k_E with s the level size ratio (1/2 for red
     * refinement). By default k_E = ceil(log(r_E) / log(s)), never coarser
     * than asked; a predictor with an error model may choose
     * better (OptimalSizePredictor).
     */
    virtual std::vector<int>
    level_changes(const Input      &input,
                  const Prediction &prediction,
                  const double      target_error) const;

    /// Does the prediction use eps_E (and so need the estimator)?
    virtual bool
    uses_estimate() const
    {
      return true;
    }

    /// Does the prediction aim at the target error (which must then be > 0)?
    virtual bool
    needs_target_error() const
    {
      return false;
    }

    /// Does every step halve every element, so that the size of every mesh
    /// is known from the input?
    virtual bool
    refines_uniformly() const
    {
      return false;
    }

  protected:
    /// The prediction made of @p size_ratio: N* and the error it should
    /// give with the local rates @p rate (in dimension @p dim).
    static Prediction
    prediction_of(Vector<double>             size_ratio,
                  const Vector<double>      &local_error,
                  const std::vector<double> &rate,
                  const unsigned int         dim);
  };
} // namespace Signorini

#endif
