#include <deal.II/dofs/dof_handler.h>

#include <signorini/cell_data_postprocessor.h>

namespace Signorini
{
  template <int dim>
  CellDataPostprocessor<dim>::CellDataPostprocessor(
    const std::string    &name,
    const Vector<double> &values)
    : DataPostprocessorScalar<dim>(name, update_default)
    , values(values)
  {}



  template <int dim>
  void
  CellDataPostprocessor<dim>::evaluate_vector_field(
    const DataPostprocessorInputs::Vector<dim> &inputs,
    std::vector<Vector<double>>                &computed_quantities) const
  {
    const auto   cell  = inputs.template get_cell<dim>();
    const double value = values[cell->active_cell_index()];
    for (auto &q : computed_quantities)
      q(0) = value;
  }

  template class CellDataPostprocessor<2>;
  template class CellDataPostprocessor<3>;
} // namespace Signorini
