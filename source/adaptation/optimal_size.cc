#include <signorini/adaptation/optimal_size.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

namespace Signorini
{
  OptimalSizePredictor::OptimalSizePredictor(const unsigned int dim,
                                             const double       rate,
                                             const double       singular_rate,
                                             const double       minimum_ratio,
                                             const double       maximum_ratio)
    : dim(dim)
    , rate(rate)
    , singular_rate(singular_rate)
    , minimum_ratio(minimum_ratio)
    , maximum_ratio(maximum_ratio)
  {}



  OptimalSizePredictor::OptimalSizePredictor(const unsigned int dim)
    : OptimalSizePredictor(dim, 1., 1., 0.0625, 2.)
  {}



  void
  OptimalSizePredictor::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    prm.declare_entry("Convergence rate",
                      "1",
                      Patterns::Double(0.05, 10.),
                      "q in eps_E(h) ~ h^q: the a priori rate of the "
                      "elements (p = 1 for P1).");
    prm.declare_entry("Singular rate",
                      "1",
                      Patterns::Double(0.05, 10.),
                      "Reduced rate for the elements with a vertex at a "
                      "singular point (where the boundary id changes, or a "
                      "contact/separation point of the active set); equal to "
                      "the convergence rate: no reduction.");
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
    prm.leave_subsection();
  }



  void
  OptimalSizePredictor::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    rate          = prm.get_double("Convergence rate");
    singular_rate = prm.get_double("Singular rate");
    if (singular_rate > rate)
      throw InputError(
        "Mesh adaptation/Singular rate = " + prm.get("Singular rate") +
        " is above Convergence rate = " + prm.get("Convergence rate") +
        ": it is the reduced rate of the elements at singular "
        "points, at most the convergence rate");
    minimum_ratio = prm.get_double("Minimum size ratio");
    maximum_ratio = prm.get_double("Maximum size ratio");
    prm.leave_subsection();
  }



  bool
  OptimalSizePredictor::needs_target_error() const
  {
    return true;
  }



  SizePredictor::Prediction
  OptimalSizePredictor::predict(const Input &input,
                                const double target_error) const
  {
    Assert(target_error > 0., ExcMessage("optimal sizes need eps_0 > 0"));
    const Vector<double> &eps_E   = input.local_error;
    const unsigned int    n       = eps_E.size();
    const double          d       = dim;
    const double          log_min = std::log(minimum_ratio),
                 log_max          = std::log(maximum_ratio);

    // log r_E(lambda) = (log(d / (2 q_E eps_E^2)) - log lambda) / (2 q_E + d),
    // limited to the admissible change per step
    std::vector<double> q(n), offset(n);
    for (unsigned int c = 0; c < n; ++c)
      {
        q[c]      = input.near_singularity[c] ? singular_rate : rate;
        offset[c] = (eps_E[c] > 0.) ?
                      std::log(d / (2. * q[c] * eps_E[c] * eps_E[c])) :
                      std::numeric_limits<double>::infinity();
      }
    const auto log_ratio = [&](const unsigned int c, const double log_lambda) {
      return std::clamp((offset[c] - log_lambda) / (2. * q[c] + d),
                        log_min,
                        log_max);
    };
    const auto error_squared = [&](const double log_lambda) {
      double sum = 0.;
      for (unsigned int c = 0; c < n; ++c)
        sum +=
          eps_E[c] * eps_E[c] * std::exp(2. * q[c] * log_ratio(c, log_lambda));
      return sum;
    };

    // error_squared decreases with lambda: bisection in log(lambda); if the
    // limits make the target unreachable (or reached by any mesh) this ends
    // at the corresponding limit
    const double target_squared = target_error * target_error;
    double       lower = -2000., upper = 2000.;
    for (unsigned int iteration = 0; iteration < 200; ++iteration)
      {
        const double middle = 0.5 * (lower + upper);
        if (error_squared(middle) > target_squared)
          lower = middle;
        else
          upper = middle;
      }

    Vector<double> size_ratio(n);
    for (unsigned int c = 0; c < n; ++c)
      size_ratio[c] = std::exp(log_ratio(c, upper));
    return prediction_of(std::move(size_ratio), eps_E, q, dim);
  }



  std::vector<int>
  OptimalSizePredictor::level_changes(const Input      &input,
                                      const Prediction &prediction,
                                      const double      target_error) const
  {
    const Vector<double> &eps_E = input.local_error;
    const unsigned int    n     = eps_E.size();
    const double          d     = dim;
    // one level multiplies sizes by s = level_size_ratio, cells by s^-d and
    // eps_E^2 by s^(2 q_E); the limits per step in whole levels:
    // r_E >= minimum_ratio, r_E <= maximum_ratio
    const double s        = input.level_size_ratio;
    const double log_step = std::log(s);
    const int    most_levels =
      static_cast<int>(std::floor(std::log(minimum_ratio) / log_step + 1e-10));
    const int fewest_levels = -static_cast<int>(
      std::floor(-std::log(maximum_ratio) / log_step + 1e-10));

    std::vector<int>    k(n), coarsest(n);
    std::vector<double> q(n);
    double              error_squared      = 0.;
    const auto          cell_error_squared = [&](const unsigned int c,
                                        const int          levels) {
      return eps_E[c] * eps_E[c] * std::pow(s, 2. * q[c] * levels);
    };
    for (unsigned int c = 0; c < n; ++c)
      {
        q[c] = input.near_singularity[c] ? singular_rate : rate;
        // (no cell becomes coarser than level 0 of the hierarchy)
        coarsest[c] = input.levels == nullptr ?
                        fewest_levels :
                        std::max(fewest_levels, -int((*input.levels)[c]));
        k[c] =
          std::clamp(static_cast<int>(std::floor(
                       std::log(prediction.size_ratio[c]) / log_step + 1e-10)),
                     coarsest[c],
                     most_levels);
        error_squared += cell_error_squared(c, k[c]);
      }

    const std::vector<int> start = k;

    // (error decrease per added cell, cell) of the next halving of a cell
    const auto next_halving = [&](const unsigned int c) {
      const double decrease =
        cell_error_squared(c, k[c]) - cell_error_squared(c, k[c] + 1);
      const double added_cells =
        std::pow(s, -d * (k[c] + 1)) - std::pow(s, -d * k[c]);
      return std::make_pair(decrease / added_cells, c);
    };
    std::priority_queue<std::pair<double, unsigned int>> candidates;
    for (unsigned int c = 0; c < n; ++c)
      if (k[c] < most_levels && eps_E[c] > 0.)
        candidates.push(next_halving(c));
    const double target_squared = target_error * target_error;
    while (error_squared > target_squared && !candidates.empty())
      {
        const unsigned int c = candidates.top().second;
        candidates.pop();
        error_squared -=
          cell_error_squared(c, k[c]) - cell_error_squared(c, k[c] + 1);
        ++k[c];
        if (k[c] < most_levels)
          candidates.push(next_halving(c));
      }

    // The last levels taken may have overshot eps_0: undo those the
    // target does not need, the costliest first.
    std::vector<unsigned int> by_cost(n);
    for (unsigned int c = 0; c < n; ++c)
      by_cost[c] = c;
    std::sort(by_cost.begin(),
              by_cost.end(),
              [&](const unsigned int a, const unsigned int b) {
                return k[a] > k[b];
              });
    for (const unsigned int c : by_cost)
      if (k[c] > start[c])
        {
          const double increase =
            cell_error_squared(c, k[c] - 1) - cell_error_squared(c, k[c]);
          if (error_squared + increase <= target_squared)
            {
              error_squared += increase;
              --k[c];
            }
        }
    if (!input.realised)
      return k;

    // The closure refines beyond the request, which lowers the error the
    // model predicts: undo requested levels within the room this leaves,
    // those with the least error increase per removed cell first, where the
    // closure does not keep the level anyway, and realise again (a few
    // rounds, keeping the smallest mesh that meets eps_0).
    std::vector<int> best         = k;
    double           fewest_cells = std::numeric_limits<double>::max();
    for (unsigned int round = 0; round < 6; ++round)
      {
        const Realised          mesh     = input.realised(k);
        const std::vector<int> &realised = mesh.level_change;
        AssertDimension(realised.size(), n);
        double realised_error = 0.;
        for (unsigned int c = 0; c < n; ++c)
          realised_error += cell_error_squared(c, realised[c]);
        if (realised_error > target_squared * (1. + 1e-12))
          break;
        if (mesh.n_cells < fewest_cells)
          {
            fewest_cells = mesh.n_cells;
            best         = k;
          }
        std::vector<std::pair<double, unsigned int>> removable;
        for (unsigned int c = 0; c < n; ++c)
          if (realised[c] == k[c] && k[c] > coarsest[c])
            removable.emplace_back(
              (cell_error_squared(c, k[c] - 1) - cell_error_squared(c, k[c])) /
                (std::pow(s, -d * k[c]) - std::pow(s, -d * (k[c] - 1))),
              c);
        std::sort(removable.begin(), removable.end());
        bool undone = false;
        for (const auto &[ratio, c] : removable)
          {
            const double increase =
              cell_error_squared(c, k[c] - 1) - cell_error_squared(c, k[c]);
            if (realised_error + increase <= target_squared)
              {
                realised_error += increase;
                --k[c];
                undone = true;
              }
          }
        if (!undone)
          break;
      }
    return best;
  }



  SIGNORINI_REGISTER(SizePredictor,
                     OptimalSizePredictor,
                     1,
                     "optimal size",
                     "the optimal size map for eps_0 of the paper's section 6");
} // namespace Signorini
