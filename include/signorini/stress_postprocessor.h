#ifndef signorini_stress_postprocessor_h
#define signorini_stress_postprocessor_h

#include <deal.II/numerics/data_postprocessor.h>

#include <signorini/material.h>

namespace Signorini
{
  using namespace dealii;

  /**
   * Stress output of the finite element solution sigma_h = K eps(u_h):
   * the in-plane components, sigma_zz of the plane state and the von Mises
   * stress, as point data (constant per P1 cell). In 3D: the six components
   * (xx, yy, zz, xy, yz, xz) and the von Mises stress.
   */
  template <int dim>
  class StressPostprocessor : public DataPostprocessor<dim>
  {
  public:
    explicit StressPostprocessor(const LinearElasticMaterial<dim> &material);

    void
    evaluate_vector_field(
      const DataPostprocessorInputs::Vector<dim> &inputs,
      std::vector<Vector<double>> &computed_quantities) const override;

    std::vector<std::string>
    get_names() const override;

    UpdateFlags
    get_needed_update_flags() const override;

  private:
    const LinearElasticMaterial<dim> &material;
  };
} // namespace Signorini

#endif
