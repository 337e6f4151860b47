#include <deal.II/base/exceptions.h>
#include <deal.II/base/point.h>

#include <deal.II/lac/vector.h>

#include <signorini/input_error.h>

// boost's JSON parser includes boost/bind.hpp, which otherwise prints a
// deprecation note about its global placeholders
#define BOOST_BIND_GLOBAL_PLACEHOLDERS
#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>
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



  namespace
  {
    /// @p text without leading and trailing blanks.
    std::string
    trimmed(const std::string &text)
    {
      const auto begin = text.find_first_not_of(" \t\r\n\f\v");
      if (begin == std::string::npos)
        return "";
      return text.substr(begin,
                         text.find_last_not_of(" \t\r\n\f\v") + 1 - begin);
    }

    /// What parse_finite_double() accepts, for messages.
    const std::string double_range = "(magnitude 0 or 1e-308 to 1e308)";

    /// Parse the whole of @p text (blanks around allowed) as a finite double
    /// whose magnitude is 0 or at least DBL_MIN: strtod also takes nan, inf
    /// and hexadecimal floats, and an underflow to 0 or a denormal would
    /// turn a positive constant into a zero or a loss of precision.
    bool
    parse_finite_double(const std::string &text, double &value)
    {
      const std::string number = trimmed(text);
      if (number.empty() ||
          number.find_first_not_of("0123456789+-.eE") != std::string::npos)
        return false;
      errno     = 0;
      char *end = nullptr;
      value     = std::strtod(number.c_str(), &end);
      return *end == '\0' && errno == 0 && std::isfinite(value);
    }

    /// An entry of a ParameterHandler: its subsections and name.
    using EntryPath = std::vector<std::string>;

    /// Append to @p entries the entries under @p tree (the JSON description
    /// of a ParameterHandler, inside the subsections @p path) declared with
    /// Patterns::Double.
    void
    collect_double_entries(const boost::property_tree::ptree &tree,
                           const EntryPath                   &path,
                           std::vector<EntryPath>            &entries)
    {
      for (const auto &child : tree)
        {
          EntryPath name = path;
          name.push_back(child.first);
          if (!child.second.get_optional<std::string>("value"))
            collect_double_entries(child.second, name, entries);
          else if (child.second.get<std::string>("pattern_description", "")
                     .rfind("[Double", 0) == 0)
            entries.push_back(name);
        }
    }

    /// The entries of @p prm declared with Patterns::Double, found in the
    /// JSON description of the declarations (made before the user's text is
    /// read, so that its bytes cannot upset the JSON parser).
    std::vector<EntryPath>
    double_entries(const ParameterHandler &prm)
    {
      std::vector<EntryPath> entries;
      try
        {
          std::stringstream json;
          prm.print_parameters(json, ParameterHandler::JSON);
          boost::property_tree::ptree tree;
          boost::property_tree::read_json(json, tree);
          collect_double_entries(tree, {}, entries);
        }
      catch (const std::exception &)
        {
          // no list, no check: the values are read as before
        }
      return entries;
    }

    /// Throw an InputError for the first of @p entries of @p prm whose value
    /// is not a finite double: Patterns::Double accepts an underflow
    /// (1e-400, a denormal), which the program would read as 0 or stop on
    /// in get_double().
    void
    check_double_entries(ParameterHandler             &prm,
                         const std::vector<EntryPath> &entries)
    {
      for (const EntryPath &entry : entries)
        {
          std::string name;
          for (unsigned int i = 0; i + 1 < entry.size(); ++i)
            {
              prm.enter_subsection(entry[i]);
              name += entry[i] + "/";
            }
          const std::string value = prm.get(entry.back());
          for (unsigned int i = 0; i + 1 < entry.size(); ++i)
            prm.leave_subsection();
          double number = 0;
          if (!parse_finite_double(value, number))
            throw InputError(name + entry.back() + " = " + trimmed(value) +
                             " is not a finite number " + double_range);
        }
    }

    /// The entry (Subsection/.../Name, or the subsection path alone if the
    /// line sets nothing) that line @p line_number of the parameter file
    /// @p text is about: deal.II's messages give the line and the bare name.
    std::string
    entry_at_line(const std::string &text, const unsigned int line_number)
    {
      std::vector<std::string> subsections;
      std::istringstream       lines(text);
      std::string              line;
      for (unsigned int n = 1; n <= line_number && std::getline(lines, line);
           ++n)
        {
          line = trimmed(line.substr(0, line.find('#')));
          std::string path;
          for (const auto &s : subsections)
            path += s + "/";
          if (line.rfind("subsection ", 0) == 0)
            subsections.push_back(trimmed(line.substr(11)));
          else if (line == "end" && !subsections.empty())
            subsections.pop_back();
          else if (n == line_number && line.rfind("set ", 0) == 0)
            return path + trimmed(line.substr(4, line.find('=') - 4));
          if (n == line_number)
            return path.empty() ? path : path.substr(0, path.size() - 1);
        }
      return "";
    }

    /// deal.II's message @p message about the .prm file @p filename, whose
    /// contents are @p text, with "Line <N> of file <...>: " replaced by
    /// "line N: Subsection/Entry: ".
    std::string
    with_entry_name(const std::string &message,
                    const std::string &filename,
                    const std::string &text)
    {
      const std::string head = "Line <";
      const std::string tail = "> of file <" + filename + ">: ";
      const auto        end  = message.find(tail);
      if (message.rfind(head, 0) != 0 || end == std::string::npos)
        return message;
      const std::string number = message.substr(head.size(), end - head.size());
      if (number.empty() ||
          number.find_first_not_of("0123456789") != std::string::npos)
        return message;
      const std::string entry = entry_at_line(text, std::stoul(number));
      std::string       rest;
      for (const char c : message.substr(end + tail.size()))
        if (!(c == ' ' && !rest.empty() && rest.back() == ' '))
          rest += c;
      return "line " + number + ": " + (entry.empty() ? "" : entry + ": ") +
             rest;
    }
  } // namespace



  void
  parse_parameter_file(ParameterHandler &prm, const std::string &filename)
  {
    const std::string name = "parameter file <" + filename + ">";
    // A file that is missing, not a file or without content is a mistake:
    // the defaults alone describe no problem.
    std::error_code                    error;
    const std::filesystem::file_status status =
      std::filesystem::status(filename, error);
    if (!std::filesystem::exists(status))
      throw InputError(name + ": does not exist");
    if (std::filesystem::is_directory(status))
      throw InputError(name + ": is a directory");
    if (!std::filesystem::is_regular_file(status))
      throw InputError(name + ": is not a regular file");
    std::ifstream in(filename, std::ios::binary);
    std::string   text((std::istreambuf_iterator<char>(in)),
                     std::istreambuf_iterator<char>());
    if (!in.is_open() || in.bad())
      throw InputError(name + ": cannot be read");
    // a UTF-8 byte order mark (some editors write one) is not content
    if (text.compare(0, 3, "\xEF\xBB\xBF") == 0)
      text.erase(0, 3);

    const std::vector<EntryPath> doubles = double_entries(prm);

    std::string extension = std::filesystem::path(filename).extension();
    for (char &c : extension)
      c = std::tolower(static_cast<unsigned char>(c));
    bool               empty = true;
    std::istringstream lines(text);
    for (std::string line; empty && std::getline(lines, line);)
      {
        line  = trimmed(line);
        empty = line.empty() || (extension == ".prm" && line[0] == '#');
      }
    if (empty)
      throw InputError(
        name + ": is empty" +
        (text.find('#') != std::string::npos ? " (only comments)" : ""));

    try
      {
        // as ParameterHandler::parse_input(filename) does, from the text
        // read above
        std::istringstream input(text);
        if (extension == ".prm")
          prm.parse_input(input, filename, "", /*skip_undefined=*/false);
        else if (extension == ".xml")
          prm.parse_input_from_xml(input, /*skip_undefined=*/false);
        else if (extension == ".json")
          prm.parse_input_from_json(input, /*skip_undefined=*/false);
        else
          throw InputError(name + ": unknown type; a parameter file ends in "
                                  ".prm (or .xml, .json)");
      }
    catch (const InputError &)
      {
        throw;
      }
    catch (const ExceptionBase &exc)
      {
        std::ostringstream info;
        exc.print_info(info);
        throw InputError(
          name + ": " +
          with_entry_name(one_line_message(info.str()), filename, text));
      }
    catch (const std::exception &exc)
      {
        throw InputError(name + ": " + one_line_message(exc.what()));
      }

    check_double_entries(prm, doubles);
  }



  namespace
  {
    /// Check the "Function constants" of the current subsection of @p prm,
    /// a list "name=value, ...": deal.II reads each value with sscanf, so
    /// that "p=0.1x" silently becomes 0.1 and "p=abc" fails with "Double
    /// number?" naming neither the parameter nor the constant.
    void
    check_function_constants(ParameterHandler  &prm,
                             const std::string &description)
    {
      const std::string list = prm.get("Function constants");
      const std::string name =
        description + ": Function constants = " + trimmed(list) + ": ";
      if (trimmed(list).empty())
        return;
      std::vector<std::string> items;
      std::istringstream       in(list);
      for (std::string item; std::getline(in, item, ',');)
        items.push_back(trimmed(item));
      if (items.back().empty())
        items.pop_back(); // a trailing comma
      std::set<std::string> names;
      for (const std::string &item : items)
        {
          const auto equal = item.find('=');
          if (equal == std::string::npos ||
              item.find('=', equal + 1) != std::string::npos)
            throw InputError(name + "<" + item +
                             "> is not of the form name=value");
          const std::string constant = trimmed(item.substr(0, equal));
          const std::string value    = trimmed(item.substr(equal + 1));
          if (constant.empty() ||
              !(std::isalpha(static_cast<unsigned char>(constant[0])) ||
                constant[0] == '_') ||
              constant.find_first_not_of(
                "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                "0123456789_") != std::string::npos)
            throw InputError(name + "<" + constant + "> in <" + item +
                             "> is not a valid name");
          double number = 0;
          if (!parse_finite_double(value, number))
            throw InputError(name + "the value <" + value + "> of " + constant +
                             " is not a finite number " + double_range);
          if (!names.insert(constant).second)
            throw InputError(name + constant + " is defined twice");
        }
    }
  } // namespace



  template <int dim>
  std::unique_ptr<Functions::ParsedFunction<dim>>
  parse_function(ParameterHandler  &prm,
                 const unsigned int n_components,
                 const std::string &description)
  {
    check_function_constants(prm, description);
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
