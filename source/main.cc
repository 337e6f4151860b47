// The signorini executable: reads a parameter file and runs the problem.
// Bad input ends with a one-line message naming the culprit and exit code 1;
// a failure of the computation with exit code 2.

#include <deal.II/base/mpi.h>

#include <signorini/input_error.h>
#include <signorini/signorini_problem.h>

#include <chrono>
#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <iostream>
#include <string>
#include <thread>

namespace
{
  void
  print_usage(std::ostream &out)
  {
    out << "Usage: signorini FILE.prm          run the computation\n"
           "       signorini --validate FILE.prm  check the input and exit\n"
           "       signorini --print-parameters [2|3]  print the "
           "documented default parameter file of that dimension (2)\n"
           "       signorini --help\n";
  }

  /// Read the parameter file @p filename and run (or only validate) the
  /// problem in @p dim dimensions.
  template <int dim>
  void
  run(const std::string &filename, const bool validate_only)
  {
    using namespace Signorini;
    ParameterHandler prm;
    SignoriniProblem<dim>::declare_parameters(prm);
    parse_parameter_file(prm, filename);
    SignoriniProblem<dim> problem(
      prm, std::filesystem::path(filename).parent_path().string());
    if (validate_only)
      {
        problem.validate();
        if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
          std::cout << filename << ": valid" << std::endl;
        return;
      }
    problem.run();
  }

  /**
   * Started without a launcher (no mpirun, srun or Hydra in the
   * environment), Open MPI's singleton start spawns an orted daemon and
   * probes every point-to-point transport: 0.3 s, more than a small run
   * needs for all its work (bench/small_runs). One process needs neither, so
   * unless the user set them, the daemon is skipped and the transport is
   * the plain one. (Other MPI libraries ignore these variables.)
   */
  void
  prefer_fast_singleton_start()
  {
    for (const char *launched :
         {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
      if (std::getenv(launched) != nullptr)
        return;
    setenv("OMPI_MCA_ess_singleton_isolated", "1", /*overwrite=*/0);
    setenv("OMPI_MCA_pml", "ob1", /*overwrite=*/0);
    // hwloc's topology discovery in MPI_Init reads the configuration of
    // every PCI device (10 ms); a single process binds no I/O device
    setenv("HWLOC_COMPONENTS", "-pci,-linuxio", /*overwrite=*/0);
  }

  /**
   * One BLAS thread per process, unless the user chose a number. OpenBLAS
   * starts a thread per core whose waits spin (sched_yield); under MUMPS's
   * dense fronts they compete with deal.II's thread pool, with the other
   * ranks of an MPI run and with any other load of the machine: on a busy
   * 2-core machine the contact solve of a 3 591-DoF cube took 1.2 to 1.7 s
   * instead of 0.08 to 0.16 s (doc/benchmarks.md, "Small runs"). OpenBLAS
   * reads its variable when it is loaded, before main(), so its own setter
   * is called, when the BLAS in use has one. The threads it started when it
   * was loaded are then ended, while they are the only other threads: with
   * one thread OpenBLAS does not start them again, and a fork() (Gmsh runs
   * in a child) no longer has OpenBLAS wake and join them in its fork
   * handler.
   */
  void
  use_one_blas_thread()
  {
    for (const char *chosen :
         {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"})
      if (std::getenv(chosen) != nullptr)
        return;
    using SetThreads = void (*)(int);
    if (const auto set_threads = reinterpret_cast<SetThreads>(
          dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
      {
        set_threads(1);
        using EndThreads = int (*)();
        if (const auto end_threads = reinterpret_cast<EndThreads>(
              dlsym(RTLD_DEFAULT, "blas_thread_shutdown_")))
          end_threads();
      }
  }
} // namespace



int
main(int argc, char **argv)
{
  using namespace Signorini;
  const std::vector<std::string> args(argv + 1, argv + argc);
  // serially or under mpirun (deal.II's thread pool on every rank)
  prefer_fast_singleton_start();
  use_one_blas_thread();
  Utilities::MPI::MPI_InitFinalize mpi(argc,
                                       argv,
                                       numbers::invalid_unsigned_int);
  const bool root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  // Under MPI, the ranks almost always meet an error together (all input is
  // replicated, solver failures come from global reductions): rank 0
  // reports and every rank exits normally with the code, without mpirun's
  // abort banner. A rank that meets an error alone (a write failure) would
  // leave the others waiting: if they do not all arrive at the barrier
  // within a few seconds, it reports itself and aborts the job. (An own
  // communicator: the barrier cannot match a collective of a rank that is
  // still computing.)
  MPI_Comm error_comm = MPI_COMM_NULL;
  if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
    MPI_Comm_dup(MPI_COMM_WORLD, &error_comm);
  // (one write per line: unbuffered, each << is a write of its own, and
  // mpirun's abort banner could come between them)
  const auto write_error_line = [](const std::string &line) {
    std::cerr << line + '\n' << std::flush;
  };
  const auto fail = [&](const std::string &message, const int code) {
    if (root)
      write_error_line("signorini: error: " + message);
    if (error_comm == MPI_COMM_NULL)
      return code;
    MPI_Request request;
    MPI_Ibarrier(error_comm, &request);
    int        all_arrived = 0;
    const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (MPI_Test(&request, &all_arrived, MPI_STATUS_IGNORE) == MPI_SUCCESS &&
           !all_arrived && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (all_arrived)
      return code;
    if (!root) // rank 0 may not know this rank's error
      {
        write_error_line(
          "signorini: error: (rank " +
          std::to_string(Utilities::MPI::this_mpi_process(MPI_COMM_WORLD)) +
          ") " + message);
        // (time for mpirun to forward the line before its banner)
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
    MPI_Abort(MPI_COMM_WORLD, code);
    return code;
  };
  try
    {
      if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h"))
        {
          if (root)
            print_usage(std::cout);
          return 0;
        }
      // the defaults of the dimension asked for (2 if none): the function
      // variables, block subdivisions and directions differ
      if ((args.size() == 1 || args.size() == 2) &&
          args[0] == "--print-parameters")
        {
          ParameterHandler prm;
          if (args.size() == 1 || args[1] == "2")
            SignoriniProblem<2>::declare_parameters(prm);
          else if (args[1] == "3")
            SignoriniProblem<3>::declare_parameters(prm);
          else
            throw InputError("--print-parameters " + args[1] +
                             ": the dimension is 2 or 3");
          if (root)
            prm.print_parameters(std::cout, ParameterHandler::PRM);
          return 0;
        }
      const bool validate_only = (args.size() == 2 && args[0] == "--validate");
      if (!(validate_only || (args.size() == 1 && args[0][0] != '-')))
        {
          // one line, as every input error: say what is wrong first
          std::string what = "no parameter file given";
          for (const std::string &arg : args)
            if (!arg.empty() && arg[0] == '-' && arg != "--validate" &&
                arg != "--help" && arg != "-h" && arg != "--print-parameters")
              {
                what = "unknown option <" + arg + ">";
                break;
              }
          if (what == "no parameter file given" && args.size() > 1)
            what = "too many arguments (" + std::to_string(args.size()) +
                   "), one parameter file expected";
          else if (what == "no parameter file given" && !args.empty())
            what = "--validate needs a parameter file";
          throw InputError(what + "; usage: signorini [--validate] FILE.prm | "
                                  "--print-parameters | --help");
        }
      const std::string filename = args.back();

      // The dimension first (as in ASPECT and Lethe): it decides which
      // problem declares and reads the other parameters.
      ParameterHandler dimension_prm;
      declare_dimension(dimension_prm, 2);
      parse_parameter_file(dimension_prm, filename, /*skip_undefined=*/true);
      const unsigned int dimension = dimension_prm.get_integer("Dimension");
      if (dimension == 2)
        run<2>(filename, validate_only);
      else
        try
          {
            run<3>(filename, validate_only);
          }
        catch (const InputError &exc)
          {
            // (the 2D-only parts name themselves in the message; the
            // prefix says which dimension was asked for)
            throw InputError("Dimension = 3: " + std::string(exc.what()));
          }
    }
  catch (const InputError &exc)
    {
      return fail(exc.what(), 1);
    }
  catch (const ExceptionBase &exc)
    {
      std::ostringstream text;
      exc.print_info(text);
      return fail(one_line_message(text.str()), 2);
    }
  catch (const std::exception &exc)
    {
      return fail(one_line_message(exc.what()), 2);
    }
  return 0;
}
