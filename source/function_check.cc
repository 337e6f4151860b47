#include <signorini/function_check.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace Signorini
{
  template <int dim>
  double
  check_finite(const Function<dim>           &function,
               const std::vector<Point<dim>> &points,
               const std::string             &name,
               const ComponentMask           &mask)
  {
    const unsigned int n_components = function.n_components;
    double             largest      = 0.;
    // component by component: no allocation (called for every cell)
    for (unsigned int i = 0; i < points.size(); ++i)
      for (unsigned int c = 0; c < n_components; ++c)
        if (const double value = mask[c] ? function.value(points[i], c) : 0.;
            !std::isfinite(value))
          {
            std::ostringstream message;
            // "nan" whatever its sign bit, so that messages do not depend
            // on how the NaN arose
            message << name << ": Function expression is not finite ("
                    << (std::isnan(value) ? "nan" :
                        value > 0.        ? "inf" :
                                            "-inf")
                    << ") at (";
            for (unsigned int d = 0; d < dim; ++d)
              message << (d > 0 ? ", " : "") << points[i][d];
            message << ")";
            if (n_components > 1)
              message << ", component " << static_cast<char>('x' + c);
            throw InputError(message.str());
          }
        else
          largest = std::max(largest, std::abs(value));
    return largest;
  }

  template double
  check_finite<2>(const Function<2> &,
                  const std::vector<Point<2>> &,
                  const std::string &,
                  const ComponentMask &);
  template double
  check_finite<3>(const Function<3> &,
                  const std::vector<Point<3>> &,
                  const std::string &,
                  const ComponentMask &);
} // namespace Signorini
