#ifndef signorini_exact_solution_h
#define signorini_exact_solution_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>

#include <signorini/contact_computation.h>

#include <memory>

namespace Signorini
{
  using namespace dealii;

  /**
   * A known displacement u (a manufactured solution), section "Exact
   * solution": the energy-norm error of a computation against it.
   */
  template <int dim>
  class ExactSolution
  {
  public:
    /// ||u - u_h|| and, if ||u|| > 0, ||u - u_h|| / ||u|| (else negative).
    struct Error
    {
      double energy_error          = 0.;
      double relative_energy_error = -1.;
    };

    static void
    declare_parameters(ParameterHandler &prm);

    void
    parse_parameters(ParameterHandler &prm);

    bool
    enabled() const;

    /// u, or nullptr if not enabled.
    const Function<dim> *
    function() const;

    /// The error of the displacement of @p computation in the energy norm
    /// ||v||^2 = int eps(v) : K : eps(v) (a collective call under MPI).
    Error
    error(const ContactComputation<dim> &computation) const;

  private:
    std::unique_ptr<Functions::ParsedFunction<dim>> displacement;
  };
} // namespace Signorini

#endif
