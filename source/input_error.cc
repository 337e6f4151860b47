#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <deal.II/lac/vector.h>

#include <signorini/input_error.h>

// boost's JSON parser includes boost/bind.hpp, which otherwise prints a
// deprecation note about its global placeholders
#define BOOST_BIND_GLOBAL_PLACEHOLDERS
#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <regex>
#include <set>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// Throw an InputError naming @p where if @p text ends its lines with
    /// a lone carriage return (classic Mac OS): deal.II reads such a file
    /// as one line, which a leading '#' makes a comment, and the defaults
    /// would then run in silence. (CR LF is read fine.)
    void
    check_line_endings(const std::string &text, const std::string &where)
    {
      for (std::size_t i = text.find('\r'); i != std::string::npos;
           i             = text.find('\r', i + 1))
        if (i + 1 == text.size() || text[i + 1] != '\n')
          throw InputError(where +
                           ": has lines ended by a lone carriage return (CR, "
                                       "classic Mac OS line endings); convert them to LF");
    }



    /// @p message on one line, each <quoted> text longer than 200 characters
    /// cut with "...", the whole at most 2000 characters: a name or value of
    /// a megabyte must not become an error line of megabytes.
    std::string
    capped(const std::string &message)
    {
      constexpr std::size_t max_quoted = 200, max_total = 2000;
      // the end of a cut, moved back out of a UTF-8 sequence
      const auto cut = [](const std::string &text, std::size_t end) {
        while (end > 0 &&
               (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80)
          --end;
        return text.substr(0, end) + "...";
      };
      std::string result;
      std::size_t position = 0;
      while (position < message.size())
        {
          const auto open  = message.find('<', position);
          const auto close = open == std::string::npos ?
                               std::string::npos :
                               message.find('>', open + 1);
          if (close == std::string::npos)
            {
              result += message.substr(position);
              break;
            }
          const std::string quoted = message.substr(open + 1, close - open - 1);
          result +=
            message.substr(position, open + 1 - position) +
            (quoted.size() > max_quoted ? cut(quoted, max_quoted) : quoted) +
            ">";
          position = close + 1;
        }
      for (char &c : result)
        if (c == '\n' || c == '\r')
          c = ' ';
      return result.size() > max_total ? cut(result, max_total) : result;
    }
  } // namespace



  InputError::InputError(const std::string &message)
    : std::runtime_error(capped(message))
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

    /// Longest quoted text kept in a message: a 1 MB name must not become a
    /// 2 MB error line.
    constexpr std::size_t max_quoted_length = 200;

    /// @p text, cut after max_quoted_length characters (not inside a UTF-8
    /// sequence) and marked with "...".
    std::string
    shortened(const std::string &text)
    {
      if (text.size() <= max_quoted_length)
        return text;
      std::size_t end = max_quoted_length;
      while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80)
        --end;
      return text.substr(0, end) + "...";
    }

    /// What parse_finite_double() accepts, for messages.
    const std::string double_range = "(magnitude 0 or 1e-308 to 1e308)";

    /// Why parse_finite_double() refuses the number @p text (out of range
    /// or not finite), for messages.
    std::string
    out_of_range_reason(const std::string &text)
    {
      errno             = 0;
      const double read = std::strtod(trimmed(text).c_str(), nullptr);
      if (std::isfinite(read) && errno == ERANGE &&
          std::abs(read) < std::numeric_limits<double>::min())
        return " is too small for double precision (subnormal or "
               "underflowing to 0): give 0 or a magnitude from 1e-308 to "
               "1e308";
      return " is not a finite number " + double_range;
    }

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

    /// The JSON description of the declarations of @p prm (made before the
    /// user's text is read, so that its bytes cannot upset the JSON parser),
    /// or an empty tree.
    boost::property_tree::ptree
    declarations(const ParameterHandler &prm)
    {
      boost::property_tree::ptree tree;
      try
        {
          std::stringstream json;
          prm.print_parameters(json, ParameterHandler::JSON);
          boost::property_tree::read_json(json, tree);
        }
      catch (const std::exception &)
        {
          // no description: no checks of the values by it
          tree.clear();
        }
      return tree;
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
            throw InputError(name + entry.back() + " = " +
                             shortened(trimmed(value)) +
                             out_of_range_reason(value));
        }
    }

    /// The line numbers and texts of the logical lines of the .prm text
    /// @p text, joined and cut as deal.II's ParameterHandler does: a line
    /// ending in a backslash continues on the next one, '#' starts a
    /// comment, tabs are blanks.
    std::vector<std::pair<unsigned int, std::string>>
    prm_lines(const std::string &text)
    {
      std::vector<std::pair<unsigned int, std::string>> result;
      std::istringstream                                in(text);
      std::string                                       line, joined;
      unsigned int                                      n = 0, first = 0;
      while (std::getline(in, line))
        {
          ++n;
          line = trimmed(line);
          if (joined.empty())
            first = n;
          if (!line.empty() && line.back() == '\\')
            {
              joined += line.substr(0, line.size() - 1);
              continue;
            }
          joined += line;
          joined = joined.substr(0, joined.find('#'));
          for (char &c : joined)
            if (c == '\t')
              c = ' ';
          result.emplace_back(first, trimmed(joined));
          joined.clear();
        }
      return result;
    }

    /// The entry (Subsection/.../Name, or the subsection path alone if the
    /// line sets nothing) that line @p line_number of the parameter file
    /// @p text is about: deal.II 9.4's messages give the line and the bare
    /// name, and it keeps the subsection path to itself.
    std::string
    entry_at_line(const std::string &text, const unsigned int line_number)
    {
      std::vector<std::string> subsections;
      for (const auto &[first_line, line] : prm_lines(text))
        {
          if (first_line > line_number)
            break;
          std::string path;
          for (const auto &s : subsections)
            path += s + "/";
          const bool here = first_line == line_number;
          if (line.rfind("subsection ", 0) == 0)
            subsections.push_back(trimmed(line.substr(11)));
          else if (line == "end" && !subsections.empty())
            subsections.pop_back();
          else if (here && line.rfind("set ", 0) == 0)
            return path + trimmed(line.substr(4, line.find('=') - 4));
          if (here)
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
      std::string       tail = "> of file <" + filename + ">: ";
      auto              end  = message.find(tail);
      if (end == std::string::npos)
        {
          // deal.II 9.4's "no such subsection" message lacks the '>'
          tail = "> of file <" + filename + ": ";
          end  = message.find(tail);
        }
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
      return "line " + number + ": " +
             (entry.empty() ? "" : shortened(entry) + ": ") + rest;
    }

    /// The name of a .json or .xml entry as deal.II writes it mangled
    /// ("Friction_20coefficient"), in clear; a clear name is left as it is.
    std::string
    demangled(const std::string &name)
    {
      std::string clear;
      for (std::size_t i = 0; i < name.size(); ++i)
        if (name[i] == '_' && i + 2 < name.size() &&
            std::isxdigit(static_cast<unsigned char>(name[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(name[i + 2])))
          {
            clear +=
              static_cast<char>(std::stoi(name.substr(i + 1, 2), nullptr, 16));
            i += 2;
          }
        else
          clear += name[i];
      return clear;
    }

    /// The path ("Contact/Friction coefficient") of the first entry under
    /// @p tree (read from a .json or .xml parameter file, inside the
    /// subsections @p path) whose value the pattern of its declaration in
    /// @p declared (the JSON description of the declarations) refuses, or
    /// "".
    std::string
    refused_entry(const boost::property_tree::ptree &declared,
                  const boost::property_tree::ptree &tree,
                  const std::string                 &path)
    {
      for (const auto &child : tree)
        {
          const auto declaration = declared.find(demangled(child.first));
          if (declaration == declared.not_found())
            continue;
          const std::string name =
            (path.empty() ? "" : path + "/") + declaration->first;
          const auto value   = child.second.get_optional<std::string>("value");
          const auto pattern = declaration->second.get_optional<std::string>(
            "pattern_description");
          if (!value && !child.second.empty())
            {
              const std::string found =
                refused_entry(declaration->second, child.second, name);
              if (!found.empty())
                return found;
            }
          else if (pattern)
            {
              const std::unique_ptr<Patterns::PatternBase> check =
                Patterns::pattern_factory(*pattern);
              if (check && !check->match(value ? *value : child.second.data()))
                return name;
            }
        }
      return "";
    }

    /// The path of the first entry or subsection under @p tree (read from
    /// a .json or .xml parameter file, inside the subsections @p path) that
    /// @p declared (the JSON description of the declarations) lacks, as the
    /// file writes it, or "".
    std::string
    undeclared_entry(const boost::property_tree::ptree &declared,
                     const boost::property_tree::ptree &tree,
                     const std::string                 &path)
    {
      for (const auto &child : tree)
        {
          if (child.first == "<xmlattr>" || child.first == "<xmlcomment>")
            continue;
          const std::string name =
            (path.empty() ? "" : path + "/") + child.first;
          const auto declaration = declared.find(demangled(child.first));
          if (declaration == declared.not_found())
            return name;
          if (!child.second.get_optional<std::string>("value") &&
              !child.second.empty())
            {
              const std::string found =
                undeclared_entry(declaration->second, child.second, name);
              if (!found.empty())
                return found;
            }
        }
      return "";
    }

    /// The path of the first name under @p tree (read from a .xml
    /// parameter file, inside the subsections @p path) that deal.II cannot
    /// demangle (an underscore not followed by two hexadecimal digits: its
    /// demangling reads other bytes, or fails an assertion), or "".
    std::string
    undemanglable_name(const boost::property_tree::ptree &tree,
                       const std::string                 &path)
    {
      for (const auto &child : tree)
        {
          if (child.first == "<xmlattr>" || child.first == "<xmlcomment>")
            continue;
          const std::string &key  = child.first;
          const std::string  name = (path.empty() ? "" : path + "/") + key;
          for (std::size_t i = key.find('_'); i != std::string::npos;
               i             = key.find('_', i + 1))
            if (i + 2 >= key.size() ||
                !std::isxdigit(static_cast<unsigned char>(key[i + 1])) ||
                !std::isxdigit(static_cast<unsigned char>(key[i + 2])))
              return name;
            else
              i += 2;
          // (the children of an entry are deal.II's own: value,
          // default_value, documentation, pattern, pattern_description)
          if (child.second.get_optional<std::string>("value"))
            continue;
          const std::string found = undemanglable_name(child.second, name);
          if (!found.empty())
            return found;
        }
      return "";
    }

    /// @p message (deal.II's "The string <v> does not match the given
    /// pattern", which names no entry) with the path of the refused entry
    /// of the .json or .xml parameter file @p text in front, or for an
    /// undeclared entry the path of the first name that is not declared;
    /// @p declared is the JSON description of the declarations.
    std::string
    with_json_or_xml_entry_name(const std::string                 &message,
                                const std::string                 &text,
                                const std::string                 &extension,
                                const boost::property_tree::ptree &declared)
    {
      const bool refused_value =
        message.find("does not match the given pattern") != std::string::npos;
      const bool undeclared =
        message.find("not yet declared") != std::string::npos ||
        message.find("was declared") != std::string::npos ||
        message.find("no such subsection") != std::string::npos;
      if (!refused_value && !undeclared)
        return message;
      try
        {
          boost::property_tree::ptree tree;
          std::istringstream          input(text);
          if (extension == ".json")
            boost::property_tree::read_json(input, tree);
          else
            {
              boost::property_tree::read_xml(input, tree);
              tree = tree.get_child("ParameterHandler");
            }
          if (refused_value)
            {
              const std::string entry = refused_entry(declared, tree, "");
              if (!entry.empty())
                return shortened(entry) + ": " + message;
            }
          else
            {
              // (deal.II names the entry it looked for, demangled into
              // other bytes from names like Number_of_cycles, or an entry
              // inside a misspelt subsection)
              const std::string entry = undeclared_entry(declared, tree, "");
              if (!entry.empty())
                return shortened(entry) +
                       ": no such entry or subsection is declared (names as "
                       "in the .prm files, e.g. \"Number of cycles\", or "
                       "mangled as deal.II writes them, Number_20of_20cycles)";
            }
        }
      catch (const std::exception &)
        {
          // the message as deal.II gave it
        }
      return message;
    }

    /// Deepest nesting of included parameter files accepted.
    constexpr unsigned int max_include_depth = 10;

    /// Follow the `include` lines of the .prm text @p text (of the file
    /// @p chain.back()) before deal.II does: deal.II recurses without a
    /// limit, so that a file including itself overflows the stack. Throw an
    /// InputError for a cycle, a nesting deeper than max_include_depth and
    /// an included file that cannot be read, naming the chain of includes.
    void
    check_includes(const std::string                  &text,
                   std::vector<std::string>           &chain,
                   std::vector<std::filesystem::path> &canonical_chain,
                   std::vector<unsigned int>          &line_chain)
    {
      for (const auto &[line_number, line] : prm_lines(text))
        {
          if (line.rfind("include ", 0) != 0 && line.rfind("INCLUDE ", 0) != 0)
            continue;
          const std::string target = trimmed(line.substr(8));
          if (target.empty())
            continue; // deal.II's own message names the line
          line_chain.push_back(line_number);
          // "<a.prm> line 3 -> <b.prm> line 1 -> <target>"
          std::string path_text;
          for (unsigned int i = 0; i < chain.size(); ++i)
            path_text += "<" + shortened(chain[i]) + "> line " +
                         std::to_string(line_chain[i]) + " -> ";
          path_text += "<" + shortened(target) + ">";
          const std::string where = "include " + path_text;
          const bool relative     = std::filesystem::path(target).is_relative();
          const std::string relative_note =
            relative ? " (relative to the working directory)" : "";

          std::error_code                    error;
          const std::filesystem::file_status status =
            std::filesystem::status(target, error);
          if (!std::filesystem::exists(status))
            throw InputError(where + ": the included file" + relative_note +
                             " does not exist");
          if (!std::filesystem::is_regular_file(status))
            throw InputError(where + ": the included file" + relative_note +
                             " is not a regular file");
          const std::filesystem::path canonical =
            std::filesystem::canonical(target, error);
          for (const auto &previous : canonical_chain)
            if (!error && previous == canonical)
              throw InputError(where + ": the files include each other in a "
                                       "cycle");
          if (chain.size() > max_include_depth)
            throw InputError(where + ": includes nested deeper than " +
                             std::to_string(max_include_depth));
          std::ifstream     in(target, std::ios::binary);
          const std::string included((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
          if (!in.is_open() || in.bad())
            throw InputError(where + ": the included file cannot be read");
          if (included.find('\0') != std::string::npos)
            throw InputError(where + ": the included file contains a NUL "
                                     "byte (binary file?)");
          check_line_endings(included, where + ": the included file");

          chain.push_back(target);
          canonical_chain.push_back(canonical);
          check_includes(included, chain, canonical_chain, line_chain);
          chain.pop_back();
          canonical_chain.pop_back();
          line_chain.pop_back();
        }
    }
  } // namespace



  void
  parse_parameter_file(ParameterHandler  &prm,
                       const std::string &filename,
                       const bool         skip_undefined)
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
    // deal.II's messages would stop at the NUL, and no parameter has one
    if (text.find('\0') != std::string::npos)
      throw InputError(name + ": contains a NUL byte (binary file?)");
    check_line_endings(text, name);

    const boost::property_tree::ptree declared = declarations(prm);
    std::vector<EntryPath>            doubles;
    collect_double_entries(declared, {}, doubles);

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

    if (extension == ".json")
      {
        // deal.II reads an array's elements as entries of empty name and
        // reports "entry <> you have not yet declared"
        bool         in_string = false;
        unsigned int line      = 1;
        for (std::size_t i = 0; i < text.size(); ++i)
          if (text[i] == '\n')
            ++line;
          else if (in_string && text[i] == '\\')
            ++i;
          else if (text[i] == '"')
            in_string = !in_string;
          else if (!in_string && text[i] == '[')
            throw InputError(name + ": line " + std::to_string(line) +
                             ": a JSON array is not a deal.II parameter file "
                             "entry (deal.II reads objects of \"name\": "
                             "\"value\" pairs)");
      }
    if (extension == ".prm")
      {
        std::vector<std::string>           chain{filename};
        std::error_code                    error;
        std::vector<std::filesystem::path> canonical_chain{
          std::filesystem::canonical(filename, error)};
        std::vector<unsigned int> line_chain;
        try
          {
            check_includes(text, chain, canonical_chain, line_chain);
          }
        catch (const InputError &exc)
          {
            throw InputError(name + ": " + exc.what());
          }
      }

    if (extension == ".xml")
      try
        {
          boost::property_tree::ptree tree;
          std::istringstream          input(text);
          boost::property_tree::read_xml(input, tree);
          const std::string name_found =
            undemanglable_name(tree.get_child("ParameterHandler",
                                              boost::property_tree::ptree()),
                               "");
          if (!name_found.empty())
            throw InputError(
              name + ": " + shortened(name_found) +
              ": no such entry or subsection is declared (in .xml files "
              "deal.II reads names mangled, e.g. Number_20of_20cycles)");
        }
      catch (const boost::property_tree::ptree_error &)
        {
          // (deal.II reports the malformed file)
        }
    try
      {
        // as ParameterHandler::parse_input(filename) does, from the text
        // read above
        std::istringstream input(text);
        if (extension == ".prm")
          prm.parse_input(input, filename, "", skip_undefined);
        else if (extension == ".xml")
          prm.parse_input_from_xml(input, skip_undefined);
        else if (extension == ".json")
          prm.parse_input_from_json(input, skip_undefined);
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
        const std::string message = one_line_message(info.str());
        throw InputError(
          name + ": " +
          (extension == ".prm" ?
             with_entry_name(message, filename, text) :
             with_json_or_xml_entry_name(message, text, extension, declared)));
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
      // Names the parser defines itself: deal.II's ParsedFunction sets pi and
      // Pi after the user's constants (a constant pi=0.1 would silently be
      // 3.14159), muparser has _pi and _e; a variable or constant of one of
      // these names makes muparser throw an exception deal.II lets through.
      const std::set<std::string> predefined{"pi", "Pi", "_pi", "_e"};
      const std::string           variable_list = prm.get("Variable names");
      std::set<std::string>       variables{"x", "y", "z", "t"};
      {
        std::istringstream in(variable_list);
        for (std::string variable; std::getline(in, variable, ',');)
          {
            variable = trimmed(variable);
            if (predefined.count(variable) != 0)
              throw InputError(description + ": Variable names = " +
                               trimmed(variable_list) + ": <" + variable +
                               "> is a predefined constant of the function "
                               "parser; choose another name");
            variables.insert(variable);
          }
      }

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
            {
              // muParser takes constants as numbers only: an expression
              // (0.1*1e6, 2+3, pi/2) is not evaluated; a number out of range
              // (1e400, 1e-400, nan, -inf) is said to be one
              char *end         = nullptr;
              errno             = 0;
              const double read = std::strtod(value.c_str(), &end);
              const bool   out_of_range =
                !value.empty() && *end == '\0' &&
                (!std::isfinite(read) || errno == ERANGE);
              throw InputError(
                name + "the value <" + value + "> of " + constant +
                (out_of_range ?
                   out_of_range_reason(value) :
                   " is not a plain number: constants take numbers "
                   "only, not expressions (write the number, e.g. "
                   "1.5e5, or put the expression into Function "
                   "expression)"));
            }
          if (predefined.count(constant) != 0)
            throw InputError(name + "<" + constant +
                             "> is a predefined constant of the function "
                             "parser and cannot be redefined; choose another "
                             "name");
          if (variables.count(constant) != 0)
            throw InputError(name + "<" + constant +
                             "> is the name of a variable (x, y, z, t or "
                             "Variable names = " +
                             trimmed(variable_list) + "); choose another name");
          if (!names.insert(constant).second)
            throw InputError(name + constant + " is defined twice");
        }
    }



    /// Check the "Variable names" of the current subsection of @p prm in
    /// dimension @p dim: deal.II takes the first dim names as the
    /// coordinates and a (dim+1)-th as the time, whatever they are called,
    /// so that x,y,t in 3D silently makes t the coordinate z and x,y,z in
    /// 2D makes z the time. A name x, y or z must be its own coordinate, t
    /// the time.
    void
    check_variable_names(ParameterHandler  &prm,
                         const unsigned int dim,
                         const std::string &description)
    {
      const std::string        list = prm.get("Variable names");
      std::vector<std::string> names;
      std::istringstream       in(list);
      for (std::string name; std::getline(in, name, ',');)
        names.push_back(trimmed(name));
      const std::string coordinates = dim == 2 ? "x, y" : "x, y, z";
      const std::string prefix      = description +
                                 ": Variable names = " + trimmed(list) +
                                 ": in " + std::to_string(dim) + "D ";
      if (names.size() != dim && names.size() != dim + 1)
        throw InputError(prefix + "give the " + std::to_string(dim) +
                         " coordinates and optionally the time, e.g. " +
                         coordinates + ", t");
      const std::string axes = "xyz";
      for (unsigned int i = 0; i < names.size(); ++i)
        {
          const std::string meaning =
            i < dim ? std::string("the coordinate ") + axes[i] : "the time";
          const bool misplaced =
            (names[i].size() == 1 &&
             axes.find(names[i][0]) != std::string::npos &&
             names[i] != (i < dim ? std::string(1, axes[i]) : "")) ||
            (names[i] == "t" && i != dim);
          if (misplaced)
            throw InputError(prefix + "<" + names[i] + "> would be " + meaning +
                             "; use " + coordinates + ", t");
        }
    }
  } // namespace



  void
  warn_once(const std::string &kind,
            const std::string &text,
            const MPI_Comm     communicator)
  {
    static std::set<std::string> printed;
    if (!printed.insert(kind).second)
      return;
    if (Utilities::MPI::this_mpi_process(communicator) == 0)
      std::cout << "Warning: " << text << std::endl;
  }



  void
  refuse_random_numbers(const std::string &expression,
                        const std::string &description)
  {
    static const std::regex call("(^|[^A-Za-z0-9_])rand(_seed)?[ \\t]*\\(");
    if (std::regex_search(expression, call))
      throw InputError(description + ": <" + expression +
                       "> calls rand() or rand_seed(), whose values differ "
                       "between runs, threads and MPI ranks: give data that "
                       "are functions of the coordinates and t only");
  }



  template <int dim>
  std::unique_ptr<Functions::ParsedFunction<dim>>
  parse_function(ParameterHandler  &prm,
                 const unsigned int n_components,
                 const std::string &description)
  {
    check_variable_names(prm, dim, description);
    check_function_constants(prm, description);
    refuse_random_numbers(prm.get("Function expression"), description);
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
    catch (...)
      {
        // muparser's mu::ParserError derives from nothing standard
        std::cerr.rdbuf(cerr_buffer);
        throw InputError(description +
                         ": invalid function: the expression parser refused "
                         "the expression, its variables or its constants");
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
