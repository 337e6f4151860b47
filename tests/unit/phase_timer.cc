// PhaseTimer's memory table (Output/Print timing): a phase that touches
// 256 MiB raises the peak resident set by about that much, a later sibling
// that touches 32 MiB raises it by nothing, the phase around both by as much
// as the first, and the whole run's peak is the largest.

#include <signorini/phase_timer.h>

#include "tests.h"

#include <regex>
#include <sstream>

using namespace SignoriniTests;

namespace
{
  /// Make @p mib MiB resident, then free them.
  void
  touch(const unsigned int mib)
  {
    std::vector<char> block(mib << 20, 1);
    volatile char     sink = block[block.size() / 2];
    (void)sink;
  }
} // namespace



int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  std::ostringstream summary;
  {
    PhaseTimer timer((ConditionalOStream(summary)));
    {
      PhaseTimer::Scope outer(timer, "outer");
      {
        PhaseTimer::Scope big(timer, "big");
        touch(256);
      }
      {
        PhaseTimer::Scope small(timer, "small");
        touch(32);
      }
    }
    timer.print_summary(MPI_COMM_WORLD);
  }
  std::map<std::string, std::pair<double, double>> rows;
  const std::regex   row(R"(\| (\w[\w ]*?) +\| +([0-9.]+) \| +([0-9.]*) \|)");
  std::string        line;
  std::istringstream lines(summary.str());
  while (std::getline(lines, line))
    {
      std::smatch match;
      if (std::regex_match(line, match, row))
        rows[match[1]] = {std::stod(match[2]),
                          match[3].length() ? std::stod(match[3]) : 0.};
    }
  const auto [big_peak, big_raise]     = rows["big"];
  const auto [small_peak, small_raise] = rows["small"];
  const auto [outer_peak, outer_raise] = rows["outer"];
  deallog << "big: raised by 240 to 270 MiB: "
          << (big_raise >= 240 && big_raise <= 270) << std::endl;
  deallog << "small: raised by 0, its peak big's: "
          << (small_raise == 0 && small_peak == big_peak) << std::endl;
  deallog << "outer: raised by at least big's raise, its peak big's: "
          << (outer_raise >= big_raise && outer_peak == big_peak) << std::endl;
  deallog << "whole run: peak at least outer's: "
          << (rows["whole run"].first >= outer_peak) << std::endl;
}
