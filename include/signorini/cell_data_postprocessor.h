#ifndef signorini_cell_data_postprocessor_h
#define signorini_cell_data_postprocessor_h

#include <deal.II/lac/vector.h>

#include <deal.II/numerics/data_postprocessor.h>

#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * Writes one value per active cell (e.g. the local error contributions
   * eps_E) as a field of the VTU output, constant on each cell.
   */
  template <int dim>
  class CellDataPostprocessor : public DataPostprocessorScalar<dim>
  {
  public:
    CellDataPostprocessor(const std::string    &name,
                          const Vector<double> &values);

    void
    evaluate_vector_field(
      const DataPostprocessorInputs::Vector<dim> &inputs,
      std::vector<Vector<double>> &computed_quantities) const override;

  private:
    const Vector<double> &values;
  };
} // namespace Signorini

#endif
