#ifndef signorini_load_path_h
#define signorini_load_path_h

#include <deal.II/base/function_parser.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>

#include <memory>
#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * The quasi-static load path (doc/theory.md section 8, "The quasi-static load
   * path"): the data are applied in Load steps = N steps at the times t_k = k /
   * N, k = 1..N. At step k every datum (tractions, body force, prescribed
   * displacements) is its Function expression evaluated at time t_k (the
   * variable t of the expressions) times the Load factor at t_k. The default
   * factor t applies data that do not use t in N equal increments; a factor 1
   * and data written in t give any other path (a normal load, then a tangential
   * one). With friction each step slides against the state of the step before,
   * so the answer depends on the path; without friction it does not, and the
   * steps only give the intermediate states. One step (the default) is today's
   * static problem, at t = 1.
   */
  class LoadPath
  {
  public:
    /// One step, factor 1 (until parse_parameters()).
    LoadPath() = default;

    /// Load steps and Load factor in section Contact.
    static void
    declare_parameters(ParameterHandler &prm);

    void
    parse_parameters(ParameterHandler &prm);

    unsigned int
    n_steps() const;

    /// t_k = k / N.
    double
    time(const unsigned int step) const;

    /// The Load factor at t_k (checked finite: an InputError names it).
    double
    factor(const unsigned int step) const;

  private:
    unsigned int                       steps = 1;
    std::string                        factor_expression;
    std::unique_ptr<FunctionParser<1>> factor_function;
  };

  /**
   * A datum along the load path: its parsed Function expression f(x, t)
   * times the load factor of the current step, so that every user of the
   * data (assembly, constraints, estimator) sees the same values. The time
   * and factor are set together by set_step().
   */
  template <int dim>
  class LoadPathFunction : public Function<dim>
  {
  public:
    explicit LoadPathFunction(
      std::unique_ptr<Functions::ParsedFunction<dim>> expression);

    /// The data of step @p step of @p path.
    void
    set_step(const LoadPath &path, const unsigned int step);

    double
    value(const Point<dim> &p, const unsigned int component = 0) const override;

    void
    vector_value(const Point<dim> &p, Vector<double> &values) const override;

    void
    vector_value_list(const std::vector<Point<dim>> &points,
                      std::vector<Vector<double>>   &values) const override;

  private:
    std::unique_ptr<Functions::ParsedFunction<dim>> expression;
    double                                          scale = 1.;
  };
} // namespace Signorini

#endif
