// Pure elasticity on a manufactured smooth solution
// (tests/inputs/manufactured.prm): the energy-norm error of P1 must converge
// at rate 1 in h over 5 uniformly refined meshes (least-squares slope within
// 0.1 of 1).

#include "tests.h"

int
main(int argc, char **argv)
{
  using namespace SignoriniTests;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  const Result r     = run("manufactured.prm", {});
  const auto  &cells = r.history.at("cells");
  const auto  &error = r.history.at("energy_error");
  // slope of log(error) against log(h), h ~ cells^(-1/2)
  double             sx = 0, sy = 0, sxx = 0, sxy = 0;
  const unsigned int n = cells.size();
  for (unsigned int i = 0; i < n; ++i)
    {
      const double x = -0.5 * std::log(cells[i]), y = std::log(error[i]);
      deallog << "cells " << static_cast<unsigned int>(cells[i])
              << " energy error " << std::setprecision(4) << error[i]
              << std::endl;
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
    }
  const double rate = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  deallog << "fitted rate " << std::setprecision(2) << rate << std::endl;
  unsigned int failures = 0;
  expect_below("number of meshes >= 5", 5. - n, 0., failures);
  expect_below("|rate - 1|", std::abs(rate - 1.), 0.1, failures);
  return failures == 0 ? 0 : 1;
}
