// The element equilibration written for any simplex
// (compute_simplex_element_equilibration(), the reconstruction on
// tetrahedra):
// - on triangles ("Simplex implementation = true") it gives the estimate of
//   the triangle-specific implementation, which is written independently
//   (edge data, its own patch systems and enhancement): the paper's
//   classical densities to round-off, the enhanced densities (both converged)
//   to 1e-7, with the prolongation condition and the equilibrium of the
//   element data to round-off;
// - with the equilibrated fields on triangles, the simplex implementation's
//   JohnsonKrizekMercierElement gives the triangle implementation's
//   Johnson-Mercier estimate (enhanced densities, converged) to 1e-7;
// - on tetrahedra (576, small enough for the Debug build), a manufactured
//   solution (exact error; the default equilibrated fields and the
//   displacement element problems) and the extruded block (a reference one
//   level finer):
//   effectivity in [1, 1.15] (equilibrated, the bound of issue 35), [1, 1.1]
//   (displacement) and [1, 1.5] (block), the Prager-Synge bound
//   ||U_ref - U^|| <= e [13], the prolongation condition and the
//   equilibrium of the element data to round-off (they hold to the level of
//   the FE solution's residual: the linear solves are made tight here),
//   sum_E eps_E^2 = eps^2 [11].

#include "tests.h"

namespace
{
  using namespace SignoriniTests;

  /// The estimator's columns of every cycle of @p prm_file with overrides.
  template <int dim>
  std::map<std::string, std::vector<double>>
  estimate(const std::string                        &prm_file,
           const std::map<std::string, std::string> &overrides,
           double                                   &local_squares_ratio)
  {
    ParameterHandler prm;
    read_parameters<dim>(prm, prm_file, overrides);
    SignoriniProblem<dim> problem(prm, input_directory());
    run_quietly(problem);
    std::map<std::string, std::vector<double>> history;
    for (const auto column :
         {"cells", "eps", "e", "equilibrium_defect", "condition_defect"})
      for (const auto &v : problem.statistics().column(column))
        history[column].push_back(v.empty() ? 0. : std::stod(v));
    // against a reference (effectivity eps / eps_ex), or the exact solution
    // (e / ||u - u_h||, u_h = U^ without contact)
    const bool exact = prm_file.find("manufactured") != std::string::npos;
    for (const auto &column :
         exact ? std::vector<std::string>{"energy_error"} :
                 std::vector<std::string>{"effectivity", "prager_synge_ratio"})
      for (const auto &v : problem.statistics().column(column))
        history[column].push_back(v.empty() ? 0. : std::stod(v));
    if (exact)
      for (unsigned int k = 0; k < history["e"].size(); ++k)
        {
          history["effectivity"].push_back(history["e"][k] /
                                           history["energy_error"][k]);
          history["prager_synge_ratio"].push_back(history["energy_error"][k] /
                                                  history["e"][k]);
        }
    local_squares_ratio = problem.error_estimate().local.norm_sqr() /
                          std::pow(problem.error_estimate().eps, 2);
    return history;
  }

  /// Check that @p value lies in [@p low, @p high].
  void
  expect_within(const std::string &name,
                const double       value,
                const double       low,
                const double       high,
                unsigned int      &failures)
  {
    expect_below(name + " >= " + std::to_string(low), low, value, failures);
    expect_below(name + " <= " + std::to_string(high), value, high, failures);
  }
} // namespace



int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  unsigned int      failures = 0;
  const std::string eet      = "Error estimator/Element equilibration/";
  double            local_squares;

  // triangles: the two implementations, with displacement element
  // problems, and with the equilibrated fields (Johnson-Mercier on the
  // triangle side, JohnsonKrizekMercierElement on the simplex side)
  for (const auto &[densities, stress] :
       std::vector<std::pair<std::string, std::string>>{
         {"least squares", "displacement"},
         {"enhanced", "displacement"},
         {"enhanced", "equilibrated"}})
    {
      std::map<std::string, std::string> overrides = {
        {"Number of cycles", "2"},
        {"Error estimator/Enable", "true"},
        {eet + "Element stress", stress},
        {eet + "Traction densities", densities},
        {eet + "Enhancement iterations", "500"},
        {eet + "Enhancement tolerance", "0"}};
      const auto triangles = estimate<2>("block.prm", overrides, local_squares);
      overrides[eet + "Simplex implementation"] = "true";
      const auto simplices = estimate<2>("block.prm", overrides, local_squares);
      for (unsigned int cycle = 0; cycle < 2; ++cycle)
        {
          const double eps = simplices.at("eps")[cycle];
          deallog << densities << ", " << stress << ", "
                  << triangles.at("cells")[cycle]
                  << " triangles: eps = " << 100. * eps << " %" << std::endl;
          expect_below("  same eps as the triangle implementation",
                       std::abs(eps - triangles.at("eps")[cycle]) / eps,
                       densities == "enhanced" ? 1e-7 : 1e-10,
                       failures);
          expect_below("  prolongation condition",
                       simplices.at("condition_defect")[cycle],
                       1e-12,
                       failures);
          expect_below("  equilibrium of the element data",
                       simplices.at("equilibrium_defect")[cycle],
                       1e-10,
                       failures);
        }
    }

  // tetrahedra: the extruded block with contact, and a manufactured solution
  const auto check_3d = [&](const std::string &name,
                            const std::string &prm_file,
                            const double       highest_effectivity,
                            const std::map<std::string, std::string> &extra) {
    std::map<std::string, std::string> overrides = {
      {"Number of cycles", "2"},
      {"Error estimator/Enable", "true"},
      {"Error estimator/Stress reconstruction", "element equilibration"},
      {"Linear solver/Relative tolerance", "1e-14"}};
    for (const auto &entry : extra)
      overrides[entry.first] = entry.second;
    const auto history   = estimate<3>(prm_file, overrides, local_squares);
    const unsigned int n = history.at("eps").size();
    for (unsigned int cycle = 0; cycle < n; ++cycle)
      {
        deallog << name << ", " << history.at("cells")[cycle]
                << " tetrahedra: eps = " << 100. * history.at("eps")[cycle]
                << " %, effectivity " << history.at("effectivity")[cycle]
                << std::endl;
        expect_within("  effectivity",
                      history.at("effectivity")[cycle],
                      1.,
                      highest_effectivity,
                      failures);
        expect_below("  Prager-Synge ||U_ref - U^|| / e",
                     history.at("prager_synge_ratio")[cycle],
                     1.,
                     failures);
        expect_below("  prolongation condition",
                     history.at("condition_defect")[cycle],
                     1e-12,
                     failures);
        expect_below("  equilibrium of the element data (and of the "
                     "equilibrated fields: tractions, divergence)",
                     history.at("equilibrium_defect")[cycle],
                     1e-10,
                     failures);
      }
    expect_below("  sum_E eps_E^2 = eps^2",
                 std::abs(local_squares - 1.),
                 1e-12,
                 failures);
  };
  check_3d("3D manufactured solution, equilibrated fields",
           "../runs/manufactured_3d.prm",
           1.15,
           {{"Number of cycles", "1"},
            {"Output directory", "output-3d-manufactured"}});
  check_3d("3D manufactured solution, displacement problems",
           "../runs/manufactured_3d.prm",
           1.1,
           {{"Number of cycles", "1"},
            {eet + "Element stress", "displacement"},
            {"Output directory", "output-3d-manufactured"}});
  check_3d("3D block",
           "../runs/estimator_3d.prm",
           1.5,
           {{"Number of cycles", "1"},
            {"Reference solution/Extra refinements", "1"},
            {"Output directory", "output-3d-block"}});

  deallog << (failures == 0 ? "all checks passed" : "FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
