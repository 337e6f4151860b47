#include <signorini/progress.h>

#include <cmath>
#include <iostream>

namespace Signorini
{
  double Progress::interval = 10.;



  Progress::Progress(const std::string &phase, const MPI_Comm communicator)
    : phase(phase)
    , root(!Utilities::MPI::job_supports_mpi() ||
           Utilities::MPI::this_mpi_process(communicator) == 0)
    , next_line(interval)
  {}



  void
  Progress::set_interval(const double seconds)
  {
    interval = seconds;
  }



  void
  Progress::print(const std::string &state)
  {
    std::cout << "   " << phase << ": " << state << " after "
              << std::lround(timer.wall_time()) << " s" << std::endl;
    next_line = timer.wall_time() + interval;
  }
} // namespace Signorini
