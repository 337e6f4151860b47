#include <deal.II/base/mpi.h>

#include <signorini/gmsh_child_process.h>
#include <signorini/progress.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fcntl.h>
#include <fstream>
#include <iostream>
#include <optional>
#include <poll.h>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace Signorini
{
  namespace
  {
    /// The first byte the child sends: how the job ended.
    constexpr char job_done = 'D', job_failed = 'F', program_ended = 'X';

    /// The child's end of the pipe (-1 in the parent).
    int report_fd = -1;

    /// Send @p status and @p text to the parent and end the child.
    [[noreturn]] void
    report_and_exit(const char status, const std::string &text)
    {
      std::string message = status + text;
      const char *data    = message.data();
      std::size_t left    = message.size();
      while (left > 0)
        {
          const ssize_t n = ::write(report_fd, data, left);
          if (n < 0 && errno == EINTR)
            continue;
          if (n <= 0)
            break;
          data += n;
          left -= n;
        }
      ::close(report_fd);
      // not exit(): no atexit handler of the parent's (MPI) in the child
      ::_exit(0);
    }

    /// What an exception escaping Gmsh says.
    std::string
    message_of(const std::exception_ptr &exception)
    {
      try
        {
          std::rethrow_exception(exception);
        }
      catch (const std::string &message)
        {
          return message.empty() ? "Gmsh failed" : "Gmsh failed: " + message;
        }
      catch (const char *message)
        {
          return "Gmsh failed: " + std::string(message);
        }
      catch (const std::exception &exc)
        {
          return "Gmsh failed: " + std::string(exc.what());
        }
      catch (...)
        {
          return "Gmsh failed (an unknown exception)";
        }
    }

    /// An exception thrown where it cannot be caught (std::terminate()).
    [[noreturn]] void
    report_termination()
    {
      const std::exception_ptr exception = std::current_exception();
      report_and_exit(job_failed,
                      exception ? message_of(exception) :
                                  "Gmsh failed: it called std::terminate()");
    }

    /// exit() in the child: Gmsh's Exit command.
    void
    report_exit()
    {
      if (report_fd >= 0)
        report_and_exit(program_ended, "");
    }

    /// The child's side: run @p job and report.
    [[noreturn]] void
    run_child(const std::function<std::string()> &job)
    {
      // plain deaths the parent reports, not the MPI library's handlers
      for (const int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT})
        std::signal(signal, SIG_DFL);
      // Gmsh's own printing, and the runtime's on an abort, go nowhere
      const int null_fd = ::open("/dev/null", O_WRONLY);
      if (null_fd >= 0)
        {
          ::dup2(null_fd, STDOUT_FILENO);
          ::dup2(null_fd, STDERR_FILENO);
          ::close(null_fd);
        }
      std::set_terminate(report_termination);
      std::atexit(report_exit);
      std::string result;
      try
        {
          result = job();
        }
      catch (...)
        {
          report_and_exit(job_failed, message_of(std::current_exception()));
        }
      report_and_exit(job_done, result);
    }
  } // namespace



  std::string
  run_on_rank_0(const std::function<std::string()> &job)
  {
    const MPI_Comm communicator = MPI_COMM_WORLD;
    const bool     distributed  = dealii::Utilities::MPI::job_supports_mpi();
    std::string    error, result;
    if (!distributed ||
        dealii::Utilities::MPI::this_mpi_process(communicator) == 0)
      try
        {
          result = job();
        }
      catch (const std::exception &exc)
        {
          error = exc.what();
        }
    if (distributed)
      {
        error = dealii::Utilities::MPI::broadcast(communicator, error);
        if (error.empty())
          result = dealii::Utilities::MPI::broadcast(communicator, result);
      }
    if (!error.empty())
      throw std::runtime_error(error);
    return result;
  }



  GmshEndedProgram::GmshEndedProgram()
    : std::runtime_error(
        "Gmsh ended the program (an Exit command in the file?)")
  {}



  namespace
  {
    /// The CPU time (user and system, in clock ticks) that process @p pid
    /// has used, from /proc; -1 where it cannot be read.
    long long
    cpu_ticks_of(const pid_t pid)
    {
      std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
      std::string   line;
      std::getline(stat, line);
      // (the command name, field 2, is in parentheses and may hold spaces)
      const std::size_t name_end = line.rfind(')');
      if (name_end == std::string::npos)
        return -1;
      std::istringstream fields(line.substr(name_end + 1));
      std::string        skipped;
      // fields 3 (state) to 13, then utime and stime (proc(5))
      for (unsigned int field = 3; field < 14; ++field)
        fields >> skipped;
      long long user = 0, system = 0;
      if (!(fields >> user >> system))
        return -1;
      return user + system;
    }

    /// One child running @p job: its result, an exception, or nothing if
    /// the child used no CPU time for @p stall_seconds (it was killed).
    std::optional<std::string>
    run_in_one_child(const std::function<std::string()> &job,
                     const std::string                  &progress,
                     const double                        stall_seconds)
    {
      int fds[2];
      if (::pipe(fds) != 0)
        throw std::runtime_error("cannot start Gmsh: pipe(): " +
                                 std::string(std::strerror(errno)));
      // (buffered output would be written twice)
      std::cout.flush();
      std::cerr.flush();
      const pid_t pid = ::fork();
      if (pid < 0)
        {
          const int error = errno;
          ::close(fds[0]);
          ::close(fds[1]);
          throw std::runtime_error("cannot start Gmsh: fork(): " +
                                   std::string(std::strerror(error)));
        }
      if (pid == 0)
        {
          ::close(fds[0]);
          report_fd = fds[1];
          run_child(job);
        }

      ::close(fds[1]);
      // (the caller is the one rank that meshes)
      Progress    progress_lines("Gmsh", MPI_COMM_SELF);
      std::string data;
      char        buffer[1 << 16];
      using Clock          = std::chrono::steady_clock;
      auto      last_work  = Clock::now();
      auto      last_look  = last_work;
      long long last_ticks = cpu_ticks_of(pid);
      bool      stalled    = false;
      while (true)
        {
          pollfd    request = {fds[0], POLLIN, 0};
          const int ready   = ::poll(&request, 1, 1000);
          if (ready > 0)
            {
              const ssize_t n = ::read(fds[0], buffer, sizeof(buffer));
              if (n > 0)
                {
                  data.append(buffer, n);
                  last_work = Clock::now();
                }
              else if (n == 0 || (errno != EINTR && errno != EAGAIN))
                break;
            }
          else if (ready < 0 && errno != EINTR)
            break;
          const long long ticks = cpu_ticks_of(pid);
          const auto      now   = Clock::now();
          // (a parent that did not run for seconds, suspended or starved,
          // cannot tell that the child did not either)
          if (ticks != last_ticks ||
              std::chrono::duration<double>(now - last_look).count() > 5.)
            {
              last_ticks = ticks;
              last_work  = now;
            }
          last_look = now;
          if (ticks >= 0 &&
              std::chrono::duration<double>(now - last_work).count() >
                stall_seconds)
            {
              ::kill(pid, SIGKILL);
              stalled = true;
              break;
            }
          if (!progress.empty())
            progress_lines.report([&progress]() { return progress; });
        }
      ::close(fds[0]);
      int status = 0;
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
      if (stalled)
        return std::nullopt;

      if (WIFSIGNALED(status))
        {
          const int   signal = WTERMSIG(status);
          const char *name   = ::sigabbrev_np(signal);
          throw std::runtime_error(
            "Gmsh failed: it crashed (signal " + std::to_string(signal) +
            (name ? ", SIG" + std::string(name) : "") + ")");
        }
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || data.empty())
        throw std::runtime_error("Gmsh failed: its process ended without a "
                                 "result");
      if (data[0] == program_ended)
        throw GmshEndedProgram();
      if (data[0] == job_failed)
        throw std::runtime_error(data.substr(1));
      return data.substr(1);
    }
  } // namespace



  std::string
  run_in_gmsh_child(const std::function<std::string()> &job,
                    const std::string                  &progress,
                    const double                        stall_seconds)
  {
    // A child that is stuck (fork() copies the locks that the parent's other
    // threads, TBB's or MPI's, held at that instant) is killed and the job
    // runs once more in a new child: the jobs are deterministic, so the
    // second child gives what the first would have.
    for (unsigned int attempt = 0; attempt < 2; ++attempt)
      if (const auto result = run_in_one_child(job, progress, stall_seconds))
        return *result;
    std::ostringstream message;
    message << "Gmsh failed: its process used no CPU time for " << stall_seconds
            << " s, twice (stuck); it was killed";
    throw std::runtime_error(message.str());
  }
} // namespace Signorini
