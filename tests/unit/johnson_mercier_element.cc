// The Johnson-Mercier macro-element (JohnsonMercierElement), on a few
// non-degenerate, non-symmetric triangles (one clockwise, one tiny, one
// obtuse and flat):
// 1. the 30 x 27 constraint matrix has rank 27 (SVD);
// 2. the tractions of a constant stress, without body force, give that
//    stress everywhere;
// 3. a linear stress field with its constant body force -div sigma is
//    reproduced exactly (uniqueness);
// 4. random equilibrated data (random tractions and a random body force on
//    each sub-triangle, the tractions projected onto those in equilibrium):
//    the constraint defect is round-off, the tractions hold at the edge
//    ends and midpoints, div sigma + f_e = 0 on each sub-triangle T_e,
//    sigma n is continuous at the midpoints of the
//    internal edges; for data not in equilibrium the maps give the
//    least-squares solution (C^T (C x - b) = 0);
// 5. the energy matrix: x^T W x = |E| sigma0 : K^-1 sigma0 for a constant
//    stress (K^-1 of plane strain written out from E and nu), and the
//    integral of sigma : K^-1 sigma by quadrature for the linear field;
// 6. response() on several threads at once gives the serial result; a
//    degenerate triangle is refused;
// 7. the affine maps from the reference triangle (the fast path) give the
//    field, energy and traction quadratic of response() on equilibrated
//    data.
// Pass/fail lines, the rank and a few rounded numbers only.

#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/estimator/johnson_mercier_element.h>

#include "tests.h"

#include <cmath>
#include <iomanip>
#include <random>
#include <thread>

using namespace SignoriniTests;

namespace
{
  using Triangle = std::array<Point<2>, 3>;
  using JM       = JohnsonMercierElement;

  std::string
  rounded(const double x, const unsigned int digits = 6)
  {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    return s.str();
  }

  const char *
  yes_no(const bool ok, unsigned int &failures)
  {
    if (!ok)
      ++failures;
    return ok ? "yes" : "NO";
  }

  Point<2>
  centroid(const Triangle &x)
  {
    return Point<2>((x[0][0] + x[1][0] + x[2][0]) / 3.,
                    (x[0][1] + x[1][1] + x[2][1]) / 3.);
  }

  double
  cross(const Tensor<1, 2> &a, const Tensor<1, 2> &b)
  {
    return a[0] * b[1] - a[1] * b[0];
  }

  double
  area(const Triangle &x)
  {
    return 0.5 * std::abs(cross(x[1] - x[0], x[2] - x[0]));
  }

  /// outward unit normal of edge e (away from the opposite vertex)
  Tensor<1, 2>
  outward_normal(const Triangle &x, const unsigned int e)
  {
    const Tensor<1, 2> d = x[(e + 1) % 3] - x[e];
    Tensor<1, 2>       n;
    n[0] = d[1];
    n[1] = -d[0];
    if (n * (x[(e + 2) % 3] - x[e]) > 0.)
      n = -n;
    return n / n.norm();
  }

  /// the nodes g, x_e, x_{e+1} of the sub-triangle T_e
  std::array<Point<2>, 3>
  sub_triangle(const Triangle &x, const unsigned int e)
  {
    return {{centroid(x), x[e], x[(e + 1) % 3]}};
  }

  /// the nodal values (xx, yy, xy) of T_e in the coefficient vector
  std::array<Tensor<1, 3>, 3>
  nodal_values(const Vector<double> &coefficients, const unsigned int e)
  {
    std::array<Tensor<1, 3>, 3> v;
    for (unsigned int j = 0; j < 3; ++j)
      for (unsigned int c = 0; c < 3; ++c)
        v[j][c] = coefficients[JM::coefficient_index(e, j, c)];
    return v;
  }

  /// linear interpolation of nodal values by barycentric coordinates (area
  /// ratios), independent of the class
  SymmetricTensor<2, 2>
  interpolate(const Triangle       &x,
              const Vector<double> &coefficients,
              const unsigned int    e,
              const Point<2>       &p)
  {
    const auto   nodes = sub_triangle(x, e);
    const auto   v     = nodal_values(coefficients, e);
    const double whole = cross(nodes[1] - nodes[0], nodes[2] - nodes[0]);
    Tensor<1, 3> value;
    for (unsigned int j = 0; j < 3; ++j)
      {
        const Point<2> &a = nodes[(j + 1) % 3], &b = nodes[(j + 2) % 3];
        value += cross(a - p, b - p) / whole * v[j];
      }
    SymmetricTensor<2, 2> sigma;
    sigma[0][0] = value[0];
    sigma[1][1] = value[1];
    sigma[0][1] = value[2];
    return sigma;
  }

  /// div of the linear field of T_e: its gradient from the nodal values
  Tensor<1, 2>
  divergence(const Triangle       &x,
             const Vector<double> &coefficients,
             const unsigned int    e)
  {
    const auto         nodes = sub_triangle(x, e);
    const auto         v     = nodal_values(coefficients, e);
    const Tensor<1, 2> a = nodes[1] - nodes[0], b = nodes[2] - nodes[0];
    const double       det = cross(a, b);
    // gradient of component c: [a; b] grad = (v1 - v0, v2 - v0)
    std::array<Tensor<1, 2>, 3> grad;
    for (unsigned int c = 0; c < 3; ++c)
      {
        const double da = v[1][c] - v[0][c], db = v[2][c] - v[0][c];
        grad[c][0] = (da * b[1] - db * a[1]) / det;
        grad[c][1] = (a[0] * db - b[0] * da) / det;
      }
    Tensor<1, 2> div;
    div[0] = grad[0][0] + grad[2][1];
    div[1] = grad[2][0] + grad[1][1];
    return div;
  }

  /// a linear stress field sigma(x) = A + B x + C y, div sigma = const
  struct LinearField
  {
    SymmetricTensor<2, 2> constant, d_x, d_y;

    SymmetricTensor<2, 2>
    operator()(const Point<2> &p) const
    {
      return constant + p[0] * d_x + p[1] * d_y;
    }

    Tensor<1, 2>
    body_force() const
    {
      Tensor<1, 2> div;
      div[0] = d_x[0][0] + d_y[0][1];
      div[1] = d_x[0][1] + d_y[1][1];
      return -div;
    }
  };

  /// the traction data sigma(x_e) n_e, sigma(x_{e+1}) n_e
  Vector<double>
  tractions_of(const Triangle &x, const LinearField &field)
  {
    Vector<double> t(JM::n_traction_values);
    for (unsigned int e = 0; e < 3; ++e)
      for (unsigned int k = 0; k < 2; ++k)
        {
          const Tensor<1, 2> traction =
            field(x[(e + k) % 3]) * outward_normal(x, e);
          for (unsigned int c = 0; c < 2; ++c)
            t[JM::traction_index(e, k, c)] = traction[c];
        }
    return t;
  }

  /// the same force on the three sub-triangles
  JM::BodyForce
  constant_force(const Tensor<1, 2> &f)
  {
    return {{f, f, f}};
  }

  Vector<double>
  apply(const JM::Response   &r,
        const Vector<double> &traction,
        const JM::BodyForce  &body_force)
  {
    Vector<double> x(JM::n_coefficients), f(6);
    r.stress_of_traction.vmult(x, traction);
    for (unsigned int e = 0; e < 3; ++e)
      for (unsigned int i = 0; i < 2; ++i)
        f[2 * e + i] = body_force[e][i];
    r.stress_of_body_force.vmult_add(x, f);
    return x;
  }

  Vector<double>
  apply(const JM::Response   &r,
        const Vector<double> &traction,
        const Tensor<1, 2>   &body_force)
  {
    return apply(r, traction, constant_force(body_force));
  }

  /// The 3 x 12 map from tractions to (resultant, moment about the
  /// centroid) and the contribution of the body force.
  void
  equilibrium(const Triangle      &x,
              FullMatrix<double>  &G,
              const JM::BodyForce &f,
              Vector<double>      &of_force)
  {
    G.reinit(3, JM::n_traction_values);
    const Point<2> g = centroid(x);
    for (unsigned int e = 0; e < 3; ++e)
      {
        const Tensor<1, 2> a = x[e] - g, b = x[(e + 1) % 3] - g;
        const double       L = (b - a).norm();
        for (unsigned int c = 0; c < 2; ++c)
          {
            G(c, JM::traction_index(e, 0, c)) = L / 2.;
            G(c, JM::traction_index(e, 1, c)) = L / 2.;
          }
        // int (x0 t1 - x1 t0) ds with linear x and t: L/6 (2 x_s t_s +
        // x_s t_e + x_e t_s + 2 x_e t_e)
        for (unsigned int k = 0; k < 2; ++k)
          {
            const double       w_a      = L / 6. * (k == 0 ? 2. : 1.);
            const double       w_b      = L / 6. * (k == 0 ? 1. : 2.);
            const Tensor<1, 2> position = w_a * a + w_b * b;
            G(2, JM::traction_index(e, k, 1)) += position[0];
            G(2, JM::traction_index(e, k, 0)) -= position[1];
          }
      }
    // f_e on T_e (area |E|/3, centroid g_e): resultant |E|/3 f_e, moment
    // |E|/3 (g_e - g) x f_e
    of_force.reinit(3);
    for (unsigned int e = 0; e < 3; ++e)
      {
        const auto         nodes = sub_triangle(x, e);
        const Tensor<1, 2> arm =
          (Tensor<1, 2>(nodes[0]) + Tensor<1, 2>(nodes[1]) +
           Tensor<1, 2>(nodes[2])) /
            3. -
          Tensor<1, 2>(centroid(x));
        of_force[0] += area(x) / 3. * f[e][0];
        of_force[1] += area(x) / 3. * f[e][1];
        of_force[2] += area(x) / 3. * (arm[0] * f[e][1] - arm[1] * f[e][0]);
      }
  }

  /// Project random tractions onto those in equilibrium with @p f.
  Vector<double>
  equilibrated(const Triangle       &x,
               const Vector<double> &t,
               const JM::BodyForce  &f)
  {
    FullMatrix<double> G;
    Vector<double>     of_force;
    equilibrium(x, G, f, of_force);
    Vector<double> defect(3);
    G.vmult(defect, t);
    defect += of_force;
    FullMatrix<double> GGt(3, 3);
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        {
          double s = 0.;
          for (unsigned int k = 0; k < JM::n_traction_values; ++k)
            s += G(i, k) * G(j, k);
          GGt(i, j) = s;
        }
    GGt.gauss_jordan();
    Vector<double> y(3), correction(JM::n_traction_values);
    GGt.vmult(y, defect);
    G.Tvmult(correction, y);
    Vector<double> result = t;
    result -= correction;
    return result;
  }

  double
  max_difference(const Vector<double> &a, const Vector<double> &b)
  {
    Vector<double> d = a;
    d -= b;
    return d.linfty_norm();
  }

  /// sigma : K^-1 tau in plane strain, written out from E and nu
  double
  plane_strain_energy(const SymmetricTensor<2, 2> &s,
                      const double                 E,
                      const double                 nu)
  {
    const double e_xx = (1. + nu) / E * ((1. - nu) * s[0][0] - nu * s[1][1]);
    const double e_yy = (1. + nu) / E * ((1. - nu) * s[1][1] - nu * s[0][0]);
    const double e_xy = (1. + nu) / E * s[0][1];
    return s[0][0] * e_xx + s[1][1] * e_yy + 2. * s[0][1] * e_xy;
  }
} // namespace

int
main()
{
  initlog();
  unsigned int failures = 0;

  const double             young = 210., nu = 0.3;
  LinearElasticMaterial<2> material;
  material.set(young, nu, LinearElasticMaterial<2>::PlaneState::plane_strain);
  const FullMatrix<double> S = JM::compliance_matrix(material);
  {
    const double       a = (1. + nu) / young;
    FullMatrix<double> expected(3, 3);
    expected(0, 0) = expected(1, 1) = a * (1. - nu);
    expected(0, 1) = expected(1, 0) = -a * nu;
    expected(2, 2)                  = 2. * a;
    double deviation                = 0.;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        deviation = std::max(deviation, std::abs(S(i, j) - expected(i, j)));
    deallog << "compliance_matrix = plane strain (1+nu)/E [[1-nu, -nu, 0], "
               "[-nu, 1-nu, 0], [0, 0, 2]]: "
            << yes_no(deviation < 1e-14 * a, failures) << std::endl;
  }
  const JM element(S);

  const std::vector<std::pair<std::string, Triangle>> triangles = {
    {"counterclockwise",
     {{Point<2>(0., 0.), Point<2>(2., 0.3), Point<2>(0.7, 1.6)}}},
    {"clockwise", {{Point<2>(1., 1.), Point<2>(0.2, 2.5), Point<2>(3.1, 1.9)}}},
    {"tiny",
     {{Point<2>(5e-3, 2e-3),
       Point<2>(6.1e-3, 2.2e-3),
       Point<2>(5.4e-3, 2.9e-3)}}},
    {"obtuse", {{Point<2>(0., 0.), Point<2>(3., 0.), Point<2>(2.2, 0.4)}}}};

  std::mt19937                           generator(42);
  std::uniform_real_distribution<double> uniform(-1., 1.);

  for (const auto &[name, x] : triangles)
    {
      deallog << "triangle " << name << ", |E| = " << rounded(area(x))
              << std::endl;
      const JM::Response r = element.response(x);

      // 1. rank of the constraint matrix
      const FullMatrix<double> C = JM::constraint_matrix(x);
      {
        LAPACKFullMatrix<double> svd(C.m(), C.n());
        svd = C;
        svd.compute_svd();
        const double largest = svd.singular_value(0);
        unsigned int rank    = 0;
        for (unsigned int i = 0; i < std::min(C.m(), C.n()); ++i)
          rank += svd.singular_value(i) > 1e-10 * largest ? 1 : 0;
        deallog << "  rank of the 30 x 27 constraint matrix: " << rank
                << ", condition number ~"
                << rounded(largest / svd.singular_value(JM::n_coefficients - 1),
                           3)
                << std::endl;
        if (rank != JM::n_coefficients)
          ++failures;
      }

      // 2. a constant stress
      SymmetricTensor<2, 2> sigma0;
      sigma0[0][0] = 1.3;
      sigma0[1][1] = 0.7;
      sigma0[0][1] = -0.4;
      {
        const LinearField    field{sigma0, {}, {}};
        const Vector<double> x_h =
          apply(r, tractions_of(x, field), Tensor<1, 2>());
        const Vector<double> expected = JM::coefficients_of(sigma0);
        deallog << "  constant stress reproduced: "
                << yes_no(max_difference(x_h, expected) <
                            1e-12 * expected.linfty_norm(),
                          failures)
                << std::endl;
        // 5. energy of the constant stress
        Vector<double> Wx(JM::n_coefficients);
        r.energy.vmult(Wx, x_h);
        const double energy = x_h * Wx;
        const double exact  = area(x) * plane_strain_energy(sigma0, young, nu);
        deallog << "  energy of the constant stress = |E| sigma0 : K^-1 "
                   "sigma0: "
                << yes_no(std::abs(energy / exact - 1.) < 1e-12, failures)
                << " (" << rounded(energy / area(x)) << " |E|)" << std::endl;
        bool symmetric = true;
        for (unsigned int i = 0; i < JM::n_coefficients; ++i)
          for (unsigned int j = 0; j < JM::n_coefficients; ++j)
            symmetric &= r.energy(i, j) == r.energy(j, i);
        deallog << "  energy matrix symmetric: " << yes_no(symmetric, failures)
                << std::endl;
      }

      // 3. a linear stress field and its body force
      {
        LinearField field;
        field.constant  = sigma0;
        field.d_x[0][0] = 0.9;
        field.d_x[1][1] = -0.3;
        field.d_x[0][1] = 0.5;
        field.d_y[0][0] = -0.6;
        field.d_y[1][1] = 1.1;
        field.d_y[0][1] = 0.2;
        // in the units of the triangle: gradients ~ |sigma| / h
        const double h = x[0].distance(x[1]);
        field.d_x /= h;
        field.d_y /= h;
        field.constant -= field.d_x * x[0][0] + field.d_y * x[0][1];
        const Tensor<1, 2>   f   = field.body_force();
        const Vector<double> x_h = apply(r, tractions_of(x, field), f);
        Vector<double>       expected(JM::n_coefficients);
        for (unsigned int e = 0; e < 3; ++e)
          {
            const auto nodes = sub_triangle(x, e);
            for (unsigned int j = 0; j < 3; ++j)
              {
                const SymmetricTensor<2, 2> s            = field(nodes[j]);
                expected[JM::coefficient_index(e, j, 0)] = s[0][0];
                expected[JM::coefficient_index(e, j, 1)] = s[1][1];
                expected[JM::coefficient_index(e, j, 2)] = s[0][1];
              }
          }
        deallog << "  linear stress with f = -div sigma reproduced: "
                << yes_no(max_difference(x_h, expected) <
                            1e-12 * expected.linfty_norm(),
                          failures)
                << std::endl;

        // 5. its energy: edge-midpoint rule on each sub-triangle (exact for
        //    quadratics)
        Vector<double> Wx(JM::n_coefficients);
        r.energy.vmult(Wx, x_h);
        double quadrature = 0.;
        for (unsigned int e = 0; e < 3; ++e)
          {
            const auto nodes = sub_triangle(x, e);
            for (unsigned int j = 0; j < 3; ++j)
              {
                const Point<2> mid =
                  0.5 * (nodes[j] + Tensor<1, 2>(nodes[(j + 1) % 3]));
                quadrature +=
                  area(x) / 9. * plane_strain_energy(field(mid), young, nu);
              }
          }
        deallog << "  energy of the linear stress = quadrature: "
                << yes_no(std::abs((x_h * Wx) / quadrature - 1.) < 1e-12,
                          failures)
                << std::endl;
      }

      // 4. random equilibrated data
      {
        bool         defect_ok = true, traction_ok = true, div_ok = true;
        bool         continuity_ok = true, value_ok = true;
        double       worst_defect = 0.;
        const double h            = std::max(
          {x[0].distance(x[1]), x[1].distance(x[2]), x[2].distance(x[0])});
        for (unsigned int trial = 0; trial < 10; ++trial)
          {
            Vector<double> t(JM::n_traction_values);
            for (auto &v : t)
              v = uniform(generator);
            // a different force on each sub-triangle
            JM::BodyForce f;
            double        largest_force = 0.;
            for (auto &force : f)
              {
                force[0]      = uniform(generator) / h;
                force[1]      = uniform(generator) / h;
                largest_force = std::max(largest_force, force.norm());
              }
            t                  = equilibrated(x, t, f);
            const double scale = std::max(t.linfty_norm(), h * largest_force);

            const Vector<double> x_h    = apply(r, t, f);
            const double         defect = element.constraint_defect(
              x, make_array_view(x_h), make_array_view(t), f);
            worst_defect = std::max(worst_defect, defect);
            defect_ok &= defect < 1e-12;

            for (unsigned int e = 0; e < 3; ++e)
              {
                const Tensor<1, 2> n = outward_normal(x, e);
                for (const double s : {0., 0.5, 1.})
                  {
                    const Point<2> p = x[e] + s * (x[(e + 1) % 3] - x[e]);
                    Tensor<1, 2>   expected;
                    for (unsigned int c = 0; c < 2; ++c)
                      expected[c] = (1. - s) * t[JM::traction_index(e, 0, c)] +
                                    s * t[JM::traction_index(e, 1, c)];
                    const SymmetricTensor<2, 2> sigma =
                      interpolate(x, x_h, e, p);
                    traction_ok &=
                      (sigma * n - expected).norm() < 1e-12 * scale;
                    value_ok &=
                      (JM::value(x, x_h, e, p) - sigma).norm() < 1e-12 * scale;
                  }
                div_ok &=
                  h * (divergence(x, x_h, e) + f[e]).norm() < 1e-12 * scale;

                // the internal edge g-x_e between T_e and T_{e-1}
                const Point<2>     g = centroid(x);
                const Tensor<1, 2> d = x[e] - g;
                Tensor<1, 2>       m;
                m[0] = -d[1];
                m[1] = d[0];
                for (const double s : {0., 0.5, 1.})
                  {
                    const Point<2> p = g + s * d;
                    continuity_ok &= ((interpolate(x, x_h, e, p) -
                                       interpolate(x, x_h, (e + 2) % 3, p)) *
                                      m)
                                       .norm() < 1e-12 * scale * m.norm();
                  }
              }
          }
        deallog << "  random equilibrated data: constraint defect < 1e-12 "
                << yes_no(defect_ok, failures) << ", tractions at the edge "
                << "ends and midpoints " << yes_no(traction_ok, failures)
                << ", div sigma + f = 0 " << yes_no(div_ok, failures)
                << ", sigma n continuous on the internal edges "
                << yes_no(continuity_ok, failures) << ", value() "
                << yes_no(value_ok, failures) << std::endl;
        if (!defect_ok)
          deallog << "    worst defect " << worst_defect << std::endl;
      }

      // 7. the affine maps (the fast path) against response() on random
      //    equilibrated data: the field, its energy, and the quadratic in
      //    the tractions on pairs of equilibrated data (its action on other
      //    data is not that of response(), see field())
      {
        const JM::AffineMap map = JM::affine_map(x);
        const double        h   = std::max(
          {x[0].distance(x[1]), x[1].distance(x[2]), x[2].distance(x[0])});
        const auto random_data = [&](const bool with_force) {
          Vector<double> t(JM::n_traction_values);
          for (auto &v : t)
            v = uniform(generator);
          JM::BodyForce f;
          if (with_force)
            for (auto &force : f)
              {
                force[0] = uniform(generator) / h;
                force[1] = uniform(generator) / h;
              }
          return std::make_pair(equilibrated(x, t, f), f);
        };
        const auto as_array = [](const Vector<double> &v) {
          std::array<double, JM::n_traction_values> a;
          std::copy(v.begin(), v.end(), a.begin());
          return a;
        };
        double field_error = 0., energy_error = 0., quadratic_error = 0.;
        for (unsigned int trial = 0; trial < 10; ++trial)
          {
            const auto [t, f]         = random_data(true);
            const Vector<double> x_h  = apply(r, t, f);
            const auto           fast = element.field(map, as_array(t), f);
            const Vector<double> x_fast(fast.begin(), fast.end());
            field_error =
              std::max(field_error,
                       max_difference(x_fast, x_h) / x_h.linfty_norm());
            energy_error =
              std::max(energy_error,
                       std::abs(element.energy(map, fast) /
                                  r.energy.matrix_norm_square(x_h) -
                                1.));

            // t1^T H t2 = (R t1)^T W (R t2) and g . t2 = x^T W R t2
            const auto [t1, f1] = random_data(false);
            const auto [t2, f2] = random_data(false);
            FullMatrix<double> hessian;
            Vector<double>     gradient;
            element.traction_quadratic(map, fast, hessian, gradient);
            Vector<double> r1(JM::n_coefficients), r2(JM::n_coefficients),
              w2(JM::n_coefficients);
            r.stress_of_traction.vmult(r1, t1);
            r.stress_of_traction.vmult(r2, t2);
            r.energy.vmult(w2, r2);
            const double hessian_form  = hessian.matrix_scalar_product(t1, t2);
            const double gradient_form = gradient * t2;
            quadratic_error =
              std::max({quadratic_error,
                        std::abs(hessian_form - r1 * w2) /
                          std::sqrt(r.energy.matrix_norm_square(r1) *
                                    r.energy.matrix_norm_square(r2)),
                        std::abs(gradient_form - x_h * w2) /
                          std::sqrt(r.energy.matrix_norm_square(x_h) *
                                    r.energy.matrix_norm_square(r2))});
          }
        deallog << "  affine maps on equilibrated data: field "
                << yes_no(field_error < 1e-12, failures) << ", energy "
                << yes_no(energy_error < 1e-12, failures)
                << ", traction quadratic "
                << yes_no(quadratic_error < 1e-12, failures) << std::endl;
        if (field_error >= 1e-12 || energy_error >= 1e-12 ||
            quadratic_error >= 1e-12)
          deallog << "    errors " << field_error << " " << energy_error << " "
                  << quadratic_error << std::endl;
      }

      // data not in equilibrium: a least-squares solution
      {
        Vector<double> t(JM::n_traction_values);
        for (auto &v : t)
          v = uniform(generator);
        Tensor<1, 2> f;
        f[0]                     = 0.5;
        const Vector<double> x_h = apply(r, t, f);
        Vector<double> residual  = JM::constraint_rhs(x, t, constant_force(f));
        residual *= -1.;
        C.vmult_add(residual, x_h);
        Vector<double> normal(JM::n_coefficients);
        C.Tvmult(normal, residual);
        deallog << "  non-equilibrated data: defect > 1e-3 "
                << yes_no(element.constraint_defect(x,
                                                    make_array_view(x_h),
                                                    make_array_view(t),
                                                    constant_force(f)) > 1e-3,
                          failures)
                << ", C^T (C x - b) = 0 (least squares) "
                << yes_no(normal.linfty_norm() < 1e-12 * t.linfty_norm(),
                          failures)
                << std::endl;
      }
    }

  // a triangle too flat for the rank to be clear (|E| < 1e-6 diam^2)
  {
    bool thrown = false;
    try
      {
        element.response(
          {{Point<2>(0., 0.), Point<2>(1., 0.), Point<2>(0.4, 1e-6)}});
      }
    catch (const std::exception &)
      {
        thrown = true;
      }
    deallog << "degenerate triangle refused: " << yes_no(thrown, failures)
            << std::endl;
  }

  // 6. concurrent calls give the serial result
  {
    std::vector<Triangle> many;
    for (unsigned int i = 0; i < 400; ++i)
      {
        Triangle x;
        do
          for (auto &p : x)
            p = Point<2>(uniform(generator), uniform(generator));
        while (area(x) < 0.05);
        many.push_back(x);
      }
    std::vector<JM::Response> serial;
    for (const auto &x : many)
      serial.push_back(element.response(x));
    const unsigned int             n_threads = 4;
    std::vector<std::vector<bool>> same(n_threads);
    std::vector<std::thread>       threads;
    for (unsigned int i = 0; i < n_threads; ++i)
      threads.emplace_back([&, i]() {
        for (unsigned int repeat = 0; repeat < 5; ++repeat)
          for (unsigned int c = 0; c < many.size(); ++c)
            {
              const JM::Response r     = element.response(many[c]);
              bool               equal = true;
              for (unsigned int a = 0; a < JM::n_coefficients; ++a)
                {
                  for (unsigned int b = 0; b < JM::n_traction_values; ++b)
                    equal &= r.stress_of_traction(a, b) ==
                             serial[c].stress_of_traction(a, b);
                  for (unsigned int b = 0; b < 2; ++b)
                    equal &= r.stress_of_body_force(a, b) ==
                             serial[c].stress_of_body_force(a, b);
                }
              same[i].push_back(equal);
            }
      });
    for (auto &thread : threads)
      thread.join();
    bool all = true;
    for (const auto &s : same)
      for (const bool b : s)
        all &= b;
    deallog << "4 threads x 2000 calls equal to the serial results: "
            << yes_no(all, failures) << std::endl;
  }

  if (failures == 0)
    deallog << "all checks passed" << std::endl;
  else
    deallog << "FAILURES: " << failures << std::endl;
}
