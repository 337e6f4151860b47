#ifndef signorini_phase_timer_h
#define signorini_phase_timer_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The wall time and the memory of each phase of a run (`Output/Print
   * timing`): a TimerOutput for the times, and for the memory the kernel's
   * high-water mark of the process's resident set (VmHWM) when each phase
   * ends, and how far the phase raised it. The last phase that raised it
   * holds the run's peak: the one to look at to lower it. (The mark is
   * read, never reset: a reset would also hide the run's peak from
   * /usr/bin/time and the bench scripts, which read it when the process
   * ends.) Phases are entered and left on one thread.
   */
  class PhaseTimer
  {
  public:
    /// Times are written to @p stream (deal.II's TimerOutput summary).
    explicit PhaseTimer(const ConditionalOStream &stream);

    /// PhaseTimer::Scope as TimerOutput::Scope: the phase @p name
    /// until the end of the scope.
    class Scope
    {
    public:
      Scope(PhaseTimer &phases, const std::string &name);
      ~Scope();
      Scope(const Scope &) = delete;
      Scope &
      operator=(const Scope &) = delete;

    private:
      PhaseTimer       &phases;
      const std::string name;
    };

    void
    enter(const std::string &name);

    void
    leave(const std::string &name);

    /**
     * Print the times, then the peak resident memory of the whole run and,
     * per phase, the peak at its end and how far it raised it (the largest
     * of its calls): the largest over the ranks of @p communicator
     * (collective: every rank calls it).
     */
    void
    print_summary(const MPI_Comm communicator) const;

  private:
    ConditionalOStream stream;
    TimerOutput        timer;
    /// The phases entered and not left, with the peak on entry (MiB).
    std::vector<std::pair<std::string, double>> active;
    /// Per phase, the peak at its end and the largest raise of one call
    /// (MiB).
    std::map<std::string, std::pair<double, double>> memory;
  };
} // namespace Signorini

#endif
