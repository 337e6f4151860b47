// The discrete contact problem solved by both solvers for both conditions on
// three configurations of the block: the paper's (no gap, vertical contact
// direction), a gap case on the right edge (horizontal direction, part of GC
// stays open), and an oblique contact direction. Checked for each: the
// complementarity conditions and global equilibrium at the solution, and the
// agreement of the active set method and Frank-Wolfe (same active set,
// energies equal to 1e-6 relative).

#include "tests.h"

int
main(int argc, char **argv)
{
  using namespace SignoriniTests;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  const std::map<std::string, std::string> mesh = {{"Mesh/Initial refinements",
                                                    "2"},
                                                   {"Number of cycles", "1"}};
  std::map<std::string, std::map<std::string, std::string>> cases = {
    {"block", mesh},
    {"gap on the right edge", gap_on_right_edge()},
    {"oblique direction",
     {{"Contact/Direction", "0.6, -0.8"},
      {"Contact/Gap/Function expression", "0.001*x"}}}};
  for (auto &[name, overrides] : cases)
    overrides.insert(mesh.begin(), mesh.end());

  unsigned int failures = 0;
  for (const auto &[name, overrides] : cases)
    for (const std::string condition : {"integral", "pointwise"})
      {
        deallog << "--- " << name << ", " << condition << " condition"
                << std::endl;
        std::map<std::string, Result> results;
        for (const std::string solver : {"active set", "Frank-Wolfe"})
          {
            auto o                 = overrides;
            o["Contact/Condition"] = condition;
            o["Contact/Solver"]    = solver;
            const Result r         = run("block.prm", o);
            deallog << solver << ": cells " << r.statistics.at("cells")
                    << ", contact nodes " << r.statistics.at("contact_nodes")
                    << ", active " << r.statistics.at("active_nodes")
                    << ", energy " << std::setprecision(8) << value(r, "energy")
                    << std::endl;
            expect_below(solver + " feasibility",
                         value(r, "feasibility"),
                         1e-9,
                         failures);
            expect_below(solver + " multiplier sign",
                         value(r, "multiplier_sign"),
                         1e-9,
                         failures);
            expect_below(solver + " complementarity",
                         value(r, "complementarity"),
                         1e-9,
                         failures);
            expect_below(solver + " residual",
                         value(r, "residual"),
                         1e-7,
                         failures);
            expect_below(solver + " resultant",
                         value(r, "resultant"),
                         1e-9,
                         failures);
            results[solver] = r;
          }
        const Result &as = results["active set"], &fw = results["Frank-Wolfe"];
        unsigned int  n_open = 0;
        for (const bool a : as.active)
          n_open += a ? 0 : 1;
        deallog << "open nodes " << n_open << " of " << as.active.size()
                << std::endl;
        expect_below("same active set",
                     as.active == fw.active ? 0. : 1.,
                     0.,
                     failures);
        expect_below("relative energy difference",
                     std::abs(value(as, "energy") - value(fw, "energy")) /
                       std::abs(value(as, "energy")),
                     1e-6,
                     failures);
        double dual_difference = 0.;
        for (unsigned int i = 0; i < as.dual.size(); ++i)
          dual_difference =
            std::max(dual_difference, std::abs(as.dual[i] - fw.dual[i]));
        expect_below("multiplier difference",
                     dual_difference / as.dual.linfty_norm(),
                     1e-6,
                     failures);
      }
  deallog << (failures == 0 ? "all checks passed" : "CHECKS FAILED")
          << std::endl;
  return failures == 0 ? 0 : 1;
}
