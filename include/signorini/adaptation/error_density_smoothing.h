#ifndef signorini_adaptation_error_density_smoothing_h
#define signorini_adaptation_error_density_smoothing_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/vector.h>

namespace Signorini
{
  using namespace dealii;

  /**
   * The local errors as the size predictor reads them: the error density
   * eps_E^2 / |E| averaged over vertex patches, a given number of passes,
   * the global error kept.
   *
   * Why: on unstructured tetrahedra eps_E scatters from cell to cell with
   * the cells' shapes, not only with the solution. The optimal sizes
   * (paper section 6) then shrink the cells whose estimate is high by
   * chance and the prediction counts that as a gain, which the next mesh,
   * whose shapes scatter anew, does not realise: the error reached stays
   * above the target. A smooth density removes that scatter; the sizes
   * still follow the solution's singularities, whose densities vary over
   * several cells.
   */
  class ErrorDensitySmoothing
  {
  public:
    /// Error density smoothing in section Mesh adaptation.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read it.
    void
    parse_parameters(ParameterHandler &prm);

    /// @p local_error (eps_E per active cell of @p mesh) with its density
    /// smoothed, sum of squares unchanged; unchanged for 0 passes.
    template <int dim>
    Vector<double>
    apply(const Triangulation<dim> &mesh,
          const Vector<double>     &local_error) const;

  private:
    unsigned int passes = 0;
  };
} // namespace Signorini

#endif
