// The error in constitutive relation (paper sections 3 and 5, [8]-[14];
// doc/theory.md section 7) on the block, both conditions, two meshes against
// a reference two levels finer than the finest, and on the manufactured
// solution without contact, with the stress reconstructions:
// - the default (element equilibration with enhanced densities and
//   Johnson-Mercier element fields): the element fields are in exact
//   equilibrium with their data (to round-off when the body force is
//   constant per element), the classical densities the enhancement starts
//   from satisfy the prolongation condition, and the effectivity is in
//   [1, 1.3] on the block and [1, 1.15] on the manufactured solution;
// - the paper's element equilibration (least squares densities, element
//   displacement problems): equilibrium and prolongation condition to
//   round-off (its effectivity is printed; measured values in
//   doc/estimator.md); likewise the enhanced densities with displacement
//   element problems;
// - star patch: the effectivity index is in [1, 2] on every mesh, the patch
//   problems are solved with data in equilibrium and the FE equilibrium
//   R(phi_i) = 0 they rely on holds, to round-off;
// - sum_E eps_E^2 = eps^2 [11] to round-off;
// - the contact term is non-negative on every element (the number of
//   elements where it is non-zero is compared with the reference output);
// - the Prager-Synge bound ||U_ref - U^||_u <= e [13];
// - without contact, eps converges at the rate of the true error;
// - the regions of the enhancement's preconditioner take it closer to the
//   minimum than the vertex patches alone, within 2 % of it.

#include "tests.h"

namespace
{
  using namespace SignoriniTests;

  struct Estimate
  {
    typename ConstitutiveRelationError<2>::Result result;
    std::map<std::string, std::vector<double>>    history;
  };

  Estimate
  estimate(const std::string                        &prm_file,
           const std::map<std::string, std::string> &overrides)
  {
    ParameterHandler prm;
    read_parameters(prm, prm_file, overrides);
    SignoriniProblem<2> problem(prm, input_directory());
    run_quietly(problem);
    Estimate e{problem.error_estimate(), {}};
    for (const auto column : {"cells",
                              "eps",
                              "eps_ex",
                              "effectivity",
                              "prager_synge_ratio",
                              "energy_error",
                              "e"})
      for (const auto &v : problem.statistics().column(column))
        e.history[column].push_back(v.empty() ? 0. : std::stod(v));
    return e;
  }

  /// A reconstruction to test: its name in the output, its parameters and
  /// the effectivity range it must meet on the block and the manufactured
  /// solution (none: printed only).
  struct Reconstruction
  {
    std::string                        label;
    std::map<std::string, std::string> parameters;
    std::pair<double, double>          block_range;
    std::pair<double, double>          manufactured_range;
  };

  const std::vector<Reconstruction> &
  reconstructions()
  {
    static const std::string eet = "Error estimator/Element equilibration/";
    static const std::pair<double, double>   none = {0., 1e300};
    static const std::vector<Reconstruction> list = {
      {"default (enhanced densities, equilibrated element fields)",
       {},
       {1., 1.3},
       {1., 1.15}},
      {"element equilibration, least squares densities, displacement fields",
       {{"Error estimator/Stress reconstruction", "element equilibration"},
        {eet + "Traction densities", "least squares"},
        {eet + "Element stress", "displacement"}},
       none,
       none},
      {"element equilibration, enhanced densities, displacement fields",
       {{"Error estimator/Stress reconstruction", "element equilibration"},
        {eet + "Element stress", "displacement"}},
       none,
       none},
      {"star patch",
       {{"Error estimator/Stress reconstruction", "star patch"}},
       {1., 2.},
       {1., 2.}}};
    return list;
  }

  void
  expect_within(const std::pair<double, double> &range,
                const double                     theta,
                unsigned int                    &failures)
  {
    if (range.second > 1e299)
      return;
    expect_below("effectivity <= " + std::to_string(range.second).substr(0, 4),
                 theta,
                 range.second,
                 failures);
    expect_below("effectivity >= 1", range.first / theta, 1., failures);
  }

  double
  slope(const std::vector<double> &cells, const std::vector<double> &values)
  {
    double             sx = 0, sy = 0, sxx = 0, sxy = 0;
    const unsigned int n = cells.size();
    for (unsigned int i = 0; i < n; ++i)
      {
        const double x = -0.5 * std::log(cells[i]), y = std::log(values[i]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
      }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  unsigned int failures = 0;

  for (const Reconstruction &reconstruction : reconstructions())
    for (const std::string condition : {"integral", "pointwise"})
      {
        deallog << "--- block, " << condition << " condition, "
                << reconstruction.label << std::endl;
        auto overrides = reconstruction.parameters;
        overrides.insert({{"Number of cycles", "2"},
                          {"Contact/Condition", condition},
                          {"Reference solution/Extra refinements", "2"}});
        const Estimate e = estimate("block.prm", overrides);
        const auto    &r = e.result;
        for (unsigned int i = 0; i < e.history.at("cells").size(); ++i)
          deallog << "cells "
                  << static_cast<unsigned int>(e.history.at("cells")[i])
                  << ": eps " << std::setprecision(3) << e.history.at("eps")[i]
                  << ", eps_ex " << e.history.at("eps_ex")[i]
                  << ", effectivity " << e.history.at("effectivity")[i]
                  << std::endl;
        const bool star = reconstruction.label == "star patch";
        expect_below(star ? "equilibrium of the patch data" :
                            "equilibrium of the element data",
                     r.equilibrium_defect,
                     1e-10,
                     failures);
        expect_below(star ? "FE equilibrium R(phi_i) = 0" :
                            "prolongation condition",
                     r.condition_defect,
                     1e-10,
                     failures);
        for (const double theta : e.history.at("effectivity"))
          expect_within(reconstruction.block_range, theta, failures);
        double sum = 0.;
        for (const double eps_E : r.local)
          sum += eps_E * eps_E;
        expect_below("|sum eps_E^2 - eps^2| / eps^2",
                     std::abs(sum - r.eps * r.eps) / (r.eps * r.eps),
                     1e-12,
                     failures);
        double most_negative = 0.;
        for (const double c : r.contact_local)
          most_negative = std::min(most_negative, c);
        unsigned int n_contributing = 0;
        for (const double c : r.contact_local)
          n_contributing += (c != 0.) ? 1 : 0;
        deallog << "elements with a non-zero contact term: " << n_contributing
                << " (contact term " << std::setprecision(2)
                << 100. * r.eps_contact << " % of e^2)" << std::endl;
        expect_below("contact term >= 0 on every element",
                     -most_negative / std::max(r.contact_term, 1e-300),
                     1e-12,
                     failures);
        expect_below(
          "Prager-Synge ||U_ref - U^|| / e <= 1",
          *std::max_element(e.history.at("prager_synge_ratio").begin(),
                            e.history.at("prager_synge_ratio").end()),
          1.,
          failures);
      }

  for (const Reconstruction &reconstruction : reconstructions())
    {
      deallog << "--- manufactured solution, no contact, "
              << reconstruction.label << std::endl;
      auto overrides = reconstruction.parameters;
      overrides.insert({"Number of cycles", "4"});
      const Estimate m = estimate("manufactured.prm", overrides);
      for (unsigned int i = 0; i < m.history.at("cells").size(); ++i)
        deallog << "cells "
                << static_cast<unsigned int>(m.history.at("cells")[i]) << ": e "
                << std::setprecision(3) << m.history.at("e")[i]
                << ", energy error " << m.history.at("energy_error")[i]
                << ", effectivity "
                << m.history.at("e")[i] / m.history.at("energy_error")[i]
                << std::endl;
      const double rate_e = slope(m.history.at("cells"), m.history.at("e"));
      const double rate_exact =
        slope(m.history.at("cells"), m.history.at("energy_error"));
      deallog << "rates: estimate " << std::setprecision(2) << rate_e
              << ", true error " << rate_exact << std::endl;
      expect_below("|rate(e) - rate(true error)|",
                   std::abs(rate_e - rate_exact),
                   0.1,
                   failures);
      // the Johnson-Mercier fields balance the mean of the body force on
      // each element: round-off only for a body force constant per element,
      // here O(h^2)
      const bool equilibrated = reconstruction.parameters.empty();
      expect_below(equilibrated ? "equilibrium of the local data (mean body "
                                  "force, 6144 cells)" :
                                  "equilibrium of the local data",
                   m.result.equilibrium_defect,
                   equilibrated ? 1e-3 : 1e-10,
                   failures);
      for (unsigned int i = 0; i < m.history.at("cells").size(); ++i)
        expect_within(reconstruction.manufactured_range,
                      m.history.at("e")[i] / m.history.at("energy_error")[i],
                      failures);
    }
  // the regions of the enhancement's preconditioner around singular points
  // (DensityEnhancement::RegionCorrection) take it closer to the minimum of
  // J than the vertex patches alone at the same tolerance (fewer
  // iterations: doc/estimator.md), within 2 % of the eps of the patches
  // alone run to round-off; the element data stay in equilibrium
  {
    deallog << "--- block, 6144 cells, enhancement regions" << std::endl;
    const std::string eet = "Error estimator/Element equilibration/";
    const std::map<std::string, std::string> mesh = {
      {"Number of cycles", "1"}, {"Mesh/Initial refinements", "3"}};
    auto patches_only = mesh, converged = mesh;
    patches_only.insert({eet + "Enhancement regions", "0"});
    converged.insert({{eet + "Enhancement regions", "0"},
                      {eet + "Enhancement tolerance", "0"},
                      {eet + "Enhancement iterations", "1000"}});
    const Estimate regions     = estimate("block.prm", mesh);
    const double   eps_regions = regions.result.eps;
    const double   eps_patches = estimate("block.prm", patches_only).result.eps;
    const double   eps_converged = estimate("block.prm", converged).result.eps;
    deallog << "eps / converged eps - 1: with regions " << std::setprecision(2)
            << eps_regions / eps_converged - 1. << ", patches alone "
            << eps_patches / eps_converged - 1. << std::endl;
    expect_below("eps with regions / eps with patches alone",
                 eps_regions / eps_patches,
                 1.,
                 failures);
    expect_below("eps with regions / converged eps",
                 eps_regions / eps_converged,
                 1.02,
                 failures);
    expect_below("converged eps / eps with regions",
                 eps_converged / eps_regions,
                 1.,
                 failures);
    expect_below("equilibrium of the element data",
                 regions.result.equilibrium_defect,
                 1e-10,
                 failures);
  }
  return failures == 0 ? 0 : 1;
}
