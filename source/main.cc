// The signorini executable: reads a parameter file and runs the problem.
// Bad input ends with a one-line message naming the culprit and exit code 1;
// a failure of the computation with exit code 2.

#include <deal.II/base/mpi.h>

#include <signorini/input_error.h>
#include <signorini/signorini_problem.h>

#include <filesystem>
#include <iostream>
#include <string>

namespace
{
  void
  print_usage(std::ostream &out)
  {
    out << "Usage: signorini FILE.prm          run the computation\n"
           "       signorini --validate FILE.prm  check the input and exit\n"
           "       signorini --print-parameters   print the documented "
           "default parameter file\n"
           "       signorini --help\n";
  }
} // namespace



int
main(int argc, char **argv)
{
  using namespace Signorini;
  const std::vector<std::string> args(argv + 1, argv + argc);
  // serially or under mpirun (deal.II's thread pool on every rank)
  Utilities::MPI::MPI_InitFinalize mpi(argc,
                                       argv,
                                       numbers::invalid_unsigned_int);
  const bool root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  // Under MPI, every rank meets the same errors (all input is replicated);
  // rank 0 reports, and an abort keeps an error on one rank from leaving
  // the others waiting.
  const auto fail = [&](const std::string &message, const int code) {
    if (root)
      std::cerr << "signorini: error: " << message << std::endl;
    if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
      MPI_Abort(MPI_COMM_WORLD, code);
    return code;
  };
  try
    {
      ParameterHandler prm;
      SignoriniProblem<2>::declare_parameters(prm);

      if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h"))
        {
          if (root)
            print_usage(std::cout);
          return 0;
        }
      if (args.size() == 1 && args[0] == "--print-parameters")
        {
          if (root)
            prm.print_parameters(std::cout, ParameterHandler::PRM);
          return 0;
        }
      const bool validate_only = (args.size() == 2 && args[0] == "--validate");
      if (!(validate_only || (args.size() == 1 && args[0][0] != '-')))
        {
          if (root)
            print_usage(std::cerr);
          return 1;
        }
      const std::string filename = args.back();

      parse_parameter_file(prm, filename);
      SignoriniProblem<2> problem(
        prm, std::filesystem::path(filename).parent_path().string());
      if (validate_only)
        {
          problem.validate();
          if (root)
            std::cout << filename << ": valid" << std::endl;
          return 0;
        }
      problem.run();
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
