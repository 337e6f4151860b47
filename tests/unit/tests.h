// Helpers shared by the unit tests: run the application on a parameter file
// with some entries overridden, and read back what it computed.
#ifndef signorini_tests_h
#define signorini_tests_h

#include <deal.II/base/logstream.h>
#include <deal.II/base/utilities.h>

#include <signorini/input_error.h>
#include <signorini/signorini_problem.h>

#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace SignoriniTests
{
  using namespace dealii;
  using namespace Signorini;

  /// Set "A/B/name" in @p prm.
  inline void
  set_entry(ParameterHandler  &prm,
            const std::string &path,
            const std::string &value)
  {
    const auto parts = Utilities::split_string_list(path, '/');
    for (unsigned int i = 0; i + 1 < parts.size(); ++i)
      prm.enter_subsection(parts[i]);
    prm.set(parts.back(), value);
    for (unsigned int i = 0; i + 1 < parts.size(); ++i)
      prm.leave_subsection();
  }

  struct Result
  {
    std::map<std::string, std::string>         statistics; // last row
    std::map<std::string, std::vector<double>> history;    // numeric columns
    std::vector<bool>                          active; // per multiplier node
    Vector<double>                             dual;
  };

  /// Directory of the tests' parameter files (tests/inputs: copies of the
  /// examples, so that editing prm/ does not change the tests).
  inline std::string
  input_directory()
  {
    return std::string(SOURCE_DIR) + "/../inputs";
  }

  /// Declare all parameters (of the problem in @p dim dimensions) and read
  /// @p prm_file (from tests/inputs/) with overrides; timing and VTU output
  /// off.
  template <int dim = 2>
  inline void
  read_parameters(ParameterHandler                         &prm,
                  const std::string                        &prm_file,
                  const std::map<std::string, std::string> &overrides)
  {
    SignoriniProblem<dim>::declare_parameters(prm);
    parse_parameter_file(prm, input_directory() + "/" + prm_file);
    set_entry(prm, "Output/Print timing", "false");
    set_entry(prm, "Output/Write vtu", "false");
    for (const auto &[path, value] : overrides)
      set_entry(prm, path, value);
  }

  /// Run @p problem with its screen log swallowed (it is not compared).
  template <int dim>
  inline void
  run_quietly(SignoriniProblem<dim> &problem)
  {
    std::ostringstream screen;
    auto *const        old = std::cout.rdbuf(screen.rdbuf());
    problem.run();
    std::cout.rdbuf(old);
  }

  /// Send deallog to the file "output" that the test harness compares.
  inline std::ofstream &
  initlog()
  {
    static std::ofstream logfile("output");
    deallog.attach(logfile);
    deallog.depth_console(0);
    deallog.depth_file(1);
    return logfile;
  }

  /// Run @p prm_file (from tests/inputs/) with overrides, without the
  /// estimator, in @p dim dimensions.
  template <int dim = 2>
  inline Result
  run(const std::string                        &prm_file,
      const std::map<std::string, std::string> &overrides)
  {
    ParameterHandler prm;
    auto             o = overrides;
    o.emplace("Error estimator/Enable", "false");
    read_parameters<dim>(prm, prm_file, o);
    SignoriniProblem<dim> problem(prm, input_directory());
    run_quietly(problem);

    Result result;
    for (const auto &column : {"cells",
                               "dofs",
                               "contact_nodes",
                               "active_nodes",
                               "iterations",
                               "cg_iterations",
                               "nested_meshes",
                               "nested_iterations",
                               "energy",
                               "contact_force",
                               "feasibility",
                               "multiplier_sign",
                               "complementarity",
                               "residual",
                               "resultant",
                               "converged",
                               "energy_error"})
      {
        result.statistics[column] = problem.statistics().last(column);
        for (const auto &v : problem.statistics().column(column))
          result.history[column].push_back(v.empty() ? 0. : std::stod(v));
      }
    result.dual   = problem.dual();
    result.active = problem.active_set();
    return result;
  }

  /// Overrides of tests/inputs/block.prm for a gap on the right edge: the
  /// block pressed to the right (horizontal contact direction, the outward
  /// normal) onto a curved foundation, part of GC staying open.
  inline std::map<std::string, std::string>
  gap_on_right_edge()
  {
    return {{"Boundary conditions/Traction 1/Boundary ids", "3, 5"},
            {"Boundary conditions/Traction 1/Function expression", "p; 0"},
            {"Boundary conditions/Traction 2/Boundary ids", ""},
            {"Contact/Boundary ids", "4, 6"},
            {"Contact/Direction", "outward normal"},
            {"Contact/Gap/Function expression", "0.002 + 0.05*(y-0.6)^2"}};
  }

  inline double
  value(const Result &result, const std::string &column)
  {
    return Utilities::string_to_double(result.statistics.at(column));
  }

  /// Print "name: OK" or "name: FAILED (value vs bound)" and count failures.
  inline void
  expect_below(const std::string &name,
               const double       value,
               const double       bound,
               unsigned int      &failures)
  {
    if (value <= bound)
      deallog << name << ": OK" << std::endl;
    else
      {
        deallog << name << ": FAILED (" << value << " > " << bound << ")"
                << std::endl;
        ++failures;
      }
  }

  /// Run @p prm_file with @p overrides from scratch and with the nested
  /// start (Contact/Nested start false, true), log both, and check that
  /// both converge to the same discrete solution (same active set, energies
  /// and contact forces to 1e-10 relative) with fewer active-set iterations
  /// on the mesh itself for the nested start. Returns {scratch, nested}.
  template <int dim = 2>
  inline std::pair<Result, Result>
  compare_starts(const std::string                        &prm_file,
                 const std::map<std::string, std::string> &overrides,
                 unsigned int                             &failures)
  {
    std::map<std::string, Result> results;
    for (const std::string start : {"false", "true"})
      {
        auto o                    = overrides;
        o["Contact/Nested start"] = start;
        const Result r            = run<dim>(prm_file, o);
        deallog << "nested start " << start << ": cells "
                << r.statistics.at("cells") << ", active "
                << r.statistics.at("active_nodes") << " of "
                << r.statistics.at("contact_nodes") << ", iterations "
                << r.statistics.at("iterations") << ", coarser meshes "
                << r.statistics.at("nested_meshes") << " ("
                << r.statistics.at("nested_iterations")
                << " iterations), converged " << r.statistics.at("converged")
                << std::endl;
        if (r.statistics.at("converged") != "1")
          {
            deallog << "not converged: FAILED" << std::endl;
            ++failures;
          }
        results[start] = r;
      }
    const Result &scratch = results["false"], &nested = results["true"];
    const auto    relative = [&](const std::string &column) {
      return std::abs(value(nested, column) - value(scratch, column)) /
             std::abs(value(scratch, column));
    };
    if (nested.active == scratch.active)
      deallog << "same active set: OK" << std::endl;
    else
      {
        deallog << "same active set: FAILED" << std::endl;
        ++failures;
      }
    expect_below("relative energy difference",
                 relative("energy"),
                 1e-10,
                 failures);
    expect_below("relative contact force difference",
                 relative("contact_force"),
                 1e-10,
                 failures);
    expect_below("fewer iterations on the mesh (nested - scratch)",
                 value(nested, "iterations") - value(scratch, "iterations"),
                 -1.,
                 failures);
    return {scratch, nested};
  }

  /// The rows of the CSV file @p filename (a contact-CC.csv), each as
  /// column name -> value.
  inline std::vector<std::map<std::string, std::string>>
  read_table(const std::string &filename)
  {
    std::ifstream in(filename);
    std::string   line;
    std::getline(in, line);
    const auto names = Utilities::split_string_list(line, ',');
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line))
      {
        const auto values = Utilities::split_string_list(line, ',');
        AssertThrow(values.size() == names.size(),
                    ExcMessage("a row of " + filename + " has " +
                               std::to_string(values.size()) + " fields"));
        rows.emplace_back();
        for (unsigned int i = 0; i < names.size(); ++i)
          rows.back()[names[i]] = values[i];
      }
    return rows;
  }
} // namespace SignoriniTests

#endif
