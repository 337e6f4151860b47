#ifndef signorini_estimator_simplex_element_equilibration_h
#define signorini_estimator_simplex_element_equilibration_h

#include <deal.II/lac/vector.h>

#include <signorini/estimator/stress_reconstruction.h>
#include <signorini/linear_algebra.h>

namespace Signorini
{
  using namespace dealii;

  /// How compute_simplex_element_equilibration() builds sigma^.
  struct SimplexEquilibrationSettings
  {
    /// p + k, the degree of the element problems (2 to 4 on triangles, 3 or
    /// 4 on tetrahedra, where degree 2 leaves some linear face densities
    /// without work).
    unsigned int degree = 3;
    /// Largest number of conjugate gradient iterations of the enhancement
    /// (0: the classical densities).
    unsigned int max_iterations = 50;
    /// Stop when an iteration decreases J by at most this fraction of the
    /// decrease so far.
    double tolerance = 1e-4;
    /// sigma^_E the Johnson-Krizek-Mercier field of the element's data
    /// (exactly statically admissible: e is a guaranteed bound) instead of
    /// the stress of its displacement problem.
    bool equilibrated_fields = true;
  };

  /// What compute_simplex_element_equilibration() measured.
  struct SimplexEquilibrationChecks
  {
    /// Largest relative defect of the prolongation condition of the
    /// classical densities (round-off if correct).
    double prolongation = 0.;
    /// Largest relative defect of the equilibrium (resultant and moment) of
    /// the data of an element problem, and with equilibrated fields of
    /// their constraints (JohnsonKrizekMercierElement::constraint_defect();
    /// round-off if correct).
    double equilibrium = 0.;
    /// The decrease of J = 1/2 sum_E ||sigma^_E - K eps(U^)||^2 in each
    /// iteration of the enhancement (positive).
    std::vector<double> measure;
    /// The wall seconds of the steps on this rank, in order.
    std::vector<std::pair<std::string, double>> seconds;
  };

  /**
   * The element equilibration technique with enhanced densities on triangles
   * and tetrahedra alike (doc/estimator.md), the construction "element
   * equilibration" uses on tetrahedra:
   *
   * 1. classical traction densities, linear on every face, from the
   *    prolongation condition int_dE F^_E phi_i = int_E sigma_h : eps(phi_i)
   *    - int_E f_d phi_i (one small system per vertex and component, its
   *    least squares solution towards the averaged finite element tractions;
   *    F^ = F_d on loaded faces, R^ on GC, free on the Dirichlet
   *    components);
   * 2. sigma^_E, a quadratic function of the element's densities: with
   *    settings.equilibrated_fields the Johnson-Krizek-Mercier field of the
   *    element's data (JohnsonKrizekMercierElement: div sigma^ + f~ = 0
   *    and sigma^ n = F^ exactly, f~ constant on each sub-simplex with the
   *    resultant and moment of f_d), otherwise K eps(v) from the Neumann
   *    problem of each element with its data, in complete polynomials of
   *    degree settings.degree (rigid motions removed);
   * 3. the enhancement (weak prolongation condition, Pled, Chamoin and
   *    Ladeveze 2012): the densities re-chosen to minimise
   *    J = 1/2 sum_E ||sigma^_E - K eps(U^)||^2 under the equilibrium of
   *    each element alone, by conjugate gradients in the changes that keep
   *    every element in equilibrium, preconditioned by the patches around
   *    the entities of dimension dim - 2 (vertices in 2D, edges in 3D: each
   *    patch re-chooses all nodal values of the faces through its entity
   *    under the equilibrium of its cells). sigma^ is statically admissible
   *    after any number of iterations. Each patch is computed by one rank
   *    and every density value sums its contributions in a fixed order: the
   *    result does not depend on the numbers of ranks and threads;
   * 4. the terms of e [14] per element.
   *
   * Fills @p error_squared and @p sum_squared as
   * StressReconstruction::compute() does (the cells this rank owns), on a
   * conforming mesh held whole by every rank.
   */
  template <int dim>
  SimplexEquilibrationChecks
  compute_simplex_element_equilibration(
    const EquilibrationInput<dim>      &input,
    const LA::Vector                   &admissible_displacement,
    const SimplexEquilibrationSettings &settings,
    Vector<double>                     &error_squared,
    Vector<double>                     &sum_squared);
} // namespace Signorini

#endif
