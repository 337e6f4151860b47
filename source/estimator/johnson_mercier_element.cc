#include <deal.II/base/exceptions.h>

#include <signorini/estimator/johnson_mercier_element.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace Signorini
{
  namespace
  {
    constexpr unsigned int n_rows = JohnsonMercierElement::n_constraints;
    constexpr unsigned int n_cols = JohnsonMercierElement::n_coefficients;
    constexpr unsigned int n_rhs = JohnsonMercierElement::n_traction_values + 6;

    /// Refuses the triangles of diameter @p h and area @p area too flat for
    /// a reliable field: the condition number of the constraints is ~5 (h^2
    /// / |E|)^2, beyond ~1e12 the result would carry no digits worth having.
    void
    check_not_degenerate(const double h, const double area)
    {
      AssertThrow(h > 0. && area > 1e-6 * h * h,
                  ExcMessage("a triangle of area < 1e-6 diameter^2 (a sliver) "
                             "has no reliable Johnson-Mercier field: remesh, "
                             "or set Error estimator/Element "
                             "equilibration/Element stress = displacement"));
    }

    /// The reference triangle of JohnsonMercierElement::AffineMap.
    const std::array<Point<2>, 3> reference_vertices = {
      {Point<2>(0., 0.), Point<2>(1., 0.), Point<2>(0., 1.)}};

    /// The Voigt pairs (a, b), a <= b, of reference_hessian_parts.
    constexpr std::array<std::array<unsigned int, 2>, 6> voigt_pairs = {
      {{{0, 0}}, {{1, 1}}, {{2, 2}}, {{0, 1}}, {{0, 2}}, {{1, 2}}}};

    /// The geometry of the split of one triangle.
    struct Split
    {
      std::array<Point<2>, 3> x;
      Point<2>                g;
      /// outward unit normal of macro-edge e
      std::array<Tensor<1, 2>, 3> n;
      /// unit normal of the internal edge g-x_k (x_k - g turned by +90 deg)
      std::array<Tensor<1, 2>, 3> m;
      /// gradients of the barycentric coordinates of T_e at its local nodes
      std::array<std::array<Tensor<1, 2>, 3>, 3> grad;
      /// diameter and area of E
      double h;
      double area;
      /// the length scaling the divergence rows: |E| / h, half the smallest
      /// height of E
      double rho;
    };

    Split
    split(const std::array<Point<2>, 3> &x)
    {
      Split s;
      s.x = x;
      s.g = Point<2>((x[0][0] + x[1][0] + x[2][0]) / 3.,
                     (x[0][1] + x[1][1] + x[2][1]) / 3.);
      s.h = 0.;
      for (unsigned int e = 0; e < 3; ++e)
        s.h = std::max(s.h, x[(e + 1) % 3].distance(x[e]));
      const double twice_signed_area =
        (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) -
        (x[1][1] - x[0][1]) * (x[2][0] - x[0][0]);
      s.area = 0.5 * std::abs(twice_signed_area);
      check_not_degenerate(s.h, s.area);
      s.rho = s.area / s.h;
      // outward: (d_y, -d_x) for counterclockwise vertices
      const double orientation = twice_signed_area > 0. ? 1. : -1.;
      for (unsigned int e = 0; e < 3; ++e)
        {
          const Tensor<1, 2> d      = x[(e + 1) % 3] - x[e];
          const double       length = d.norm();
          s.n[e][0]                 = orientation * d[1] / length;
          s.n[e][1]                 = -orientation * d[0] / length;

          const Tensor<1, 2> r = x[e] - s.g;
          s.m[e][0]            = -r[1] / r.norm();
          s.m[e][1]            = r[0] / r.norm();

          // T_e = (g, x_e, x_{e+1}): grad lambda_j = rot(p_{j+1} - p_{j+2})/D
          const std::array<Point<2>, 3> p = {{s.g, x[e], x[(e + 1) % 3]}};
          const double D = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                           (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
          for (unsigned int j = 0; j < 3; ++j)
            {
              const Point<2> &a = p[(j + 1) % 3], &b = p[(j + 2) % 3];
              s.grad[e][j][0] = (a[1] - b[1]) / D;
              s.grad[e][j][1] = (b[0] - a[0]) / D;
            }
        }
      return s;
    }

    /// The scaled constraint matrix in column-major order: c[j][r] is the
    /// entry of row r and column j (row order of constraint_matrix()).
    using ColumnMajor = std::array<std::array<double, n_rows>, n_cols>;

    /**
     * Visits the nonzero entries of the scaled constraint matrix:
     * @p add(j, r, value) for each contribution to the entry of row r and
     * column j (a row and column may be met more than once: the entries are
     * the sums).
     */
    template <typename AddEntry>
    void
    for_each_constraint_entry(const Split &s, const AddEntry &add)
    {
      using JM = JohnsonMercierElement;
      // component i of sigma n for the node (e, j), coefficient factor
      // sigma n = (s_xx n0 + s_xy n1, s_xy n0 + s_yy n1)
      const auto add_traction = [&add](const unsigned int  row,
                                       const unsigned int  e,
                                       const unsigned int  j,
                                       const Tensor<1, 2> &normal,
                                       const double        sign) {
        add(JM::coefficient_index(e, j, 0), row, sign * normal[0]);
        add(JM::coefficient_index(e, j, 2), row, sign * normal[1]);
        add(JM::coefficient_index(e, j, 2), row + 1, sign * normal[0]);
        add(JM::coefficient_index(e, j, 1), row + 1, sign * normal[1]);
      };
      for (unsigned int k = 0; k < 3; ++k)
        {
          const unsigned int previous = (k + 2) % 3;
          // at g: local node 0 of both; at x_k: node 1 of T_k, 2 of T_{k-1}
          add_traction(4 * k, k, 0, s.m[k], 1.);
          add_traction(4 * k, previous, 0, s.m[k], -1.);
          add_traction(4 * k + 2, k, 1, s.m[k], 1.);
          add_traction(4 * k + 2, previous, 2, s.m[k], -1.);
        }
      for (unsigned int e = 0; e < 3; ++e)
        for (unsigned int k = 0; k < 2; ++k)
          add_traction(12 + JM::traction_index(e, k, 0), e, k + 1, s.n[e], 1.);
      // div sigma = (d_x s_xx + d_y s_xy, d_x s_xy + d_y s_yy)
      for (unsigned int e = 0; e < 3; ++e)
        for (unsigned int j = 0; j < 3; ++j)
          {
            const Tensor<1, 2> &grad = s.grad[e][j];
            const unsigned int  row  = 24 + 2 * e;
            add(JM::coefficient_index(e, j, 0), row, s.rho * grad[0]);
            add(JM::coefficient_index(e, j, 2), row, s.rho * grad[1]);
            add(JM::coefficient_index(e, j, 2), row + 1, s.rho * grad[0]);
            add(JM::coefficient_index(e, j, 1), row + 1, s.rho * grad[1]);
          }
    }

    /// The scaled constraint matrix, assembled.
    void
    assemble(const Split &s, ColumnMajor &c)
    {
      for (auto &column : c)
        column.fill(0.);
      for_each_constraint_entry(s,
                                [&c](const unsigned int j,
                                     const unsigned int r,
                                     const double value) { c[j][r] += value; });
    }



    void
    rhs(const Split                            &s,
        const ArrayView<const double>          &traction,
        const JohnsonMercierElement::BodyForce &body_force,
        std::array<double, n_rows>             &b)
    {
      AssertDimension(traction.size(),
                      JohnsonMercierElement::n_traction_values);
      b.fill(0.);
      for (unsigned int i = 0; i < JohnsonMercierElement::n_traction_values;
           ++i)
        b[12 + i] = traction[i];
      for (unsigned int e = 0; e < 3; ++e)
        for (unsigned int i = 0; i < 2; ++i)
          b[24 + 2 * e + i] = -s.rho * body_force[e][i];
    }

    /**
     * The order in which response() eliminates: the 18 coefficients at the
     * vertices first, x_k's six (T_k at its node 1, T_{k-1} at its node 2)
     * with the six rows at x_k (continuity across g-x_k there, the tractions
     * of edge k at its start and of edge k-1 at its end), which involve no
     * other coefficient; then the 9 coefficients at g with the continuity
     * rows at g; the 6 divergence rows, which couple everything, last.
     * Householder QR in that order fills in only the divergence rows, so
     * that most reflectors are short.
     */
    struct Ordering
    {
      /// new column (row) position -> coefficient (row of
      /// constraint_matrix())
      std::array<unsigned int, n_cols> column;
      std::array<unsigned int, n_rows> row;
      /// row of constraint_matrix() -> new position
      std::array<unsigned int, n_rows> row_position;
    };

    constexpr Ordering
    make_ordering()
    {
      using JM = JohnsonMercierElement;
      Ordering     o{};
      unsigned int c = 0, r = 0;
      for (unsigned int k = 0; k < 3; ++k)
        {
          const unsigned int previous = (k + 2) % 3;
          for (unsigned int i = 0; i < 3; ++i)
            o.column[c++] = JM::coefficient_index(k, 1, i);
          for (unsigned int i = 0; i < 3; ++i)
            o.column[c++] = JM::coefficient_index(previous, 2, i);
          for (unsigned int i = 0; i < 2; ++i)
            o.row[r++] = 4 * k + 2 + i;
          for (unsigned int i = 0; i < 2; ++i)
            o.row[r++] = 12 + JM::traction_index(k, 0, i);
          for (unsigned int i = 0; i < 2; ++i)
            o.row[r++] = 12 + JM::traction_index(previous, 1, i);
        }
      for (unsigned int e = 0; e < 3; ++e)
        for (unsigned int i = 0; i < 3; ++i)
          o.column[c++] = JM::coefficient_index(e, 0, i);
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int i = 0; i < 2; ++i)
          o.row[r++] = 4 * k + i;
      for (unsigned int i = 0; i < 6; ++i)
        o.row[r++] = 24 + i;
      for (unsigned int i = 0; i < n_rows; ++i)
        o.row_position[o.row[i]] = i;
      return o;
    }

    /// computed at compile time: no shared state at run time
    constexpr Ordering order = make_ordering();
  } // namespace



  JohnsonMercierElement::JohnsonMercierElement(
    const FullMatrix<double> &compliance_)
  {
    AssertThrow(compliance_.m() == 3 && compliance_.n() == 3,
                ExcMessage("JohnsonMercierElement: the compliance must be a "
                           "3x3 matrix"));
    double largest = 0.;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        largest = std::max(largest, std::abs(compliance_(i, j)));
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        {
          AssertThrow(std::abs(compliance_(i, j) - compliance_(j, i)) <=
                        1e-12 * largest,
                      ExcMessage("JohnsonMercierElement: the compliance must "
                                 "be symmetric"));
          compliance[3 * i + j] = 0.5 * (compliance_(i, j) + compliance_(j, i));
        }

    const Response reference = response(reference_vertices);
    for (unsigned int i = 0; i < n_coefficients; ++i)
      {
        for (unsigned int t = 0; t < n_traction_values; ++t)
          reference_stress_of_traction[n_traction_values * i + t] =
            reference.stress_of_traction(i, t);
        for (unsigned int d = 0; d < 6; ++d)
          reference_stress_of_body_force[6 * i + d] =
            reference.stress_of_body_force(i, d);
      }
    const auto r = [this](const unsigned int e,
                          const unsigned int j,
                          const unsigned int c,
                          const unsigned int t) {
      return reference_stress_of_traction[n_traction_values *
                                            coefficient_index(e, j, c) +
                                          t];
    };
    for (unsigned int p = 0; p < voigt_pairs.size(); ++p)
      {
        const unsigned int a = voigt_pairs[p][0], b = voigt_pairs[p][1];
        auto              &part = reference_hessian_parts[p];
        part.fill(0.);
        for (unsigned int e = 0; e < 3; ++e)
          for (unsigned int j = 0; j < 3; ++j)
            for (unsigned int l = 0; l < 3; ++l)
              {
                const double mass = (j == l ? 2. : 1.);
                for (unsigned int t = 0; t < n_traction_values; ++t)
                  for (unsigned int u = 0; u < n_traction_values; ++u)
                    part[n_traction_values * t + u] +=
                      mass * (r(e, j, a, t) * r(e, l, b, u) +
                              (a != b ? r(e, j, b, t) * r(e, l, a, u) : 0.));
              }
      }
  }



  JohnsonMercierElement::AffineMap
  JohnsonMercierElement::affine_map(const std::array<Point<2>, 3> &x)
  {
    const Tensor<1, 2>          a = x[1] - x[0], b = x[2] - x[0];
    const double                determinant = a[0] * b[1] - a[1] * b[0];
    const std::array<double, 3> length      = {
           {a.norm(), x[2].distance(x[1]), b.norm()}};
    const std::array<double, 3> reference_length = {{1., std::sqrt(2.), 1.}};
    AffineMap                   map;
    map.area = 0.5 * std::abs(determinant);
    check_not_degenerate(std::max({length[0], length[1], length[2]}), map.area);
    // F = (a b) as columns
    map.inverse_jacobian[0][0] = b[1] / determinant;
    map.inverse_jacobian[0][1] = -b[0] / determinant;
    map.inverse_jacobian[1][0] = -a[1] / determinant;
    map.inverse_jacobian[1][1] = a[0] / determinant;
    map.body_force_map         = std::abs(determinant) * map.inverse_jacobian;
    for (unsigned int e = 0; e < 3; ++e)
      map.length_ratio[e] = length[e] / reference_length[e];
    // (F s F^T)_ij = F_ik s_kl F_jl on the Voigt components (xx, yy, xy)
    const double j = 1. / std::abs(determinant);
    map.piola      = {{j * a[0] * a[0],
                       j * b[0] * b[0],
                       j * 2. * a[0] * b[0],
                       j * a[1] * a[1],
                       j * b[1] * b[1],
                       j * 2. * a[1] * b[1],
                       j * a[0] * a[1],
                       j * b[0] * b[1],
                       j * (a[0] * b[1] + b[0] * a[1])}};
    return map;
  }



  std::array<double, JohnsonMercierElement::n_coefficients>
  JohnsonMercierElement::field(
    const AffineMap                             &map,
    const std::array<double, n_traction_values> &traction,
    const BodyForce                             &body_force) const
  {
    // the reference data
    std::array<double, n_traction_values> reference_traction;
    for (unsigned int e = 0; e < 3; ++e)
      for (unsigned int k = 0; k < 2; ++k)
        for (unsigned int c = 0; c < 2; ++c)
          reference_traction[traction_index(e, k, c)] =
            map.length_ratio[e] *
            (map.inverse_jacobian[c][0] * traction[traction_index(e, k, 0)] +
             map.inverse_jacobian[c][1] * traction[traction_index(e, k, 1)]);
    std::array<double, 6> reference_force;
    for (unsigned int e = 0; e < 3; ++e)
      for (unsigned int i = 0; i < 2; ++i)
        reference_force[2 * e + i] =
          map.body_force_map[i][0] * body_force[e][0] +
          map.body_force_map[i][1] * body_force[e][1];

    // the reference field, then its transform node by node
    std::array<double, n_coefficients> reference_field, x;
    for (unsigned int i = 0; i < n_coefficients; ++i)
      {
        const double *const row =
          &reference_stress_of_traction[n_traction_values * i];
        double value = 0.;
        for (unsigned int d = 0; d < 6; ++d)
          value +=
            reference_stress_of_body_force[6 * i + d] * reference_force[d];
        for (unsigned int t = 0; t < n_traction_values; ++t)
          value += row[t] * reference_traction[t];
        reference_field[i] = value;
      }
    for (unsigned int node = 0; node < 9; ++node)
      for (unsigned int r = 0; r < 3; ++r)
        x[3 * node + r] = map.piola[3 * r] * reference_field[3 * node] +
                          map.piola[3 * r + 1] * reference_field[3 * node + 1] +
                          map.piola[3 * r + 2] * reference_field[3 * node + 2];
    return x;
  }



  double
  JohnsonMercierElement::energy(
    const AffineMap                          &map,
    const std::array<double, n_coefficients> &x) const
  {
    // W = |E| / 36 [2 1 1; 1 2 1; 1 1 2] (x) S per sub-triangle
    double result = 0.;
    for (unsigned int e = 0; e < 3; ++e)
      {
        const double *const   nodes = &x[9 * e];
        std::array<double, 3> sum   = {{nodes[0] + nodes[3] + nodes[6],
                                        nodes[1] + nodes[4] + nodes[7],
                                        nodes[2] + nodes[5] + nodes[8]}};
        for (unsigned int j = 0; j < 3; ++j)
          for (unsigned int c = 0; c < 3; ++c)
            for (unsigned int d = 0; d < 3; ++d)
              result += nodes[3 * j + c] * compliance[3 * c + d] *
                        (nodes[3 * j + d] + sum[d]);
      }
    return map.area / 36. * result;
  }



  void
  JohnsonMercierElement::traction_quadratic(
    const AffineMap                          &map,
    const std::array<double, n_coefficients> &x,
    FullMatrix<double>                       &hessian,
    Vector<double>                           &gradient) const
  {
    // S^ = |E| / 36 P^T S P, the compliance in reference components with
    // the scale of W
    std::array<double, 9> sp, s_hat;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        sp[3 * i + j] = compliance[3 * i] * map.piola[j] +
                        compliance[3 * i + 1] * map.piola[3 + j] +
                        compliance[3 * i + 2] * map.piola[6 + j];
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        s_hat[3 * i + j] =
          map.area / 36. *
          (map.piola[i] * sp[j] + map.piola[3 + i] * sp[3 + j] +
           map.piola[6 + i] * sp[6 + j]);

    // Q: the 2 x 2 blocks ratio_e F^-1 of the reference tractions, entry
    // (reference value t, physical component c of the same pair) at 2 t + c
    std::array<double, 2 * n_traction_values> q;
    for (unsigned int t = 0; t < n_traction_values; ++t)
      for (unsigned int c = 0; c < 2; ++c)
        q[2 * t + c] = map.length_ratio[t / 4] * map.inverse_jacobian[t % 2][c];

    // H^ = sum_ab S^_ab G_ab, then Q^T H^ Q by 2 x 2 blocks: H^ Q, then
    // Q^T (H^ Q) (a third of the flops of the triple products entry by
    // entry)
    constexpr unsigned int    n = n_traction_values;
    std::array<double, n * n> h_hat;
    h_hat.fill(0.);
    for (unsigned int p = 0; p < voigt_pairs.size(); ++p)
      {
        const double weight = s_hat[3 * voigt_pairs[p][0] + voigt_pairs[p][1]];
        const auto  &part   = reference_hessian_parts[p];
        for (unsigned int i = 0; i < h_hat.size(); ++i)
          h_hat[i] += weight * part[i];
      }
    std::array<double, n * n> h_hat_q;
    for (unsigned int t = 0; t < n; ++t)
      for (unsigned int u = 0; u < n; ++u)
        {
          const unsigned int u0 = u - u % 2;
          h_hat_q[n * t + u]    = h_hat[n * t + u0] * q[2 * u0 + u % 2] +
                               h_hat[n * t + u0 + 1] * q[2 * (u0 + 1) + u % 2];
        }
    hessian.reinit(n, n);
    for (unsigned int t = 0; t < n; ++t)
      {
        const unsigned int t0 = t - t % 2;
        for (unsigned int u = 0; u < n; ++u)
          hessian(t, u) = q[2 * t0 + t % 2] * h_hat_q[n * t0 + u] +
                          q[2 * (t0 + 1) + t % 2] * h_hat_q[n * (t0 + 1) + u];
      }

    // the gradient Q^T R^^T P^T W x
    std::array<double, n_coefficients> wx, reference_wx;
    for (unsigned int e = 0; e < 3; ++e)
      {
        const double *const nodes = &x[9 * e];
        for (unsigned int j = 0; j < 3; ++j)
          for (unsigned int c = 0; c < 3; ++c)
            {
              double value = 0.;
              for (unsigned int d = 0; d < 3; ++d)
                value += compliance[3 * c + d] * (nodes[3 * j + d] + nodes[d] +
                                                  nodes[3 + d] + nodes[6 + d]);
              wx[9 * e + 3 * j + c] = map.area / 36. * value;
            }
      }
    for (unsigned int node = 0; node < 9; ++node)
      for (unsigned int c = 0; c < 3; ++c)
        reference_wx[3 * node + c] = map.piola[c] * wx[3 * node] +
                                     map.piola[3 + c] * wx[3 * node + 1] +
                                     map.piola[6 + c] * wx[3 * node + 2];
    std::array<double, n_traction_values> reference_gradient;
    reference_gradient.fill(0.);
    for (unsigned int i = 0; i < n_coefficients; ++i)
      for (unsigned int t = 0; t < n_traction_values; ++t)
        reference_gradient[t] +=
          reference_stress_of_traction[n_traction_values * i + t] *
          reference_wx[i];
    gradient.reinit(n_traction_values);
    for (unsigned int t = 0; t < n_traction_values; ++t)
      {
        const unsigned int t0 = t - t % 2;
        gradient[t]           = q[2 * t0 + t % 2] * reference_gradient[t0] +
                      q[2 * (t0 + 1) + t % 2] * reference_gradient[t0 + 1];
      }
  }



  FullMatrix<double>
  JohnsonMercierElement::compliance_matrix(
    const LinearElasticMaterial<2> &material)
  {
    // the stiffness on the Voigt vectors of tensor components:
    // column j = material.stress(strain with unit component j)
    FullMatrix<double> stiffness(3, 3);
    for (unsigned int j = 0; j < 3; ++j)
      {
        SymmetricTensor<2, 2> strain;
        if (j < 2)
          strain[j][j] = 1.;
        else
          strain[0][1] = 1.; // e_xy = e_yx = 1
        const SymmetricTensor<2, 2> stress = material.stress(strain);
        stiffness(0, j)                    = stress[0][0];
        stiffness(1, j)                    = stress[1][1];
        stiffness(2, j)                    = stress[0][1];
      }
    // (inverted relative to its largest entry: the determinant, of the
    // order of E^3, leaves the range of doubles for E = 1e-300 or 1e300)
    const double scale = stiffness.linfty_norm();
    stiffness /= scale;
    FullMatrix<double> inverse(3, 3);
    inverse.invert(stiffness);
    // S = diag(1, 1, 2) J, symmetric up to round-off
    FullMatrix<double> result(3, 3);
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        result(i, j) = 0.5 *
                       ((i == 2 ? 2. : 1.) * inverse(i, j) +
                        (j == 2 ? 2. : 1.) * inverse(j, i)) /
                       scale;
    return result;
  }



  JohnsonMercierElement::Response
  JohnsonMercierElement::response(const std::array<Point<2>, 3> &vertices) const
  {
    const Split s = split(vertices);
    ColumnMajor a;
    assemble(s, a);

    // Householder QR of the 30 x 27 matrix with its rows and columns
    // permuted into the block structure (see Ordering), skipping the zeros:
    // the reflector of step k is I - tau_k v v^T with v = column k of p on
    // the rows of support[k] (all at or below k), the rows of R above the
    // diagonal of p and on r_diagonal.
    ColumnMajor                       p;
    std::array<std::uint32_t, n_cols> nonzero; // rows of column j of p
    for (unsigned int j = 0; j < n_cols; ++j)
      {
        nonzero[j] = 0;
        for (unsigned int r = 0; r < n_rows; ++r)
          {
            p[j][r] = a[order.column[j]][order.row[r]];
            if (p[j][r] != 0.)
              nonzero[j] |= std::uint32_t(1) << r;
          }
      }

    std::array<double, n_cols>                            tau, r_diagonal;
    std::array<std::uint32_t, n_cols>                     support;
    std::array<std::array<unsigned char, n_rows>, n_cols> rows;
    std::array<unsigned int, n_cols>                      n_support;
    for (unsigned int k = 0; k < n_cols; ++k)
      {
        support[k] =
          (nonzero[k] & (~std::uint32_t(0) << k)) | (std::uint32_t(1) << k);
        n_support[k] = 0;
        for (unsigned int r = k; r < n_rows; ++r)
          if (support[k] & (std::uint32_t(1) << r))
            rows[k][n_support[k]++] = r;
        const unsigned char *const list = rows[k].data();
        const unsigned int         n    = n_support[k];

        double *const v    = p[k].data();
        double        norm = 0.;
        for (unsigned int i = 0; i < n; ++i)
          norm += v[list[i]] * v[list[i]];
        norm               = std::sqrt(norm);
        const double alpha = v[k] >= 0. ? -norm : norm;
        r_diagonal[k]      = alpha;
        if (norm == 0.)
          {
            tau[k] = 0.;
            continue;
          }
        tau[k] = 1. / (norm * (norm + std::abs(v[k])));
        v[k] -= alpha;
        for (unsigned int j = k + 1; j < n_cols; ++j)
          if (nonzero[j] & support[k])
            {
              double *const w   = p[j].data();
              double        dot = 0.;
              for (unsigned int i = 0; i < n; ++i)
                dot += v[list[i]] * w[list[i]];
              dot *= tau[k];
              for (unsigned int i = 0; i < n; ++i)
                w[list[i]] -= dot * v[list[i]];
              nonzero[j] |= support[k];
            }
      }
    // full column rank (see the class documentation; split() refuses the
    // triangles too flat for the rank to be numerically clear): only a
    // guard against non-finite input here
    double largest = 0., smallest = 1e300;
    for (const double d : r_diagonal)
      {
        largest  = std::max(largest, std::abs(d));
        smallest = std::min(smallest, std::abs(d));
      }
    AssertThrow(std::isfinite(largest) && smallest > 1e-14 * largest,
                ExcMessage("JohnsonMercierElement: the constraint matrix is "
                           "rank deficient (degenerate triangle?)"));

    // the right-hand sides (permuted rows): unit traction values and unit
    // body forces
    std::array<std::array<double, n_rows>, n_rhs> b;
    std::array<std::uint32_t, n_rhs>              b_nonzero;
    for (auto &column : b)
      column.fill(0.);
    for (unsigned int t = 0; t < n_traction_values; ++t)
      {
        const unsigned int r = order.row_position[12 + t];
        b[t][r]              = 1.;
        b_nonzero[t]         = std::uint32_t(1) << r;
      }
    for (unsigned int d = 0; d < 6; ++d)
      {
        // component d % 2 of the force on T_{d / 2}: divergence row 24 + d
        const unsigned int r             = order.row_position[24 + d];
        b[n_traction_values + d][r]      = -s.rho;
        b_nonzero[n_traction_values + d] = std::uint32_t(1) << r;
      }

    // Q^T b, then R x = (Q^T b)[0:27]
    for (unsigned int c = 0; c < n_rhs; ++c)
      {
        double *const column = b[c].data();
        for (unsigned int k = 0; k < n_cols; ++k)
          if (b_nonzero[c] & support[k])
            {
              const double *const        v    = p[k].data();
              const unsigned char *const list = rows[k].data();
              double                     dot  = 0.;
              for (unsigned int i = 0; i < n_support[k]; ++i)
                dot += v[list[i]] * column[list[i]];
              dot *= tau[k];
              for (unsigned int i = 0; i < n_support[k]; ++i)
                column[list[i]] -= dot * v[list[i]];
              b_nonzero[c] |= support[k];
            }
      }
    // by columns of R, all right-hand sides at once (independent updates
    // rather than a chain of dependent ones)
    std::array<double, n_cols> inverse_diagonal;
    for (unsigned int k = 0; k < n_cols; ++k)
      inverse_diagonal[k] = 1. / r_diagonal[k];
    for (unsigned int k = n_cols; k-- > 0;)
      {
        const double *const r = p[k].data();
        for (auto &column : b)
          {
            column[k] *= inverse_diagonal[k];
            for (unsigned int i = 0; i < k; ++i)
              column[i] -= r[i] * column[k];
          }
      }

    Response response;
    response.stress_of_traction.reinit(n_cols, n_traction_values);
    response.stress_of_body_force.reinit(n_cols, 6);
    for (unsigned int i = 0; i < n_cols; ++i)
      {
        for (unsigned int t = 0; t < n_traction_values; ++t)
          response.stress_of_traction(order.column[i], t) = b[t][i];
        for (unsigned int d = 0; d < 6; ++d)
          response.stress_of_body_force(order.column[i], d) =
            b[n_traction_values + d][i];
      }

    // int_{T_e} lambda_j lambda_l = |T_e| (1 + delta_jl) / 12, |T_e| = |E|/3
    response.energy.reinit(n_cols, n_cols);
    const double scale = s.area / 3. / 12.;
    for (unsigned int e = 0; e < 3; ++e)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int l = 0; l < 3; ++l)
          for (unsigned int c = 0; c < 3; ++c)
            for (unsigned int d = 0; d < 3; ++d)
              response.energy(coefficient_index(e, j, c),
                              coefficient_index(e, l, d)) =
                scale * (j == l ? 2. : 1.) * compliance[3 * c + d];
    return response;
  }



  Vector<double>
  JohnsonMercierElement::coefficients_of(const SymmetricTensor<2, 2> &stress)
  {
    Vector<double> x(n_coefficients);
    for (unsigned int e = 0; e < 3; ++e)
      for (unsigned int j = 0; j < 3; ++j)
        {
          x[coefficient_index(e, j, 0)] = stress[0][0];
          x[coefficient_index(e, j, 1)] = stress[1][1];
          x[coefficient_index(e, j, 2)] = stress[0][1];
        }
    return x;
  }



  SymmetricTensor<2, 2>
  JohnsonMercierElement::value(const std::array<Point<2>, 3> &vertices,
                               const Vector<double>          &coefficients,
                               const unsigned int             e,
                               const Point<2>                &p)
  {
    AssertDimension(coefficients.size(), n_coefficients);
    AssertIndexRange(e, 3);
    const Split           s       = split(vertices);
    const Point<2>        node[3] = {s.g, vertices[e], vertices[(e + 1) % 3]};
    SymmetricTensor<2, 2> sigma;
    for (unsigned int j = 0; j < 3; ++j)
      {
        // lambda_j(p) = 1 + grad lambda_j . (p - node_j)
        const double lambda = 1. + s.grad[e][j] * (p - node[j]);
        sigma[0][0] += lambda * coefficients[coefficient_index(e, j, 0)];
        sigma[1][1] += lambda * coefficients[coefficient_index(e, j, 1)];
        sigma[0][1] += lambda * coefficients[coefficient_index(e, j, 2)];
      }
    return sigma;
  }



  FullMatrix<double>
  JohnsonMercierElement::constraint_matrix(
    const std::array<Point<2>, 3> &vertices)
  {
    ColumnMajor c;
    assemble(split(vertices), c);
    FullMatrix<double> matrix(n_rows, n_cols);
    for (unsigned int r = 0; r < n_rows; ++r)
      for (unsigned int j = 0; j < n_cols; ++j)
        matrix(r, j) = c[j][r];
    return matrix;
  }



  Vector<double>
  JohnsonMercierElement::constraint_rhs(const std::array<Point<2>, 3> &vertices,
                                        const Vector<double>          &traction,
                                        const BodyForce &body_force)
  {
    std::array<double, n_rows> b;
    rhs(split(vertices), make_array_view(traction), body_force, b);
    return Vector<double>(b.begin(), b.end());
  }



  double
  JohnsonMercierElement::constraint_defect(
    const std::array<Point<2>, 3> &vertices,
    const ArrayView<const double> &coefficients,
    const ArrayView<const double> &traction,
    const BodyForce               &body_force) const
  {
    AssertDimension(coefficients.size(), n_coefficients);
    const Split s = split(vertices);
    // (the constraints applied entry by entry: assembling the dense 30 x 27
    // matrix was a third of the time of the final fields at 1.6M DoFs)
    std::array<double, n_rows> residual;
    rhs(s, traction, body_force, residual);
    for (auto &r : residual)
      r = -r;
    for_each_constraint_entry(
      s, [&](const unsigned int j, const unsigned int r, const double value) {
        residual[r] += value * coefficients[j];
      });

    double size = 0.;
    for (const double t : traction)
      size = std::max(size, std::abs(t));
    for (const double x : coefficients)
      size = std::max(size, std::abs(x));
    for (unsigned int e = 0; e < 3; ++e)
      for (unsigned int i = 0; i < 2; ++i)
        size = std::max(size, s.rho * std::abs(body_force[e][i]));
    double largest = 0.;
    for (const double r : residual)
      largest = std::max(largest, std::abs(r));
    return size > 0. ? largest / size : 0.;
  }
} // namespace Signorini
