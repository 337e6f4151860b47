#ifndef signorini_estimator_star_patch_equilibration_h
#define signorini_estimator_star_patch_equilibration_h

#include <signorini/estimator/stress_reconstruction.h>

namespace Signorini
{
  /**
   * The star-patch (flux-free) construction of sigma^ (Cottereau, Diez and
   * Huerta 2009; Pares, Diez and Huerta 2006; called SPET by Pled, Chamoin
   * and Ladeveze 2011; doc/theory.md section 7) for P1 triangles. With
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
   * V_i uses a hierarchical basis (vertex functions lambda_a, edge
   * functions lambda_a lambda_b (lambda_b - lambda_a)^m oriented by the
   * global vertex numbers, interior bubbles): the P1 interpolant of its
   * higher-order functions is zero and that of a vertex function is itself,
   * so the data are R(phi_i psi) on the higher-order functions and zero on
   * the vertex functions.
   *
   * compute() runs the steps: per cell sigma_h, U~_h -/+ U^ and f_d, per
   * boundary edge F_d + R^; the patch problems (on the worker threads); per
   * cell ||sigma^ -/+ K eps(U^)||^2_E, the terms of e [14], eps [9] and
   * eps_E [10].
   *
   * Written out for triangles; on tetrahedra compute() runs the same
   * construction with deal.II's Lagrange elements
   * (compute_lagrange_star_patch(), "Local degree" 2), and so on triangles
   * with "Lagrange elements" = true (a cross-check).
   */
  template <int dim>
  class StarPatchEquilibration : public StressReconstruction<dim>
  {
  public:
    /// compute() is implemented in 2D and 3D.
    static constexpr bool is_implemented = true;

    /// Section Error estimator/Star patch: "Local degree" and "Lagrange
    /// elements".
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
    /// compute() by compute_lagrange_star_patch().
    void
    compute_with_lagrange_elements(const EquilibrationInput<dim> &input,
                                   const LA::Vector &admissible_displacement,
                                   Vector<double>   &error_squared,
                                   Vector<double>   &sum_squared);

    // (the defaults of the parameters until parse_parameters())
    /// The degree of the patch problems.
    unsigned int local_degree = 2;
    /// Whether compute() uses compute_lagrange_star_patch() (always in 3D).
    bool lagrange_elements = (dim == 3);
  };

  /// In 3D: compute_lagrange_star_patch().
  template <>
  void
  StarPatchEquilibration<3>::compute(const EquilibrationInput<3> &input,
                                     const LA::Vector &admissible_displacement,
                                     Vector<double>   &error_squared,
                                     Vector<double>   &sum_squared);
} // namespace Signorini

#endif
