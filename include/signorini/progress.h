#ifndef signorini_progress_h
#define signorini_progress_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * Progress lines on rank 0 in the long phases that print nothing else
   * (the iterations of a contact solve, the steps of an estimate): a line
   * "   <phase>: <state> after <t> s" once the phase has run for the run's
   * interval, and then at most once per interval. Lines depend on the
   * clock: they are printed only when the run prints its timings
   * (Output/Print timing), which the regression tests, whose screen logs
   * are compared, turn off.
   */
  class Progress
  {
  public:
    /// Start the clock of @p phase (named in every line).
    Progress(const std::string &phase, const MPI_Comm communicator);

    /// Print "<phase>: @p state" if the interval has passed since the
    /// start or the last line. @p state is only built when printed.
    template <typename State>
    void
    report(const State &state);

    /// The seconds between lines for every phase of the run (0: none).
    static void
    set_interval(const double seconds);

  private:
    void
    print(const std::string &state);

    static double interval;

    const std::string phase;
    const bool        root;
    Timer             timer;
    double            next_line;
  };



  template <typename State>
  void
  Progress::report(const State &state)
  {
    if (root && interval > 0. && timer.wall_time() >= next_line)
      print(state());
  }
} // namespace Signorini

#endif
