#ifndef signorini_estimator_lagrange_star_patch_h
#define signorini_estimator_lagrange_star_patch_h

#include <deal.II/lac/vector.h>

#include <signorini/estimator/stress_reconstruction.h>
#include <signorini/linear_algebra.h>

namespace Signorini
{
  using namespace dealii;

  /// What compute_lagrange_star_patch() measured.
  struct StarPatchDefects
  {
    /// Largest relative residual of a patch problem (its solution error).
    double equilibrium = 0.;
    /// Largest defect of the finite element equilibrium R(phi_i e_c) = 0
    /// of the input, over the free components of the patches' vertices,
    /// relative to galerkin_scale (once computed).
    double galerkin = 0.;
    /// The largest sum of the absolute values of the terms of an
    /// R(phi_i e_c).
    double galerkin_scale = 0.;
  };

  /**
   * The star-patch construction of StarPatchEquilibration (the patch
   * problems find z_i in V_i: int K eps(z_i) : eps(v) = R(phi_i (v - Pi_h v))
   * and sigma^ = sigma_h + sum_i K eps(z_i)), written with deal.II's
   * Lagrange elements for triangles and tetrahedra alike: V_i is FE_SimplexP
   * of degree @p degree on the cells around vertex i, zero at the nodes of
   * the Dirichlet components. Each patch matrix is assembled from the cells
   * and factorised densely (a Cholesky factor, after the rigid motions the
   * Dirichlet nodes leave free, on which the data vanish, are made definite
   * without changing the solution).
   *
   * Fills @p error_squared and @p sum_squared as
   * StressReconstruction::compute() does (the cells this rank owns), on a
   * conforming mesh held whole by every rank.
   */
  template <int dim>
  StarPatchDefects
  compute_lagrange_star_patch(const EquilibrationInput<dim> &input,
                              const LA::Vector  &admissible_displacement,
                              const unsigned int degree,
                              Vector<double>    &error_squared,
                              Vector<double>    &sum_squared);
} // namespace Signorini

#endif
