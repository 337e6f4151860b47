#include <deal.II/base/exceptions.h>
#include <deal.II/base/point.h>

#include <deal.II/lac/vector.h>

#include <signorini/input_error.h>

#include <iostream>
#include <sstream>

namespace Signorini
{
  InputError::InputError(const std::string &message)
    : std::runtime_error(message)
  {}



  std::string
  one_line_message(const std::string &text)
  {
    // deal.II's exception texts are framed by lines of dashes and carry the
    // source location; keep the lines after "Additional information:" if
    // present, else every non-empty line, joined by blanks.
    std::istringstream       in(text);
    std::string              line;
    std::vector<std::string> lines;
    bool                     after_additional = false;
    std::vector<std::string> additional;
    while (std::getline(in, line))
      {
        const auto begin = line.find_first_not_of(" \t");
        if (begin == std::string::npos ||
            line.find("-----") != std::string::npos)
          continue;
        line = line.substr(begin);
        if (line.rfind("Additional information:", 0) == 0)
          {
            after_additional = true;
            continue;
          }
        if (line.rfind("Stacktrace:", 0) == 0)
          break;
        (after_additional ? additional : lines).push_back(line);
      }
    const auto &kept = additional.empty() ? lines : additional;
    std::string result;
    for (const auto &l : kept)
      result += (result.empty() ? "" : " ") + l;
    return result;
  }



  void
  parse_parameter_file(ParameterHandler &prm, const std::string &filename)
  {
    try
      {
        prm.parse_input(filename,
                        "",
                        /*skip_undefined=*/false,
                        /*assert_mandatory_entries_are_found=*/false);
      }
    catch (const ExceptionBase &exc)
      {
        std::ostringstream text;
        exc.print_info(text);
        throw InputError("parameter file <" + filename +
                         ">: " + one_line_message(text.str()));
      }
    catch (const std::exception &exc)
      {
        throw InputError("parameter file <" + filename +
                         ">: " + one_line_message(exc.what()));
      }
  }



  template <int dim>
  std::unique_ptr<Functions::ParsedFunction<dim>>
  parse_function(ParameterHandler  &prm,
                 const unsigned int n_components,
                 const std::string &description)
  {
    auto function =
      std::make_unique<Functions::ParsedFunction<dim>>(n_components);
    // deal.II echoes muparser's diagnostics on std::cerr before throwing;
    // keep them out of the user's terminal, the exception says the same.
    std::ostringstream    muparser_diagnostics;
    std::streambuf *const cerr_buffer =
      std::cerr.rdbuf(muparser_diagnostics.rdbuf());
    try
      {
        function->parse_parameters(prm);
        Vector<double> values(n_components);
        function->vector_value(Point<dim>(),
                               values); // forces muparser to parse
        std::cerr.rdbuf(cerr_buffer);
      }
    catch (const ExceptionBase &exc)
      {
        std::cerr.rdbuf(cerr_buffer);
        std::ostringstream text;
        exc.print_info(text);
        throw InputError(description + ": invalid function (expected " +
                         std::to_string(n_components) +
                         " component(s), "
                         "separated by ';'): " +
                         one_line_message(text.str()));
      }
    catch (const std::exception &exc)
      {
        std::cerr.rdbuf(cerr_buffer);
        throw InputError(description +
                         ": invalid function: " + one_line_message(exc.what()));
      }
    return function;
  }

  template std::unique_ptr<Functions::ParsedFunction<2>>
  parse_function<2>(ParameterHandler &,
                    const unsigned int,
                    const std::string &);
  template std::unique_ptr<Functions::ParsedFunction<3>>
  parse_function<3>(ParameterHandler &,
                    const unsigned int,
                    const std::string &);
} // namespace Signorini
