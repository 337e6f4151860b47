#include <deal.II/base/numbers.h>

#include <deal.II/lac/vector.h>

#include <signorini/input_error.h>
#include <signorini/load_path.h>

#include <cmath>
#include <iostream>
#include <sstream>

namespace Signorini
{
  void
  LoadPath::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    prm.declare_entry("Load steps",
                      "1",
                      Patterns::Integer(1, 10000),
                      "Solve the quasi-static problem in this many steps, at "
                      "t = 1/N, 2/N, ..., 1: each step's data are the "
                      "Function expressions at time t times the Load factor; "
                      "with friction each step slides against the previous "
                      "state. Steps > 1 write their outputs per step "
                      "(load-steps.csv, steps-CC.pvd).");
    prm.declare_entry("Load factor",
                      "t",
                      Patterns::Anything(),
                      "The factor of all data (tractions, body force, "
                      "prescribed displacements) as a function of the time "
                      "t of the load path: t gives equal increments, 1 lets "
                      "the data's own t decide (e.g. a normal load, then a "
                      "tangential one).");
    prm.leave_subsection();
  }



  void
  LoadPath::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    steps             = prm.get_integer("Load steps");
    factor_expression = prm.get("Load factor");
    prm.leave_subsection();
    refuse_random_numbers(factor_expression, "Contact/Load factor");
    factor_function = std::make_unique<FunctionParser<1>>(1);
    // (muparser's diagnostics on std::cerr: the message says the same)
    std::ostringstream    muparser_diagnostics;
    std::streambuf *const cerr_buffer =
      std::cerr.rdbuf(muparser_diagnostics.rdbuf());
    try
      {
        // the constants every other expression has (ParsedFunction's)
        factor_function->initialize("t",
                                    factor_expression,
                                    {{"pi", numbers::PI}, {"Pi", numbers::PI}});
        factor_function->value(Point<1>(1.)); // forces muparser to parse
        std::cerr.rdbuf(cerr_buffer);
      }
    catch (const ExceptionBase &exc)
      {
        std::cerr.rdbuf(cerr_buffer);
        std::ostringstream text;
        exc.print_info(text);
        throw InputError(
          "Contact/Load factor: <" + factor_expression +
          "> is not a function of t alone: " + one_line_message(text.str()));
      }
    catch (...)
      {
        // (muparser's mu::ParserError derives from nothing standard)
        std::cerr.rdbuf(cerr_buffer);
        throw InputError("Contact/Load factor: <" + factor_expression +
                         "> is not a function of t alone: the expression "
                         "parser refused it");
      }
    // every value used, now: a NaN at some step is an input error
    for (unsigned int k = 1; k <= steps; ++k)
      factor(k);
  }



  unsigned int
  LoadPath::n_steps() const
  {
    return steps;
  }



  double
  LoadPath::time(const unsigned int step) const
  {
    return static_cast<double>(step) / steps;
  }



  double
  LoadPath::factor(const unsigned int step) const
  {
    const double t = time(step);
    if (!factor_function) // (not parsed: the static problem)
      return 1.;
    const double value = factor_function->value(Point<1>(t));
    if (!std::isfinite(value))
      {
        std::ostringstream text;
        text << "Contact/Load factor: <" << factor_expression << "> is "
             << value << " at t = " << t << "; it must be finite";
        throw InputError(text.str());
      }
    return value;
  }



  template <int dim>
  LoadPathFunction<dim>::LoadPathFunction(
    std::unique_ptr<Functions::ParsedFunction<dim>> expression)
    : Function<dim>(expression->n_components)
    , expression(std::move(expression))
  {}



  template <int dim>
  void
  LoadPathFunction<dim>::set_step(const LoadPath &path, const unsigned int step)
  {
    this->set_time(path.time(step));
    expression->set_time(path.time(step));
    scale = path.factor(step);
  }



  template <int dim>
  double
  LoadPathFunction<dim>::value(const Point<dim>  &p,
                               const unsigned int component) const
  {
    return scale * expression->value(p, component);
  }



  template <int dim>
  void
  LoadPathFunction<dim>::vector_value(const Point<dim> &p,
                                      Vector<double>   &values) const
  {
    expression->vector_value(p, values);
    values *= scale;
  }



  template <int dim>
  void
  LoadPathFunction<dim>::vector_value_list(
    const std::vector<Point<dim>> &points,
    std::vector<Vector<double>>   &values) const
  {
    expression->vector_value_list(points, values);
    for (auto &v : values)
      v *= scale;
  }



  template class LoadPathFunction<2>;
  template class LoadPathFunction<3>;
} // namespace Signorini
