#ifndef signorini_estimator_johnson_mercier_element_h
#define signorini_estimator_johnson_mercier_element_h

#include <deal.II/base/array_view.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <signorini/material.h>

#include <array>

namespace Signorini
{
  using namespace dealii;

  /**
   * The Johnson-Mercier macro-element (C. Johnson, B. Mercier, "Some
   * equilibrium finite element methods for two-dimensional elasticity
   * problems", Numer. Math. 30 (1978) 103-116): a statically admissible,
   * i.e. exactly equilibrated, stress field on one triangle E from the
   * linear traction densities on its edges and a body force constant on
   * each sub-triangle of its split.
   *
   * The triangle E with vertices x0, x1, x2 is split at its centroid g into
   * the three sub-triangles T_e = (g, x_e, x_{e+1 mod 3}), e = 0, 1, 2, so
   * that T_e carries the macro-edge e (from x_e to x_{e+1}). The space:
   * symmetric 2x2 stress fields, linear on each T_e, with continuous normal
   * traction sigma n across the three internal edges g-x_k. Its
   * coefficients are the values (xx, yy, xy) of the field of T_e at the
   * sub-triangle's vertices g, x_e, x_{e+1} (local nodes j = 0, 1, 2):
   *
   *   coefficient 9 e + 3 j + c,   c = 0: sigma_xx, 1: sigma_yy, 2: sigma_xy
   *
   * (coefficient_index()); the field is discontinuous, so g carries three
   * values and x_k two (one in T_k, one in T_{k-1}).
   *
   * The data: the traction t = sigma n on each macro-edge e (n the unit
   * normal pointing out of E), linear along the edge, given by its values at
   * x_e (k = 0, "start") and x_{e+1} (k = 1, "end"), as the 12 numbers
   *
   *   traction 4 e + 2 k + c,   c the component (traction_index()),
   *
   * and a body force f, constant on each sub-triangle: f_e on T_e
   * (BodyForce). The constraints on the 27 coefficients, 30 equations
   * (constraint_matrix() for their order and scaling):
   *   - 12: continuity of sigma n across each internal edge g-x_k, at g and
   *     at x_k (both sides are linear on that edge);
   *   - 12: sigma n = t at both ends of each macro-edge;
   *   - 6: div sigma + f_e = 0 on each T_e (div of a linear field is
   *     constant), scaled by the length rho = |E| / diam(E) (half the
   *     smallest height of E) so that all rows have the dimension of a
   *     stress and entries of at most 1.5 in size whatever the shape (the
   *     sub-triangles have area |E|/3, so |grad lambda| <= 1.5 diam(E) /
   *     |E|): scaling by diam(E) instead gives condition numbers 100 times
   *     larger on triangles of aspect ratio 100.
   * The matrix has full column rank 27: a field without data is
   * divergence-free, so sigma = curl curl phi with phi an Airy function
   * that is C^1 and piecewise cubic on the split (the Hsieh-Clough-Tocher
   * element) modulo affine functions, whose traction free boundary gives
   * phi = d phi / dn = 0 on the boundary of E, and all 12 HCT degrees of
   * freedom lie there: phi = 0. The range has dimension 27 of 30: its
   * orthogonal complement is the 3 equilibrium conditions (resultant and
   * moment of t and f), so for data in equilibrium the field exists and is
   * unique. (The count: the space has dimension 27 - 12 = 15, its
   * divergence-free part 9 = 12 HCT functions - 3 affine ones, as many as
   * the equilibrated tractions 12 - 3, and the divergence fills the other 6,
   * the piecewise constants.)
   *
   * response() gives the maps from the data to that field for one triangle,
   * computed by one Householder QR of the (scaled) 30 x 27 constraint
   * matrix, its rows and columns ordered vertex by vertex so that the
   * zeros are skipped (about 7 microseconds per triangle, -O2); for data
   * not in equilibrium they give the least-squares solution of the scaled
   * constraints (the maps are the pseudo-inverse, hence linear on all
   * data). The condition number of the scaled constraints is ~10 on well
   * shaped triangles (~200 with angles of 143, 27 and 10 degrees) and grows
   * like 5 (diam(E)^2 / |E|)^2 on flat ones, the relative accuracy of the field
   * being about 1e-16 times that; triangles with |E| < 1e-6 diam(E)^2 are
   * refused. The class holds no mutable state: response() may be called
   * concurrently from any number of threads.
   */
  class JohnsonMercierElement
  {
  public:
    static constexpr unsigned int n_coefficients    = 27;
    static constexpr unsigned int n_traction_values = 12;
    static constexpr unsigned int n_constraints     = 30;

    /// A body force constant on each sub-triangle: f_e on T_e.
    using BodyForce = std::array<Tensor<1, 2>, 3>;

    /// Coefficient of component @p c (0 xx, 1 yy, 2 xy) of the field of
    /// sub-triangle @p e at its local node @p j (0 g, 1 x_e, 2 x_{e+1}).
    static constexpr unsigned int
    coefficient_index(const unsigned int e,
                      const unsigned int j,
                      const unsigned int c)
    {
      return 9 * e + 3 * j + c;
    }

    /// Traction value of component @p c at end @p k (0: x_e, 1: x_{e+1}) of
    /// macro-edge @p e.
    static constexpr unsigned int
    traction_index(const unsigned int e,
                   const unsigned int k,
                   const unsigned int c)
    {
      return 4 * e + 2 * k + c;
    }

    /**
     * @p compliance: K^-1 as a symmetric 3x3 matrix S on the Voigt vector
     * s = (s_xx, s_yy, s_xy) of the TENSOR components (no factor 2 on the
     * shear stress) such that
     *
     *   sigma : K^-1 tau = s^T S t,
     *
     * i.e. S = diag(1, 1, 2) J where J maps s to the tensor components
     * (e_xx, e_yy, e_xy) of the strain K^-1 sigma (the factor 2 counts e_xy
     * and e_yx in the double contraction). For isotropic plane strain
     * S = (1 + nu) / E [[1 - nu, -nu, 0], [-nu, 1 - nu, 0], [0, 0, 2]].
     */
    explicit JohnsonMercierElement(const FullMatrix<double> &compliance);

    /// The compliance matrix S of the constructor for @p material, built by
    /// inverting the map eps -> material.stress(eps) on the Voigt vectors.
    static FullMatrix<double>
    compliance_matrix(const LinearElasticMaterial<2> &material);

    struct Response
    {
      /// 27 x 12: the stress coefficients per unit traction value (column
      /// traction_index(e, k, c)).
      FullMatrix<double> stress_of_traction;
      /// 27 x 6: the stress coefficients per unit body force component
      /// (column 2 e + i: component i of f_e).
      FullMatrix<double> stress_of_body_force;
      /// 27 x 27 symmetric: int_E sigma : K^-1 tau over the coefficient
      /// vectors (exact P1 mass matrices of the sub-triangles, each of area
      /// |E|/3, times the compliance; block diagonal per sub-triangle).
      FullMatrix<double> energy;
    };

    /**
     * The linear maps of the triangle with @p vertices (either orientation):
     * coefficients = stress_of_traction t + stress_of_body_force f is the
     * unique field of the space with sigma n = t on the boundary and
     * div sigma + f = 0 when (t, f) are in equilibrium; otherwise the
     * least-squares solution of the scaled constraints. Throws for a
     * degenerate triangle (|E| < 1e-6 diam(E)^2).
     */
    Response
    response(const std::array<Point<2>, 3> &vertices) const;

    /**
     * What the fast path below needs of one triangle: its affine map
     * x = x0 + F x^ from the reference triangle x^0 = (0, 0), x^1 = (1, 0),
     * x^2 = (0, 1) (vertex k onto vertex k, so edge e onto edge e and the
     * split onto the split) and the double Piola transform
     * sigma = F sigma^ F^T / |det F|. That transform maps the space onto
     * itself, the normal tractions of every edge by sigma n ds =
     * F sigma^ n^ ds^ and the divergence by div sigma = F div^ sigma^ /
     * |det F|: the field of data (t, f) is the transform of the field of the
     * reference data t^ = (L_e / L^_e) F^-1 t on edge e and f^ = |det F|
     * F^-1 f, which is unique for data in equilibrium. The reference maps
     * are computed once (constructor), so an element costs a few small
     * products instead of a QR factorisation.
     */
    struct AffineMap
    {
      /// F^-1.
      Tensor<2, 2> inverse_jacobian;
      /// |E| = |det F| / 2.
      double area;
      /// |det F| F^-1, the map of the body force.
      Tensor<2, 2> body_force_map;
      /// L_e / L^_e for the edges e = 0, 1, 2.
      std::array<double, 3> length_ratio;
      /// The Voigt matrix (row major; xx, yy, xy) of sigma^ -> F sigma^ F^T /
      /// |det F|.
      std::array<double, 9> piola;
    };

    /// The map of the triangle with @p vertices (either orientation). Throws
    /// for a degenerate triangle, as response() does.
    static AffineMap
    affine_map(const std::array<Point<2>, 3> &vertices);

    /**
     * The field (27 coefficients) of the data @p traction (12 values, in
     * traction_index() order) and @p body_force on the triangle of @p map,
     * from the reference maps: equal to response() up to round-off for data
     * in equilibrium; for other data the transform of the least-squares
     * field of the reference triangle (which may differ from response()'s
     * by the size of the defect).
     */
    std::array<double, n_coefficients>
    field(const AffineMap                             &map,
          const std::array<double, n_traction_values> &traction,
          const BodyForce                             &body_force) const;

    /// int_E sigma : K^-1 sigma for the coefficients @p x on the triangle
    /// of @p map (x^T W x with W = Response::energy).
    double
    energy(const AffineMap                          &map,
           const std::array<double, n_coefficients> &x) const;

    /**
     * The quadratic of the field in its traction values, for the triangle
     * of @p map: @p hessian (12 x 12) = R^T W R with R the map of the
     * tractions to the coefficients (Response::stress_of_traction up to its
     * action on data not in equilibrium) and @p gradient (12) = R^T W @p x.
     */
    void
    traction_quadratic(const AffineMap                          &map,
                       const std::array<double, n_coefficients> &x,
                       FullMatrix<double>                       &hessian,
                       Vector<double> &gradient) const;

    /// The coefficient vector (27) of the constant stress @p stress.
    static Vector<double>
    coefficients_of(const SymmetricTensor<2, 2> &stress);

    /// The field of sub-triangle @p e at the point @p p (the linear
    /// interpolation of its three nodal values; @p p need not lie in T_e).
    static SymmetricTensor<2, 2>
    value(const std::array<Point<2>, 3> &vertices,
          const Vector<double>          &coefficients,
          const unsigned int             e,
          const Point<2>                &p);

    /**
     * The scaled 30 x 27 constraint matrix C, rows:
     *   4 k + 2 p + i       (0-11): component i of (sigma_{T_k} -
     *     sigma_{T_{k-1}}) m_k at p = 0: g, p = 1: x_k, with m_k the unit
     *     normal of the internal edge g-x_k (rotation of x_k - g by +90
     *     degrees);
     *   12 + 4 e + 2 k + c  (12-23): component c of sigma_{T_e} n_e at end k
     *     of macro-edge e (the data: traction_index(e, k, c));
     *   24 + 2 e + i        (24-29): rho (div sigma_{T_e})_i (the data:
     *     -rho (f_e)_i), rho = |E| / diam(E).
     */
    static FullMatrix<double>
    constraint_matrix(const std::array<Point<2>, 3> &vertices);

    /// The right-hand side (30) of the constraints of constraint_matrix() for
    /// the data @p traction (12) and @p body_force.
    static Vector<double>
    constraint_rhs(const std::array<Point<2>, 3> &vertices,
                   const Vector<double>          &traction,
                   const BodyForce               &body_force);

    /**
     * The largest residual of the 30 constraints (rows scaled as in
     * constraint_matrix()) for @p coefficients and the data, relative to the
     * size of the data and of the field: max_r |(C x - b)_r| /
     * max(|t|_inf, rho |f|_inf, |x|_inf), zero if all of them vanish.
     * Round-off (~1e-16 times the condition number of C: ~10 on well shaped
     * triangles, growing like the square of the aspect ratio) for the
     * response to equilibrated data.
     */
    double
    constraint_defect(const std::array<Point<2>, 3> &vertices,
                      const ArrayView<const double> &coefficients,
                      const ArrayView<const double> &traction,
                      const BodyForce               &body_force) const;

  private:
    /// S, row major
    std::array<double, 9> compliance;
    /// The maps of response() on the reference triangle, row major:
    /// coefficients per unit traction value (27 x 12) and per unit body
    /// force component (27 x 6).
    std::array<double, n_coefficients * n_traction_values>
                                           reference_stress_of_traction;
    std::array<double, n_coefficients * 6> reference_stress_of_body_force;
    /**
     * G_ab = R^^T (M^ (x) E_ab) R^ (12 x 12, row major) for the six pairs
     * a <= b of Voigt components (xx, yy, xy; order 00, 11, 22, 01, 02, 12),
     * R^ the reference map of the tractions, M^ the pattern [2 1 1; 1 2 1;
     * 1 1 2] of the P1 mass matrix of a sub-triangle and E_ab the symmetric
     * unit matrix: the Hessian of any triangle is Q^T (sum_ab S^_ab G_ab) Q
     * with S^ its compliance in reference components.
     */
    std::array<std::array<double, n_traction_values * n_traction_values>, 6>
      reference_hessian_parts;
  };
} // namespace Signorini

#endif
