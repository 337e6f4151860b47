#ifndef signorini_material_h
#define signorini_material_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/symmetric_tensor.h>

namespace Signorini
{
  using namespace dealii;

  /**
   * Isotropic linear elasticity (Hooke's tensor K of the paper) in plane
   * strain or plane stress. In plane stress the Lame constant lambda is
   * replaced by 2 lambda mu / (lambda + 2 mu), so that the in-plane relation
   * keeps the same form.
   */
  template <int dim>
  class LinearElasticMaterial
  {
  public:
    /// The 2D reduction of the 3D law (Material/Plane state).
    enum class PlaneState
    {
      plane_strain,
      plane_stress
    };

    static void
    declare_parameters(ParameterHandler &prm);

    /// Read the parameters; throws InputError for E <= 0 or nu outside (-1,
    /// 1/2).
    void
    parse_parameters(ParameterHandler &prm);

    /// Set the constants directly (unit tests, benchmarks).
    void
    set(const double     young_modulus,
        const double     poisson_ratio,
        const PlaneState plane_state);

    /// K : eps
    SymmetricTensor<2, dim>
    stress(const SymmetricTensor<2, dim> &strain) const;

    /// K^{-1} : sigma, the inverse constitutive relation used by the error in
    /// constitutive relation.
    SymmetricTensor<2, dim>
    strain(const SymmetricTensor<2, dim> &stress) const;

    /// sigma_zz: lambda tr(eps) in plane strain, zero in plane stress.
    double
    out_of_plane_stress(const SymmetricTensor<2, dim> &strain) const;

    /// Von Mises equivalent stress including sigma_zz.
    double
    von_mises_stress(const SymmetricTensor<2, dim> &strain) const;

    /// Lame's lambda of the in-plane relation (modified in plane stress)
    double
    lambda() const;

    double
    mu() const;

    double     young_modulus = 1.0;
    double     poisson_ratio = 0.3;
    PlaneState plane_state   = PlaneState::plane_strain;
  };
} // namespace Signorini

#endif
