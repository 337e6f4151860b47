// run_in_gmsh_child() (include/signorini/gmsh_child_process.h) turns every
// way its child can end into a result or an exception of the parent:
// - a result, and an exception thrown by the job, pass through the pipe;
// - a crash names the signal, an exit() is GmshEndedProgram;
// - a child stuck on a lock that another thread of the parent held when it
//   forked (no CPU time used) is killed and the job runs once more: the
//   second child gives the result; a job stuck every time is an error that
//   says so, after two stall limits, not a hang.

#include <deal.II/base/mpi.h>

#include <signorini/gmsh_child_process.h>

#include "tests.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

using namespace SignoriniTests;

namespace
{
  /// What run_in_gmsh_child() returns or throws for @p job.
  std::string
  outcome(const std::function<std::string()> &job,
          const double                        stall_seconds = 60)
  {
    try
      {
        return "result '" + run_in_gmsh_child(job, "", stall_seconds) + "'";
      }
    catch (const GmshEndedProgram &exc)
      {
        return std::string("GmshEndedProgram: ") + exc.what();
      }
    catch (const std::exception &exc)
      {
        return std::string("error: ") + exc.what();
      }
  }
} // namespace



int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  deallog << "result: " << outcome([]() { return std::string("42"); })
          << std::endl;
  deallog << "throws: " << outcome([]() -> std::string {
    throw std::runtime_error("no such entity");
  }) << std::endl;
  deallog << "crashes: " << outcome([]() -> std::string {
    std::raise(SIGSEGV);
    return "";
  }) << std::endl;
  deallog << "exits: " << outcome([]() -> std::string { std::exit(3); })
          << std::endl;

  // Another thread holds a mutex while the parent forks: the first child
  // waits for it forever. The parent's thread releases it soon after, so the
  // second child finds it free.
  {
    std::mutex        lock;
    std::atomic<bool> locked{false};
    std::thread       holder([&]() {
      const std::lock_guard<std::mutex> guard(lock);
      locked = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    });
    while (!locked)
      std::this_thread::yield();
    const auto start  = std::chrono::steady_clock::now();
    const auto result = outcome(
      [&]() {
        const std::lock_guard<std::mutex> guard(lock);
        return std::string("meshed");
      },
      1.);
    holder.join();
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
    deallog << "stuck once: " << result
            << (seconds > 1. ? ", after the stall limit" : ", too early")
            << std::endl;
  }

  // A job that blocks in every child
  deallog << "stuck twice: "
          << outcome(
               []() -> std::string {
                 while (true)
                   ::pause();
               },
               1.)
          << std::endl;
}
