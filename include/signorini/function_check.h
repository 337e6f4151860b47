#ifndef signorini_function_check_h
#define signorini_function_check_h

#include <deal.II/base/function.h>
#include <deal.II/base/point.h>

#include <deal.II/fe/component_mask.h>

#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * Evaluate the input function @p function at @p points and throw an
   * InputError naming the parameter @p name and the first point where a
   * component selected by @p mask (default: all) is NaN or infinite. A parsed
   * expression can be syntactically valid and still undefined on part of the
   * domain (sqrt of a negative number, division by zero); its value would
   * otherwise flow silently into the computation. Returns the largest
   * magnitude of the selected components at @p points.
   */
  template <int dim>
  double
  check_finite(const Function<dim>           &function,
               const std::vector<Point<dim>> &points,
               const std::string             &name,
               const ComponentMask           &mask = ComponentMask());
} // namespace Signorini

#endif
