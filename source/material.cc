#include <signorini/input_error.h>
#include <signorini/material.h>
#include <signorini/registry.h>

namespace Signorini
{
  namespace
  {
    /// The names of the values of Material/Plane state.
    template <int dim>
    const NamedValues<typename LinearElasticMaterial<dim>::PlaneState> &
    plane_state_names()
    {
      using PlaneState = typename LinearElasticMaterial<dim>::PlaneState;
      static const NamedValues<PlaneState> names(
        {{"plane strain", PlaneState::plane_strain, ""},
         {"plane stress", PlaneState::plane_stress, ""}});
      return names;
    }
  } // namespace



  template <int dim>
  void
  LinearElasticMaterial<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    {
      prm.declare_entry("Young modulus",
                        "1",
                        Patterns::Double(),
                        "Young's modulus E (stress units), must be > 0.");
      prm.declare_entry("Poisson ratio",
                        "0.3",
                        Patterns::Double(),
                        "Poisson's ratio nu, in (-1, 0.5).");
      prm.declare_entry("Plane state",
                        plane_state_names<dim>().default_name(),
                        Patterns::Selection(
                          plane_state_names<dim>().selection()),
                        "2D reduction of the 3D law.");
    }
    prm.leave_subsection();
  }



  template <int dim>
  void
  LinearElasticMaterial<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    {
      young_modulus = prm.get_double("Young modulus");
      poisson_ratio = prm.get_double("Poisson ratio");
      plane_state   = plane_state_names<dim>().value(prm.get("Plane state"));
    }
    prm.leave_subsection();
    if (!(young_modulus > 0.))
      throw InputError("Material/Young modulus = " +
                       std::to_string(young_modulus) + " must be > 0");
    if (!(poisson_ratio > -1. && poisson_ratio < 0.5))
      throw InputError(
        "Material/Poisson ratio = " + std::to_string(poisson_ratio) +
        " must lie in (-1, 0.5): the material would not be "
        "stable (nu = 0.5 is incompressible, which P1 locks)");
  }



  template <int dim>
  void
  LinearElasticMaterial<dim>::set(const double     E,
                                  const double     nu,
                                  const PlaneState plane_state_)
  {
    young_modulus = E;
    poisson_ratio = nu;
    plane_state   = plane_state_;
  }



  template <int dim>
  double
  LinearElasticMaterial<dim>::mu() const
  {
    return young_modulus / (2. * (1. + poisson_ratio));
  }



  template <int dim>
  double
  LinearElasticMaterial<dim>::lambda() const
  {
    const double lambda_3d = young_modulus * poisson_ratio /
                             ((1. + poisson_ratio) * (1. - 2. * poisson_ratio));
    if (plane_state == PlaneState::plane_stress && dim == 2)
      return 2. * lambda_3d * mu() / (lambda_3d + 2. * mu());
    return lambda_3d;
  }



  template <int dim>
  SymmetricTensor<2, dim>
  LinearElasticMaterial<dim>::stress(const SymmetricTensor<2, dim> &eps) const
  {
    return lambda() * trace(eps) * unit_symmetric_tensor<dim>() +
           2. * mu() * eps;
  }



  template <int dim>
  SymmetricTensor<2, dim>
  LinearElasticMaterial<dim>::strain(const SymmetricTensor<2, dim> &sigma) const
  {
    // Invert sigma = lambda tr(eps) I + 2 mu eps in the dim-dimensional space:
    // tr(sigma) = (dim lambda + 2 mu) tr(eps).
    const double l = lambda(), m = mu();
    const double tr_eps = trace(sigma) / (dim * l + 2. * m);
    return (sigma - l * tr_eps * unit_symmetric_tensor<dim>()) / (2. * m);
  }



  template <int dim>
  double
  LinearElasticMaterial<dim>::out_of_plane_stress(
    const SymmetricTensor<2, dim> &eps) const
  {
    return (dim == 2 && plane_state == PlaneState::plane_strain) ?
             lambda() * trace(eps) :
             0.;
  }



  template <int dim>
  double
  LinearElasticMaterial<dim>::von_mises_stress(
    const SymmetricTensor<2, dim> &eps) const
  {
    const SymmetricTensor<2, dim> sigma = stress(eps);
    // Deviator of the full 3x3 stress (sigma_zz from the plane state).
    SymmetricTensor<2, 3> s3;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = i; j < dim; ++j)
        s3[i][j] = sigma[i][j];
    if (dim == 2)
      s3[2][2] = out_of_plane_stress(eps);
    const SymmetricTensor<2, 3> s = deviator(s3);
    return std::sqrt(1.5 * scalar_product(s, s));
  }

  template class LinearElasticMaterial<2>;
  template class LinearElasticMaterial<3>;
} // namespace Signorini
