#ifndef signorini_gmsh_child_process_h
#define signorini_gmsh_child_process_h

#include <functional>
#include <stdexcept>
#include <string>

namespace Signorini
{
  /**
   * Gmsh runs inside our process and a user's geometry can make it abort
   * (an exception thrown where it cannot be caught), crash (a segfault on
   * some option combinations) or call exit() (the Exit command). So every
   * call of Gmsh on a user's file runs in a forked child: run_in_gmsh_child()
   * returns what @p job returns in the child, passed back through a pipe,
   * and turns any way the child can end into an exception of the parent:
   * GmshEndedProgram for an exit(), std::runtime_error for everything else
   * ("Gmsh failed: <Gmsh's message>", "Gmsh failed: it crashed (signal
   * 11, SIGSEGV)").
   *
   * The child does not touch MPI (Open MPI tolerates a fork after MPI_Init
   * for such a child), writes nothing to the terminal and ends with _exit().
   * Under MPI, call it on one rank and broadcast the result.
   *
   * While the child works, the parent prints "   Gmsh: <progress> after
   * N s" as a Progress line (nothing if @p progress is empty), so that a
   * long meshing is not silent.
   *
   * A child that uses no CPU time for @p stall_seconds (and sends nothing)
   * is stuck, not slow: Gmsh computes and reads only local files, while a
   * fork() copies a lock another thread of the parent held at that instant
   * as held forever. It is killed and @p job runs once more in a new child;
   * a second stall is an error ("... used no CPU time for 60 s, twice").
   */
  std::string
  run_in_gmsh_child(const std::function<std::string()> &job,
                    const std::string                  &progress,
                    const double                        stall_seconds = 60);

  /**
   * @p job (a call of run_in_gmsh_child(), or anything else that must run
   * once) on rank 0 of MPI_COMM_WORLD, its result broadcast: every rank
   * returns the same string, or throws std::runtime_error with the message
   * of what @p job threw. Collective (also fine without MPI).
   */
  std::string
  run_on_rank_0(const std::function<std::string()> &job);

  /// The child called exit(): a .geo file's Exit command.
  class GmshEndedProgram : public std::runtime_error
  {
  public:
    GmshEndedProgram();
  };
} // namespace Signorini

#endif
