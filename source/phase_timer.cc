#include <deal.II/base/utilities.h>

#include <signorini/phase_timer.h>

#include <algorithm>
#include <boost/serialization/map.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <iomanip>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// The process's peak resident set so far (VmHWM, MiB).
    double
    peak_resident_mib()
    {
      Utilities::System::MemoryStats stats;
      Utilities::System::get_memory_stats(stats);
      return stats.VmHWM / 1024.;
    }
  } // namespace



  PhaseTimer::PhaseTimer(const ConditionalOStream &stream)
    : stream(stream)
    , timer(this->stream, TimerOutput::never, TimerOutput::wall_times)
  {}



  PhaseTimer::Scope::Scope(PhaseTimer &phases, const std::string &name)
    : phases(phases)
    , name(name)
  {
    phases.enter(name);
  }



  PhaseTimer::Scope::~Scope()
  {
    phases.leave(name);
  }



  void
  PhaseTimer::enter(const std::string &name)
  {
    active.emplace_back(name, peak_resident_mib());
    timer.enter_subsection(name);
  }



  void
  PhaseTimer::leave(const std::string &name)
  {
    timer.leave_subsection(name);
    const auto it =
      std::find_if(active.rbegin(), active.rend(), [&](const auto &phase) {
        return phase.first == name;
      });
    if (it == active.rend())
      return;
    const double peak          = peak_resident_mib();
    auto &[peak_at_end, raise] = memory[name];
    peak_at_end                = std::max(peak_at_end, peak);
    raise                      = std::max(raise, peak - it->second);
    active.erase(std::next(it).base());
  }



  void
  PhaseTimer::print_summary(const MPI_Comm communicator) const
  {
    timer.print_summary();
    const std::string whole_run = "whole run";
    auto              records   = memory;
    records[whole_run]          = {peak_resident_mib(), 0.};
    const auto gathered = Utilities::MPI::gather(communicator, records, 0);
    if (!stream.is_active() || gathered.empty())
      return;
    std::map<std::string, std::pair<double, double>> largest;
    for (const auto &rank_records : gathered)
      for (const auto &[name, record] : rank_records)
        {
          auto &[peak_at_end, raise] = largest[name];
          peak_at_end                = std::max(peak_at_end, record.first);
          raise                      = std::max(raise, record.second);
        }
    const std::string title = "Peak resident memory (MiB), largest rank";
    const std::string rule  = "+" + std::string(title.size() + 2, '-') +
                             "+-------------+-------------+\n";
    std::ostringstream table;
    table << rule << "| " << title << " | at its end  |  raised by  |\n"
          << rule << std::fixed << std::setprecision(1);
    const auto row = [&](const std::string &name) {
      const auto [peak_at_end, raise] = largest[name];
      table << "| " << std::left << std::setw(title.size()) << name << " | "
            << std::right << std::setw(11) << peak_at_end << " | ";
      if (name == whole_run)
        table << std::string(11, ' ') << " |\n";
      else
        table << std::setw(11) << raise << " |\n";
    };
    row(whole_run);
    for (const auto &record : largest)
      if (record.first != whole_run)
        row(record.first);
    table << rule;
    stream << '\n' << table.str() << std::endl;
  }
} // namespace Signorini
