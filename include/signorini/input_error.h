#ifndef signorini_input_error_h
#define signorini_input_error_h

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * An error in the user's input (parameter file, mesh file, function
   * expression). Its message is one line that names the culprit; the
   * executable prints it and exits with a non-zero code, in Debug and in
   * Release alike.
   */
  class InputError : public std::runtime_error
  {
  public:
    explicit InputError(const std::string &message);
  };

  /**
   * Read @p filename into @p prm. deal.II's own exceptions (unknown entry,
   * value not matching its pattern, missing file) are turned into an
   * InputError whose message is the one-line essence of deal.II's text.
   * With @p skip_undefined, entries @p prm does not declare are ignored (to
   * read one entry, such as Dimension, before the others are declared).
   */
  void
  parse_parameter_file(ParameterHandler  &prm,
                       const std::string &filename,
                       const bool         skip_undefined = false);

  /**
   * Parse the Functions::ParsedFunction declared in the current subsection of
   * @p prm, evaluate it once to surface syntax errors now rather than in the
   * middle of an assembly, and name @p description in the error message.
   */
  template <int dim>
  std::unique_ptr<Functions::ParsedFunction<dim>>
  parse_function(ParameterHandler  &prm,
                 const unsigned int n_components,
                 const std::string &description);

  /**
   * Throw an InputError naming @p description if @p expression calls the
   * function parser's rand() or rand_seed(): their values differ between
   * runs, threads and MPI ranks, so that no result would be reproducible.
   */
  void
  refuse_random_numbers(const std::string &expression,
                        const std::string &description);

  /**
   * Print "Warning: @p text" on rank 0 of @p communicator unless a warning of
   * this @p kind was printed before in this process: once per run, not per
   * mesh nor again for the problems of a reference solution or a nested
   * start.
   */
  void
  warn_once(const std::string &kind,
            const std::string &text,
            const MPI_Comm     communicator);

  /**
   * Collapse a multi-line deal.II exception text into its informative line(s).
   */
  std::string
  one_line_message(const std::string &text);
} // namespace Signorini

#endif
