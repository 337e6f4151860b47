#ifndef signorini_estimator_johnson_krizek_mercier_element_h
#define signorini_estimator_johnson_krizek_mercier_element_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <signorini/material.h>

#include <array>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The Johnson-Krizek-Mercier macro-element on a triangle or a tetrahedron
   * (Johnson and Mercier, Numer. Math. 30, 1978, for triangles; Krizek,
   * Aplikace Matematiky 27, 1982, for tetrahedra; Gopalakrishnan, Guzman and
   * Lee, "The Johnson-Krizek-Mercier elasticity element in higher
   * dimensions", arXiv 2403.13189, for any dimension): a statically
   * admissible, i.e. exactly equilibrated, stress field on one simplex E
   * from linear tractions on its faces and a body force constant on each
   * sub-simplex of its split.
   *
   * The split (Alfeld): E with vertices x_0 ... x_d is cut at its centroid
   * g into the d + 1 sub-simplices T_s, T_s having the vertices of E with
   * x_s replaced by g; T_s carries the face F_s of E opposite x_s. The
   * space: symmetric stresses, linear on each T_s, with continuous normal
   * traction across the interior faces. The coefficients are the nodal
   * values of each T_s: node j of T_s is x_j, or g for j = s
   * (coefficient_index()). The data: the traction t = sigma n on each face
   * F_s (n the outward unit normal), linear, by its values at the vertices
   * x_j, j != s (traction_index()), and a body force f_s constant on each
   * T_s. The constraints: continuity of sigma n at the nodes of each
   * interior face, sigma n = t at the nodes of each face of E, div sigma +
   * f_s = 0 on each T_s.
   *
   * Dimensions: d = 2: 27 coefficients, 12 continuity conditions, a space
   * of dimension 15 = 12 traction values + 6 divergence values - 3
   * equilibrium conditions; d = 3: 96 coefficients, 54 continuity
   * conditions, dimension 42 = 36 + 12 - 6. In both the data map to the
   * space is one to one (the constructor checks it): for data in
   * equilibrium (zero resultant and moment of t and f) the field exists and
   * is unique, for other data the class gives the least-squares field.
   *
   * The computation: once on the reference simplex x^_0 = 0, x^_k = e_k,
   * the maps from the data to the field (the pseudo-inverse of the
   * constraints). On E, x = x_0 + B x^ maps the split onto the split, and
   * the double Piola transform sigma = B sigma^ B^T / |det B| maps the
   * space onto itself, the tractions by sigma n ds = B sigma^ n^ ds^ and
   * the divergence by div sigma = B div^ sigma^ / |det B|: the field of
   * (t, f) is the transform of the reference field of t^ = (|F_s| / |F^_s|)
   * B^-1 t and f^ = |det B| B^-1 f. An element costs a few small products.
   * The class holds no mutable state: its functions may be called
   * concurrently.
   */
  template <int dim>
  class JohnsonKrizekMercierElement
  {
  public:
    static constexpr unsigned int n_vertices = dim + 1;
    /// Independent components of a symmetric tensor (SymmetricTensor's
    /// unrolled order).
    static constexpr unsigned int n_components =
      SymmetricTensor<2, dim>::n_independent_components;
    /// (sub-simplex, node) pairs.
    static constexpr unsigned int n_nodes        = n_vertices * n_vertices;
    static constexpr unsigned int n_coefficients = n_nodes * n_components;
    /// Faces x corners x components.
    static constexpr unsigned int n_traction_values = n_vertices * dim * dim;

    /// Node @p j of sub-simplex @p s (x_j, or g for j == s).
    static constexpr unsigned int
    node_index(const unsigned int s, const unsigned int j)
    {
      return s * n_vertices + j;
    }

    /// Coefficient of component @p c (unrolled) at node @p j of T_s.
    static constexpr unsigned int
    coefficient_index(const unsigned int s,
                      const unsigned int j,
                      const unsigned int c)
    {
      return node_index(s, j) * n_components + c;
    }

    /// Traction value of component @p c at vertex x_j (j != s) of the face
    /// F_s opposite x_s.
    static constexpr unsigned int
    traction_index(const unsigned int s,
                   const unsigned int j,
                   const unsigned int c)
    {
      return (s * dim + (j < s ? j : j - 1)) * dim + c;
    }

    /// The tractions, by traction_index() / dim (the vector at a corner).
    using Traction = std::array<Tensor<1, dim>, n_vertices * dim>;
    /// The body force f_s on each T_s.
    using BodyForce = std::array<Tensor<1, dim>, n_vertices>;
    /// The nodal values, by node_index().
    using Field = std::array<SymmetricTensor<2, dim>, n_nodes>;

    /// The affine map of one simplex from the reference one.
    struct Geometry
    {
      /// The vertices (either orientation).
      std::array<Point<dim>, n_vertices> vertices;
      /// B, B^-1, |det B|.
      Tensor<2, dim> jacobian, inverse_jacobian;
      double         determinant;
      /// |E|, the diameter, the centroid g.
      double     measure, diameter;
      Point<dim> centroid;
      /// |F_s| / |F^_s|, and the outward unit normal of F_s.
      std::array<double, n_vertices>         face_ratio;
      std::array<Tensor<1, dim>, n_vertices> normal;
    };

    /**
     * The geometry of the simplex with @p vertices. Throws for a simplex
     * too flat for a reliable field (|E| < 1e-6 diam(E)^d, where the
     * condition of the constraints has lost some twelve digits).
     */
    static Geometry
    geometry(const std::array<Point<dim>, n_vertices> &vertices);

    /// The reference maps, and the compliance K^-1 of @p material.
    explicit JohnsonKrizekMercierElement(
      const LinearElasticMaterial<dim> &material);

    /// The field of the data (@p traction, @p body_force) on the simplex of
    /// @p geometry.
    Field
    field(const Geometry  &geometry,
          const Traction  &traction,
          const BodyForce &body_force) const;

    /// The field of sub-simplex @p s at @p point (the linear interpolation of
    /// its nodal values; @p point need not lie in T_s).
    static SymmetricTensor<2, dim>
    value(const Geometry    &geometry,
          const Field       &field,
          const unsigned int s,
          const Point<dim>  &point);

    /// int_E (sigma - tau) : K^-1 (sigma - tau) for the field @p field and
    /// the constant stress @p tau (exact: P1 mass matrices of the T_s).
    double
    energy(const Geometry                &geometry,
           const Field                   &field,
           const SymmetricTensor<2, dim> &tau) const;

    /// A vector of traction values, and a matrix on them (row major).
    using TractionVector = std::array<double, n_traction_values>;
    using TractionMatrix =
      std::array<double, n_traction_values * n_traction_values>;

    /**
     * The energy of energy() as a quadratic function of the traction values
     * t (traction_index() order) for the body force @p body_force and the
     * constant stress @p tau: t^T H t + 2 g^T t + c. hessian() gives H,
     * linear_part() g and c.
     */
    TractionMatrix
    hessian(const Geometry &geometry) const;

    /// g and c of hessian()'s quadratic.
    std::pair<TractionVector, double>
    linear_part(const Geometry                &geometry,
                const BodyForce               &body_force,
                const SymmetricTensor<2, dim> &tau) const;

    /**
     * The body force, constant on each T_s, of least L2 distance to the
     * mean @p resultant / |E| whose resultant is @p resultant and whose
     * moments are @p moments: moments[k] = int_E f . (S_k (x - g)), S_k the
     * k-th infinitesimal rotation (2D: (x, y) -> (-y, x); 3D: x -> e_k x
     * x). f_d itself where f_d is constant on E.
     */
    static BodyForce
    balanced_body_force(
      const Geometry                                  &geometry,
      const Tensor<1, dim>                            &resultant,
      const std::array<double, (dim * (dim - 1)) / 2> &moments);

    /// The infinitesimal rotation S_k v of balanced_body_force().
    static Tensor<1, dim>
    rotation(const unsigned int k, const Tensor<1, dim> &v);

    /**
     * The largest defect of the constraints of @p field for the data,
     * computed on E itself (not through the reference maps): the jumps of
     * sigma n at the nodes of the interior faces, sigma n - t at the nodes
     * of the faces and rho (div sigma + f) on the sub-simplices (rho = |E|
     * / max |F_s|), relative to the largest of |t|, rho |f| and |sigma|
     * (zero if all vanish). Round-off for data in equilibrium.
     */
    static double
    constraint_defect(const Geometry  &geometry,
                      const Field     &field,
                      const Traction  &traction,
                      const BodyForce &body_force);

  private:
    /// Reference coefficients, and a matrix on unrolled components (row
    /// major).
    using Coefficients    = std::array<double, n_coefficients>;
    using ComponentMatrix = std::array<double, n_components * n_components>;

    /// The reference maps (row major): the coefficients of sigma^ per unit
    /// reference traction value (n_coefficients x n_traction_values) and per
    /// unit reference body force component (n_coefficients x n_vertices
    /// dim).
    std::vector<double> traction_map, body_force_map;
    /**
     * P_t^T (M^ (x) E_ab) P_t for the pairs a <= b of components, P_t =
     * traction_map, M^ the P1 mass matrices of the reference sub-simplices
     * and E_ab the symmetric unit matrix: H of a simplex is T^T (sum_ab C^_ab
     * G_ab) T / |det B|, C^ its compliance in reference components.
     */
    std::vector<TractionMatrix> hessian_parts;
    /// K^-1 on unrolled components: sigma : K^-1 tau = s^T S t.
    ComponentMatrix compliance;

    /// C^ = Pi^T S Pi (Pi: sigma^ -> B sigma^ B^T on unrolled components).
    ComponentMatrix
    reference_compliance(const Geometry &geometry) const;

    /// The reference coefficients of a field from reference data.
    Coefficients
    reference_coefficients(const Geometry  &geometry,
                           const Traction  &traction,
                           const BodyForce &body_force) const;

    /// M^ (x) C applied to reference coefficients @p x.
    Coefficients
    weighted(const ComponentMatrix &compliance, const Coefficients &x) const;
  };
} // namespace Signorini

#endif
