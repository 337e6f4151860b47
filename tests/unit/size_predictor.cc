// The size predictors of the paper's section 6 (doc/adaptation.md), on
// synthetic local errors:
// - optimal size, uniform rate: r_E equals the closed form of
//   doc/adaptation.md
//   and the predicted error sum eps_E^2 r_E^(2q) is eps_0^2;
// - optimal size with a reduced rate on some cells: the constraint holds
//   and the Lagrange condition of the minimisation of N* = sum r_E^-d holds
//   (d r_E^(-d-1) / (2 q_E eps_E^2 r_E^(2 q_E - 1)) is the same for all E);
// - perturbing the optimal sizes along the constraint increases N*;
// - the limits on the size change are respected, and the constraint still
//   holds when the limits bind on some cells;
// - fixed fraction: the halved cells are the largest contributions and the
//   smallest such set that holds the requested share of eps^2;
// - optimal size in whole levels: the predicted error meets eps_0, the
//   levels respect the limits and level 0, the count is below that of the
//   rounding of every r_E to the finer power of two, and equals the fewest
//   cells found by enumerating every choice of levels on small cases;
// - in levels of bisection (size ratio 2^(-1/2)) the count comes closer to
//   N*, and with a closure the levels it leaves room for are undone.

#include <signorini/adaptation/fixed_fraction.h>
#include <signorini/adaptation/optimal_size.h>

#include "tests.h"

#include <algorithm>
#include <cmath>
#include <random>

using namespace SignoriniTests;

namespace
{
  Vector<double>
  synthetic_errors(const unsigned int n)
  {
    // a few cells dominate, as near a singular point
    std::mt19937                           generator(7);
    std::uniform_real_distribution<double> uniform(0., 1.);
    Vector<double>                         eps_E(n);
    for (unsigned int c = 0; c < n; ++c)
      eps_E[c] = 0.01 * std::pow(uniform(generator), 3.) + 1e-4;
    eps_E[3] = 0.08;
    eps_E[4] = 0.05;
    return eps_E;
  }

  double
  element_count(const Vector<double> &r)
  {
    double n = 0.;
    for (const double ratio : r)
      n += 1. / (ratio * ratio);
    return n;
  }
} // namespace

int
main()
{
  initlog();
  const unsigned int   d = 2, n = 200;
  const Vector<double> eps_E = synthetic_errors(n);
  const double         eps_0 = 0.02;
  const double         q     = 1.;
  std::vector<bool>    regular(n, false), singular(n, false);
  singular[3] = singular[4] = singular[10] = true;
  deallog << "eps = " << eps_E.l2_norm() << ", eps_0 = " << eps_0 << std::endl;

  // 1. uniform rate, wide limits: the closed form
  {
    const OptimalSizePredictor predictor(d, q, q, 1e-3, 1e3);
    const auto prediction = predictor.predict({eps_E, regular}, eps_0);
    double     sum        = 0.;
    for (const double e : eps_E)
      sum += std::pow(e, 2. * d / (2. * q + d));
    double deviation = 0.;
    for (unsigned int c = 0; c < n; ++c)
      {
        const double closed = std::pow(eps_E[c], -2. / (2. * q + d)) *
                              std::pow(eps_0 * eps_0 / sum, 1. / (2. * q));
        deviation =
          std::max(deviation, std::abs(prediction.size_ratio[c] / closed - 1.));
      }
    deallog << "closed form: max relative deviation of r_E "
            << (deviation < 1e-10 ? "< 1e-10" : "TOO LARGE") << std::endl;
    deallog << "predicted error / eps_0 - 1: "
            << (std::abs(prediction.predicted_error / eps_0 - 1.) < 1e-10 ?
                  "< 1e-10" :
                  "TOO LARGE")
            << std::endl;
    deallog << "N* = " << prediction.predicted_cells << " (sum r_E^-2 "
            << element_count(prediction.size_ratio) << ")" << std::endl;
  }

  // 2. reduced rate on three cells: constraint and Lagrange condition
  const double               q_singular = 0.5;
  const OptimalSizePredictor predictor(d, q, q_singular, 1e-3, 1e3);
  const auto prediction = predictor.predict({eps_E, singular}, eps_0);
  {
    double constraint = 0., lowest = 1e300, highest = 0.;
    for (unsigned int c = 0; c < n; ++c)
      {
        const double r  = prediction.size_ratio[c];
        const double qE = singular[c] ? q_singular : q;
        constraint += eps_E[c] * eps_E[c] * std::pow(r, 2. * qE);
        const double multiplier =
          d * std::pow(r, -double(d) - 1.) /
          (2. * qE * eps_E[c] * eps_E[c] * std::pow(r, 2. * qE - 1.));
        lowest  = std::min(lowest, multiplier);
        highest = std::max(highest, multiplier);
      }
    deallog << "reduced rate: sum eps_E^2 r_E^(2 q_E) / eps_0^2 - 1 "
            << (std::abs(constraint / (eps_0 * eps_0) - 1.) < 1e-10 ?
                  "< 1e-10" :
                  "TOO LARGE")
            << ", spread of the Lagrange multiplier "
            << (highest / lowest - 1. < 1e-8 ? "< 1e-8" : "TOO LARGE")
            << std::endl;
    deallog << "singular cells: r_E = " << prediction.size_ratio[3] << ", "
            << prediction.size_ratio[4] << ", " << prediction.size_ratio[10]
            << "; regular cell 5: r_E = " << prediction.size_ratio[5]
            << std::endl;
  }

  // 3. optimality: move along the constraint (shrink cell a, grow cell b
  //    so that eps_a^2 r_a^2qa + eps_b^2 r_b^2qb is unchanged): N* grows
  {
    const double base          = element_count(prediction.size_ratio);
    bool         all_increased = true;
    for (const auto &[a, b] : std::vector<std::pair<unsigned, unsigned>>{
           {3, 4}, {4, 3}, {5, 3}, {10, 20}, {20, 30}, {30, 4}})
      for (const double step : {1e-3, -1e-3})
        {
          Vector<double> r  = prediction.size_ratio;
          const double   qa = singular[a] ? q_singular : q;
          const double   qb = singular[b] ? q_singular : q;
          const double   ea = eps_E[a] * eps_E[a], eb = eps_E[b] * eps_E[b];
          const double   budget =
            ea * std::pow(r[a], 2. * qa) + eb * std::pow(r[b], 2. * qb);
          r[a] *= (1. + step);
          r[b] = std::pow((budget - ea * std::pow(r[a], 2. * qa)) / eb,
                          1. / (2. * qb));
          if (!(element_count(r) > base))
            deallog << "   " << a << ' ' << b << ' ' << step << ": "
                    << element_count(r) - base << std::endl;
          all_increased &= element_count(r) > base;
        }
    deallog << "perturbations along the constraint increase N*: "
            << (all_increased ? "yes" : "NO") << std::endl;
  }

  // 4. limits on the change per step
  {
    const double               minimum = 0.25, maximum = 1.5;
    const double               eps_1 = 0.04;
    const OptimalSizePredictor limited(d, q, q, minimum, maximum);
    const auto                 p = limited.predict({eps_E, regular}, eps_1);
    unsigned int               at_minimum = 0, at_maximum = 0;
    bool                       within = true;
    for (const double r : p.size_ratio)
      {
        within &= (r >= minimum * (1. - 1e-12) && r <= maximum * (1. + 1e-12));
        at_minimum += (r <= minimum * (1. + 1e-12)) ? 1 : 0;
        at_maximum += (r >= maximum * (1. - 1e-12)) ? 1 : 0;
      }
    deallog << "eps_0 = " << eps_1 << ", limits [" << minimum << ", " << maximum
            << "]: " << (within ? "respected" : "VIOLATED") << ", "
            << at_minimum << " cells at the minimum, " << at_maximum
            << " at the maximum, predicted error / eps_0 - 1 "
            << (std::abs(p.predicted_error / eps_1 - 1.) < 1e-10 ? "< 1e-10" :
                                                                   "TOO LARGE")
            << std::endl;
    // unreachable in one step: every cell at the minimum
    const OptimalSizePredictor tight(d, q, q, minimum, maximum);
    const auto                 t = tight.predict({eps_E, regular}, 1e-4);
    deallog << "unreachable target: all cells at the minimum "
            << (*std::max_element(t.size_ratio.begin(), t.size_ratio.end()) <=
                    minimum * (1. + 1e-12) ?
                  "yes" :
                  "NO")
            << ", predicted error " << t.predicted_error << " = eps / 4 "
            << eps_E.l2_norm() / 4. << std::endl;
  }

  // 5. fixed fraction
  {
    const double                 fraction = 0.5;
    const FixedFractionPredictor marking(d, fraction);
    const auto                   p    = marking.predict({eps_E, regular}, 0.);
    double                       held = 0., smallest_marked = 1e300;
    double                       largest_unmarked = 0.;
    unsigned int                 n_marked         = 0;
    for (unsigned int c = 0; c < n; ++c)
      if (p.size_ratio[c] < 1.)
        {
          held += eps_E[c] * eps_E[c];
          smallest_marked = std::min(smallest_marked, eps_E[c]);
          ++n_marked;
        }
      else
        largest_unmarked = std::max(largest_unmarked, eps_E[c]);
    const double total = eps_E.norm_sqr();
    deallog << "fixed fraction " << fraction << ": " << n_marked
            << " cells hold " << held / total << " of eps^2; largest first "
            << (smallest_marked >= largest_unmarked ? "yes" : "NO")
            << "; minimal "
            << (held - smallest_marked * smallest_marked < fraction * total ?
                  "yes" :
                  "NO")
            << "; N* = " << p.predicted_cells << std::endl;
  }

  // 6. optimal size in whole levels
  {
    const OptimalSizePredictor      predictor(d, q, 0.5, 1. / 16., 2.);
    const std::vector<unsigned int> levels(n, 1);
    const SizePredictor::Input      input{eps_E, regular, &levels};
    const auto                      p = predictor.predict(input, eps_0);
    const std::vector<int> k = predictor.level_changes(input, p, eps_0);
    const std::vector<int> rounded =
      predictor.SizePredictor::level_changes(input, p, eps_0);
    const auto error_squared = [&](const std::vector<int> &halvings) {
      double sum = 0.;
      for (unsigned int c = 0; c < n; ++c)
        sum += eps_E[c] * eps_E[c] * std::pow(2., -2. * q * halvings[c]);
      return sum;
    };
    const auto count = [&](const std::vector<int> &halvings) {
      double cells = 0.;
      for (const int h : halvings)
        cells += std::pow(2., double(d) * h);
      return cells;
    };
    const bool within_limits = *std::min_element(k.begin(), k.end()) >= -1 &&
                               *std::max_element(k.begin(), k.end()) <= 4;
    deallog << "whole levels: predicted error meets eps_0 "
            << (error_squared(k) <= eps_0 * eps_0 * (1. + 1e-12) ? "yes" : "NO")
            << ", within the limits " << (within_limits ? "yes" : "NO")
            << "; cells " << count(k) << ", N* = " << p.predicted_cells
            << ", rounding every r_E down " << count(rounded)
            << "; fewer than the rounding "
            << (count(k) <= count(rounded) ? "yes" : "NO") << std::endl;

    // levels of size ratio 2^(-1/2) (bisection: a level halves the area),
    // then with a synthetic closure (in a chain of cells, a level at least
    // that of each neighbour minus one): the predicted error of the realised
    // levels meets eps_0, and undoing levels in the room the closure leaves
    // saves cells
    SizePredictor::Input   bisection{eps_E, regular, &levels, std::sqrt(0.5)};
    const std::vector<int> k_bisection =
      predictor.level_changes(bisection, p, eps_0);
    const auto bisection_error = [&](const std::vector<int> &levels) {
      double sum = 0.;
      for (unsigned int c = 0; c < n; ++c)
        sum += eps_E[c] * eps_E[c] * std::pow(2., -q * levels[c]);
      return sum;
    };
    const auto bisection_count = [&](const std::vector<int> &levels) {
      double cells = 0.;
      for (const int h : levels)
        cells += std::pow(2., double(h));
      return cells;
    };
    const auto closure = [&](std::vector<int> levels) {
      for (bool changed = true; changed;)
        {
          changed = false;
          for (unsigned int c = 0; c + 1 < n; ++c)
            for (const auto [a, b] :
                 {std::make_pair(c, c + 1), std::make_pair(c + 1, c)})
              if (levels[a] < levels[b] - 1)
                {
                  levels[a] = levels[b] - 1;
                  changed   = true;
                }
        }
      return levels;
    };
    bisection.realised = [&](const std::vector<int> &levels) {
      const std::vector<int> closed = closure(levels);
      return SizePredictor::Realised{
        closed, static_cast<unsigned int>(bisection_count(closed))};
    };
    const std::vector<int> k_closed =
      predictor.level_changes(bisection, p, eps_0);
    deallog << "bisection levels: predicted error meets eps_0 "
            << (bisection_error(k_bisection) <= eps_0 * eps_0 * (1. + 1e-12) ?
                  "yes" :
                  "NO")
            << "; cells " << bisection_count(k_bisection) << " = "
            << bisection_count(k_bisection) / p.predicted_cells
            << " N*; with the closure " << bisection_count(closure(k_bisection))
            << ", with the closure "
            << "taken into account " << bisection_count(closure(k_closed))
            << " (predicted error meets eps_0 "
            << (bisection_error(closure(k_closed)) <=
                    eps_0 * eps_0 * (1. + 1e-12) ?
                  "yes" :
                  "NO")
            << ")" << std::endl;

    // small cases: every choice of levels in [-1, 4] (6^5 of them)
    std::mt19937                           generator(11);
    std::uniform_real_distribution<double> uniform(0., 1.);
    unsigned int                           n_optimal = 0, n_cases = 20;
    double                                 worst = 1.;
    for (unsigned int trial = 0; trial < n_cases; ++trial)
      {
        const unsigned int        m = 5;
        Vector<double>            small(m);
        std::vector<bool>         regular_small(m, false);
        std::vector<unsigned int> levels_small(m, 1);
        for (unsigned int c = 0; c < m; ++c)
          small[c] = 0.01 + 0.1 * std::pow(uniform(generator), 2.);
        const double target =
          small.l2_norm() * (0.05 + 0.3 * uniform(generator));
        const SizePredictor::Input small_input{small,
                                               regular_small,
                                               &levels_small};
        const auto small_prediction = predictor.predict(small_input, target);
        const std::vector<int> chosen =
          predictor.level_changes(small_input, small_prediction, target);
        const auto small_count = [&](const std::vector<int> &h) {
          double cells = 0.;
          for (const int x : h)
            cells += std::pow(2., double(d) * x);
          return cells;
        };
        const auto small_error = [&](const std::vector<int> &h) {
          double sum = 0.;
          for (unsigned int c = 0; c < m; ++c)
            sum += small[c] * small[c] * std::pow(2., -2. * q * h[c]);
          return sum;
        };
        double           fewest = 1e300;
        std::vector<int> h(m, -1);
        for (unsigned int code = 0; code < 7776; ++code)
          {
            unsigned int rest = code;
            for (unsigned int c = 0; c < m; ++c, rest /= 6)
              h[c] = int(rest % 6) - 1;
            if (small_error(h) <= target * target * (1. + 1e-12))
              fewest = std::min(fewest, small_count(h));
          }
        if (small_error(chosen) <= target * target * (1. + 1e-12) &&
            small_count(chosen) <= fewest * (1. + 1e-12))
          ++n_optimal;
        worst = std::max(worst, small_count(chosen) / fewest);
      }
    deallog << "small cases: the fewest cells in " << n_optimal << " of "
            << n_cases << ", at most " << worst << " times the fewest"
            << std::endl;
  }
}
