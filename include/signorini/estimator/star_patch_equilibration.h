#ifndef signorini_estimator_star_patch_equilibration_h
#define signorini_estimator_star_patch_equilibration_h

#include <signorini/estimator/stress_reconstruction.h>

namespace Signorini
{
  /**
   * The star-patch (flux-free) construction of sigma^ (Cottereau, Diez and
   * Huerta 2009; Pares, Diez and Huerta 2006; called SPET by Pled, Chamoin
   * and Ladeveze 2011; doc/theory.md section 7) for P1 simplices. With
   * R(v) = int f_d . v + int_G2 F_d . v + int_GC R^ . v -
   * int sigma_h : eps(v) the residual of the finite element solution (zero
   * on the finite element space: sigma_h is in FE equilibrium with the
   * loads), one Neumann problem per vertex patch (star) omega_i:
   *
   *   find z_i in V_i:  int_{omega_i} K eps(z_i) : eps(v)
   *                       = R(phi_i (v - Pi_h v))   for all v in V_i,
   *
   * V_i the continuous piecewise polynomials of degree "Local degree" on
   * omega_i (zero on the Dirichlet part), Pi_h the P1 interpolant. Its data
   * vanish on rigid motions (they are P1), so the problem is solvable
   * without the traction densities of the element equilibration; and since
   * the phi_i are a partition of unity,
   *
   *   sigma^ = sigma_h + sum_i K eps(z_i)
   *
   * satisfies int sigma^ : eps(v) = int f_d . v + int_G2 F_d . v +
   * int_GC R^ . v for all v of the global space of that degree (the
   * equilibrium [2] in that weak sense; exactly statically admissible when
   * the local problems are solved exactly). The tractions of sigma^ on the
   * element edges are polynomials of degree p + k - 1 instead of the linear
   * densities of the EET, which is what brings the effectivity closer to
   * one (doc/estimator.md).
   *
   * The patch problems are solved with deal.II's Lagrange elements on
   * triangles and tetrahedra alike (compute_lagrange_star_patch(): FE_SimplexP
   * of degree "Local degree" on the cells around vertex i, zero at the nodes
   * of the Dirichlet components, one dense Cholesky factor per patch); then,
   * per cell, ||sigma^ -/+ K eps(U^)||^2_E, the terms of e [14].
   */
  template <int dim>
  class StarPatchEquilibration : public StressReconstruction<dim>
  {
  public:
    /// Section Error estimator/Star patch: "Local degree".
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read section Error estimator/Star patch; throws InputError for a
    /// degree the elements do not reach.
    void
    parse_parameters(ParameterHandler &prm);

    /// The steps above; see StressReconstruction::compute().
    void
    compute(const EquilibrationInput<dim> &input,
            const LA::Vector              &admissible_displacement,
            Vector<double>                &error_squared,
            Vector<double>                &sum_squared) override;

    /// The finite element equilibrium R(phi_i e_c) = 0 of the input.
    std::string
    condition() const override;

  private:
    /// The degree of the patch problems (its default until
    /// parse_parameters()).
    unsigned int local_degree = 2;
  };
} // namespace Signorini

#endif
