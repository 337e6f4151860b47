#ifndef signorini_estimator_element_equilibration_h
#define signorini_estimator_element_equilibration_h

#include <signorini/estimator/density_enhancement.h>
#include <signorini/estimator/stress_reconstruction.h>

namespace Signorini
{
  /**
   * The element equilibration technique of Ladeveze and Pelle ([LAD 91], the
   * paper's "construction classique" of section 5; doc/theory.md section 7)
   * for P1 triangles. compute() runs its steps:
   *
   * 0. per cell, sigma_h, eps(U^) and the loads of the prolongation
   *    condition; per edge, its geometry and the projections the boundary
   *    data give (F_d on loaded edges, R^ on GC);
   * 1. traction densities F^_E, linear on every edge, with F^_E + F^_E' = 0
   *    on interior edges, F^ = F_d on loaded edges, F^ = R^ on GC, free on
   *    the Dirichlet part, satisfying the prolongation condition
   *      int_dE F^_E . phi_i = int_E sigma_h : eps(phi_i) - int_E f_d . phi_i
   *    for every vertex function phi_i of E. For each vertex and component
   *    this is a small system for the edge projections b_G(i) =
   *    int_G F^ phi_i; among its solutions the one closest (least squares)
   *    to the projections of the averaged finite element tractions is taken
   *    (a one-parameter family at interior vertices). The two projections of
   *    an edge then give its linear density. Optionally the free parameters
   *    minimise the error measure instead;
   * 2. sigma^ = K eps(v) on each element from the Neumann problem with data
   *    (f_d, F^_E) in complete polynomials of degree "Local degree" (p + k),
   *    rigid motions removed from the basis: in equilibrium [2] with the
   *    loads and R^ on each element;
   * 3. per element ||sigma^ -/+ K eps(U^)||^2_E, the terms of e [14], eps
   *    [9] and eps_E [10].
   *
   * Meshes with hanging nodes are not supported (the adaptation builds
   * conforming meshes).
   *
   * On tetrahedra the same steps are those of
   * compute_simplex_element_equilibration(): enhanced densities
   * preconditioned by edge patches and Johnson-Krizek-Mercier fields (or
   * displacement element problems); the minimised densities are written for
   * triangles and refused there by name.
   */
  template <int dim>
  class ElementEquilibration : public StressReconstruction<dim>
  {
  public:
    /// The choice of the free parameters of the traction densities
    /// ("Traction densities").
    enum class TractionDensities
    {
      least_squares,
      minimised,
      enhanced
    };

    /// How sigma^ is built on each element from its densities ("Element
    /// stress").
    enum class ElementStress
    {
      displacement,
      equilibrated
    };

    /// Section Error estimator/Element equilibration: "Local degree",
    /// "Traction densities", "Element stress" and the enhancement's.
    static void
    declare_parameters(ParameterHandler &prm);

    /**
     * Read section Error estimator/Element equilibration; throws InputError
     * for a combination the implementation does not cover.
     *
     * With "Traction densities = minimised" the free parameters of the
     * patch systems are not chosen by least squares towards the averaged FE
     * tractions but so as to minimise sum_E ||sigma^ - K eps(U^)||^2_E over
     * all of them (one global, sparse, symmetric positive semi-definite
     * system solved by CG); the equilibrium and prolongation conditions hold
     * either way.
     */
    void
    parse_parameters(ParameterHandler &prm);

    /// The steps 0 to 3 above; see StressReconstruction::compute().
    void
    compute(const EquilibrationInput<dim> &input,
            const LA::Vector              &admissible_displacement,
            Vector<double>                &error_squared,
            Vector<double>                &sum_squared) override;

    /// The prolongation condition.
    std::string
    condition() const override;

  private:
    // (the defaults of the parameters until parse_parameters())
    /// p + k, the degree of the element problems.
    unsigned int local_degree = 3;
    /// How the free parameters of the densities are chosen: least squares,
    /// or minimising the error ("Traction densities = minimised").
    TractionDensities traction_densities = TractionDensities::enhanced;
    /// How sigma^ is built on each element ("Element stress").
    ElementStress element_stress = ElementStress::equilibrated;
    /// The iterations of the enhanced densities ("Enhancement iterations").
    unsigned int enhancement_iterations = (dim == 2) ? 50 : 300;
    /// Its stopping tolerance ("Enhancement tolerance").
    double enhancement_tolerance = (dim == 2) ? 1e-4 : 1e-7;
    /// The regions its preconditioner solves at once ("Enhancement regions",
    /// "Enhancement region rings").
    DensityEnhancement::RegionSettings enhancement_regions{3, 6};
    /// Whether triangles are computed by compute_on_simplices() too
    /// ("Simplex implementation").
    bool simplex_implementation = false;

    /// The steps with compute_simplex_element_equilibration() (tetrahedra,
    /// and triangles with "Simplex implementation").
    void
    compute_on_simplices(const EquilibrationInput<dim> &input,
                         const LA::Vector              &admissible_displacement,
                         Vector<double>                &error_squared,
                         Vector<double>                &sum_squared);
  };

  /// In 3D: compute_simplex_element_equilibration().
  template <>
  void
  ElementEquilibration<3>::compute(const EquilibrationInput<3> &input,
                                   const LA::Vector &admissible_displacement,
                                   Vector<double>   &error_squared,
                                   Vector<double>   &sum_squared);
} // namespace Signorini

#endif
