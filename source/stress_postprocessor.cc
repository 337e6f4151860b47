#include <signorini/stress_postprocessor.h>

namespace Signorini
{
  template <int dim>
  StressPostprocessor<dim>::StressPostprocessor(
    const LinearElasticMaterial<dim> &material)
    : material(material)
  {}



  template <int dim>
  std::vector<std::string>
  StressPostprocessor<dim>::get_names() const
  {
    if (dim == 2)
      return {"sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz", "von_mises"};
    return {"sigma_xx",
            "sigma_yy",
            "sigma_zz",
            "sigma_xy",
            "sigma_yz",
            "sigma_xz",
            "von_mises"};
  }



  template <int dim>
  UpdateFlags
  StressPostprocessor<dim>::get_needed_update_flags() const
  {
    return update_gradients;
  }



  template <int dim>
  void
  StressPostprocessor<dim>::evaluate_vector_field(
    const DataPostprocessorInputs::Vector<dim> &inputs,
    std::vector<Vector<double>>                &computed_quantities) const
  {
    for (unsigned int q = 0; q < inputs.solution_gradients.size(); ++q)
      {
        Tensor<2, dim> grad;
        for (unsigned int c = 0; c < dim; ++c)
          grad[c] = inputs.solution_gradients[q][c];
        const SymmetricTensor<2, dim> eps   = symmetrize(grad);
        const SymmetricTensor<2, dim> sigma = material.stress(eps);
        if constexpr (dim == 2)
          {
            computed_quantities[q][0] = sigma[0][0];
            computed_quantities[q][1] = sigma[1][1];
            computed_quantities[q][2] = sigma[0][1];
            computed_quantities[q][3] = material.out_of_plane_stress(eps);
            computed_quantities[q][4] = material.von_mises_stress(eps);
          }
        else
          {
            // the names of get_names(): diagonal, then xy, yz, xz
            static constexpr unsigned int pairs[6][2] = {
              {0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
            for (unsigned int k = 0; k < 6; ++k)
              computed_quantities[q][k] = sigma[pairs[k][0]][pairs[k][1]];
            computed_quantities[q][6] = material.von_mises_stress(eps);
          }
      }
  }

  template class StressPostprocessor<2>;
  template class StressPostprocessor<3>;
} // namespace Signorini
