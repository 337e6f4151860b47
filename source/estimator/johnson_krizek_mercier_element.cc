#include <deal.II/base/exceptions.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/estimator/johnson_krizek_mercier_element.h>

#include <algorithm>
#include <cmath>

namespace Signorini
{
  namespace
  {
    /// d!
    constexpr double
    factorial(const int d)
    {
      return d <= 1 ? 1. : d * factorial(d - 1);
    }

    /// The gradients of the barycentric coordinates of the simplex with
    /// @p points (either orientation; not degenerate).
    template <int dim>
    std::array<Tensor<1, dim>, dim + 1>
    barycentric_gradients(const std::array<Point<dim>, dim + 1> &points)
    {
      Tensor<2, dim> jacobian;
      for (unsigned int k = 1; k <= dim; ++k)
        for (unsigned int i = 0; i < dim; ++i)
          jacobian[i][k - 1] = points[k][i] - points[0][i];
      const Tensor<2, dim>                inverse = invert(jacobian);
      std::array<Tensor<1, dim>, dim + 1> gradients;
      for (unsigned int k = 1; k <= dim; ++k)
        {
          for (unsigned int i = 0; i < dim; ++i)
            gradients[k][i] = inverse[k - 1][i];
          gradients[0] -= gradients[k];
        }
      return gradients;
    }

    /// The nodes of sub-simplex @p s: the vertices, x_s replaced by g.
    template <int dim>
    std::array<Point<dim>, dim + 1>
    sub_simplex(const std::array<Point<dim>, dim + 1> &vertices,
                const Point<dim>                      &centroid,
                const unsigned int                     s)
    {
      std::array<Point<dim>, dim + 1> nodes = vertices;
      nodes[s]                              = centroid;
      return nodes;
    }

    /// The symmetric tensor with unrolled component @p c equal to one (both
    /// entries off the diagonal).
    template <int dim>
    SymmetricTensor<2, dim>
    unit(const unsigned int c)
    {
      SymmetricTensor<2, dim> result;
      result[SymmetricTensor<2, dim>::unrolled_to_component_indices(c)] = 1.;
      return result;
    }

    /// The unrolled index of entry (a, b).
    template <int dim>
    unsigned int
    unrolled(const unsigned int a, const unsigned int b)
    {
      return SymmetricTensor<2, dim>::component_to_unrolled_index(
        TableIndices<2>(a, b));
    }

    /// B s B^T / scale, symmetrised.
    template <int dim>
    SymmetricTensor<2, dim>
    congruence(const Tensor<2, dim>          &b,
               const SymmetricTensor<2, dim> &s,
               const double                   scale)
    {
      const Tensor<2, dim> full = b * Tensor<2, dim>(s) * transpose(b);
      return symmetrize(full) / scale;
    }
  } // namespace



  template <int dim>
  typename JohnsonKrizekMercierElement<dim>::Geometry
  JohnsonKrizekMercierElement<dim>::geometry(
    const std::array<Point<dim>, n_vertices> &vertices)
  {
    Geometry g;
    g.vertices = vertices;
    for (unsigned int k = 1; k <= dim; ++k)
      for (unsigned int i = 0; i < dim; ++i)
        g.jacobian[i][k - 1] = vertices[k][i] - vertices[0][i];
    g.determinant = std::abs(determinant(g.jacobian));
    g.measure     = g.determinant / factorial(dim);
    g.diameter    = 0.;
    g.centroid    = Point<dim>();
    for (unsigned int v = 0; v < n_vertices; ++v)
      {
        g.centroid += vertices[v] / double(n_vertices);
        for (unsigned int w = 0; w < v; ++w)
          g.diameter = std::max(g.diameter, vertices[v].distance(vertices[w]));
      }
    AssertThrow(g.diameter > 0. &&
                  g.measure > 1e-6 * std::pow(g.diameter, double(dim)),
                ExcMessage(
                  "a cell of measure < 1e-6 diameter^dim (a sliver) has no "
                  "reliable Johnson-Krizek-Mercier field: remesh, or set "
                  "Error estimator/Element equilibration/Element stress = "
                  "displacement"));
    g.inverse_jacobian   = invert(g.jacobian);
    const auto gradients = barycentric_gradients<dim>(vertices);
    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        g.normal[s] = -gradients[s] / gradients[s].norm();
        // |F_s| = d |E| |grad lambda_s|; on the reference |grad lambda_0| =
        // sqrt(d), |grad lambda_k| = 1
        g.face_ratio[s] = g.determinant * gradients[s].norm() /
                          (s == 0 ? std::sqrt(double(dim)) : 1.);
      }
    return g;
  }



  template <int dim>
  JohnsonKrizekMercierElement<dim>::JohnsonKrizekMercierElement(
    const LinearElasticMaterial<dim> &material)
  {
    // sigma : K^-1 tau = s^T S t on unrolled components
    for (unsigned int a = 0; a < n_components; ++a)
      for (unsigned int b = 0; b < n_components; ++b)
        compliance[a * n_components + b] =
          unit<dim>(a) * material.strain(unit<dim>(b));

    // the constraints on the reference simplex: continuity across the
    // interior faces (zero data), then the tractions (traction_index()),
    // then the divergence (s dim + a)
    std::array<Point<dim>, n_vertices> reference_vertices;
    for (unsigned int k = 1; k <= dim; ++k)
      reference_vertices[k][k - 1] = 1.;
    const Geometry     reference = geometry(reference_vertices);
    const unsigned int n_continuity =
      (n_vertices * (n_vertices - 1) / 2) * dim * dim;
    const unsigned int n_divergence = n_vertices * dim;
    FullMatrix<double> constraints(n_continuity + n_traction_values +
                                     n_divergence,
                                   n_coefficients);
    // row += factor (sigma n)_a at node (s, j)
    const auto add_traction = [&](const unsigned int    row,
                                  const unsigned int    s,
                                  const unsigned int    j,
                                  const unsigned int    a,
                                  const Tensor<1, dim> &n,
                                  const double          factor) {
      for (unsigned int b = 0; b < dim; ++b)
        constraints(row, coefficient_index(s, j, unrolled<dim>(a, b))) +=
          factor * n[b];
    };
    unsigned int row = 0;
    for (unsigned int s = 0; s < n_vertices; ++s)
      for (unsigned int t = s + 1; t < n_vertices; ++t)
        {
          // the face of T_s opposite its node x_t is the one it shares with
          // T_t: g and the x_j, j != s, t
          const auto gradients = barycentric_gradients<dim>(
            sub_simplex<dim>(reference_vertices, reference.centroid, s));
          const Tensor<1, dim> m = gradients[t] / gradients[t].norm();
          for (unsigned int j = 0; j < n_vertices; ++j)
            if (j != t)
              for (unsigned int a = 0; a < dim; ++a, ++row)
                {
                  // at g: node s of T_s, node t of T_t
                  add_traction(row, s, j, a, m, 1.);
                  add_traction(row, t, j == s ? t : j, a, m, -1.);
                }
        }
    Assert(row == n_continuity, ExcInternalError());
    for (unsigned int s = 0; s < n_vertices; ++s)
      for (unsigned int j = 0; j < n_vertices; ++j)
        if (j != s)
          for (unsigned int a = 0; a < dim; ++a)
            add_traction(n_continuity + traction_index(s, j, a),
                         s,
                         j,
                         a,
                         reference.normal[s],
                         1.);
    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        const auto gradients = barycentric_gradients<dim>(
          sub_simplex<dim>(reference_vertices, reference.centroid, s));
        for (unsigned int j = 0; j < n_vertices; ++j)
          for (unsigned int a = 0; a < dim; ++a)
            add_traction(n_continuity + n_traction_values + s * dim + a,
                         s,
                         j,
                         a,
                         gradients[j],
                         1.);
      }

    // the pseudo-inverse (C^T C)^-1 C^T: C has full column rank (checked),
    // the data of equilibrium lie in its range
    FullMatrix<double> normal(n_coefficients, n_coefficients);
    constraints.Tmmult(normal, constraints);
    {
      LAPACKFullMatrix<double> svd(n_coefficients, n_coefficients);
      svd = normal;
      svd.compute_svd();
      AssertThrow(svd.singular_value(n_coefficients - 1) >
                    1e-10 * svd.singular_value(0),
                  ExcMessage("the Johnson-Krizek-Mercier constraints lost "
                             "their full column rank"));
    }
    FullMatrix<double> inverse(n_coefficients, n_coefficients);
    inverse.invert(normal);
    FullMatrix<double> pseudo_inverse(n_coefficients, constraints.m());
    inverse.mTmult(pseudo_inverse, constraints);
    traction_map.resize(n_coefficients * n_traction_values);
    body_force_map.resize(n_coefficients * n_divergence);
    for (unsigned int i = 0; i < n_coefficients; ++i)
      {
        for (unsigned int t = 0; t < n_traction_values; ++t)
          traction_map[i * n_traction_values + t] =
            pseudo_inverse(i, n_continuity + t);
        // div sigma = -f
        for (unsigned int f = 0; f < n_divergence; ++f)
          body_force_map[i * n_divergence + f] =
            -pseudo_inverse(i, n_continuity + n_traction_values + f);
      }

    // the parts of the Hessian
    for (unsigned int a = 0; a < n_components; ++a)
      for (unsigned int b = a; b < n_components; ++b)
        {
          ComponentMatrix pair{};
          pair[a * n_components + b] = 1.;
          pair[b * n_components + a] = 1.;
          std::vector<Coefficients> weighted_columns(n_traction_values);
          for (unsigned int t = 0; t < n_traction_values; ++t)
            {
              Coefficients column;
              for (unsigned int i = 0; i < n_coefficients; ++i)
                column[i] = traction_map[i * n_traction_values + t];
              weighted_columns[t] = weighted(pair, column);
            }
          TractionMatrix part{};
          for (unsigned int t = 0; t < n_traction_values; ++t)
            for (unsigned int u = 0; u < n_traction_values; ++u)
              for (unsigned int i = 0; i < n_coefficients; ++i)
                part[t * n_traction_values + u] +=
                  traction_map[i * n_traction_values + t] *
                  weighted_columns[u][i];
          hessian_parts.push_back(part);
        }
  }



  template <int dim>
  typename JohnsonKrizekMercierElement<dim>::ComponentMatrix
  JohnsonKrizekMercierElement<dim>::reference_compliance(
    const Geometry &geometry) const
  {
    ComponentMatrix piola;
    for (unsigned int b = 0; b < n_components; ++b)
      {
        const SymmetricTensor<2, dim> image =
          congruence<dim>(geometry.jacobian, unit<dim>(b), 1.);
        for (unsigned int a = 0; a < n_components; ++a)
          piola[a * n_components + b] =
            image[SymmetricTensor<2, dim>::unrolled_to_component_indices(a)];
      }
    ComponentMatrix product{}, result{};
    for (unsigned int a = 0; a < n_components; ++a)
      for (unsigned int c = 0; c < n_components; ++c)
        for (unsigned int b = 0; b < n_components; ++b)
          product[a * n_components + b] +=
            compliance[a * n_components + c] * piola[c * n_components + b];
    for (unsigned int a = 0; a < n_components; ++a)
      for (unsigned int c = 0; c < n_components; ++c)
        for (unsigned int b = 0; b < n_components; ++b)
          result[a * n_components + b] +=
            piola[c * n_components + a] * product[c * n_components + b];
    return result;
  }



  template <int dim>
  typename JohnsonKrizekMercierElement<dim>::Coefficients
  JohnsonKrizekMercierElement<dim>::weighted(const ComponentMatrix &c_hat,
                                             const Coefficients    &x) const
  {
    // the P1 mass matrix of a reference sub-simplex: |T^_s| / ((d + 1)
    // (d + 2)) (1 + delta_jk), |T^_s| = 1 / (d! (d + 1))
    const double mass =
      1. / (factorial(dim) * n_vertices * n_vertices * (n_vertices + 1));
    Coefficients result;
    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        // sum of the nodal values of T_s, then (1 + delta) per node
        std::array<double, n_components> sum{};
        for (unsigned int j = 0; j < n_vertices; ++j)
          for (unsigned int c = 0; c < n_components; ++c)
            sum[c] += x[coefficient_index(s, j, c)];
        for (unsigned int j = 0; j < n_vertices; ++j)
          for (unsigned int a = 0; a < n_components; ++a)
            {
              double value = 0.;
              for (unsigned int b = 0; b < n_components; ++b)
                value += c_hat[a * n_components + b] *
                         (sum[b] + x[coefficient_index(s, j, b)]);
              result[coefficient_index(s, j, a)] = mass * value;
            }
      }
    return result;
  }



  template <int dim>
  typename JohnsonKrizekMercierElement<dim>::Coefficients
  JohnsonKrizekMercierElement<dim>::reference_coefficients(
    const Geometry  &geometry,
    const Traction  &traction,
    const BodyForce &body_force) const
  {
    constexpr unsigned int n_forces = n_vertices * dim;
    TractionVector         reference_traction;
    for (unsigned int corner = 0; corner < n_vertices * dim; ++corner)
      {
        const Tensor<1, dim> t = geometry.face_ratio[corner / dim] *
                                 (geometry.inverse_jacobian * traction[corner]);
        for (unsigned int c = 0; c < dim; ++c)
          reference_traction[corner * dim + c] = t[c];
      }
    std::array<double, n_forces> reference_force;
    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        const Tensor<1, dim> f =
          geometry.determinant * (geometry.inverse_jacobian * body_force[s]);
        for (unsigned int c = 0; c < dim; ++c)
          reference_force[s * dim + c] = f[c];
      }
    Coefficients x;
    for (unsigned int i = 0; i < n_coefficients; ++i)
      {
        const double *traction_row = &traction_map[i * n_traction_values];
        const double *force_row    = &body_force_map[i * n_forces];
        double        value        = 0.;
        for (unsigned int t = 0; t < n_traction_values; ++t)
          value += traction_row[t] * reference_traction[t];
        for (unsigned int f = 0; f < n_forces; ++f)
          value += force_row[f] * reference_force[f];
        x[i] = value;
      }
    return x;
  }



  template <int dim>
  typename JohnsonKrizekMercierElement<dim>::Field
  JohnsonKrizekMercierElement<dim>::field(const Geometry  &geometry,
                                          const Traction  &traction,
                                          const BodyForce &body_force) const
  {
    const Coefficients x =
      reference_coefficients(geometry, traction, body_force);
    Field result;
    for (unsigned int node = 0; node < n_nodes; ++node)
      {
        SymmetricTensor<2, dim> reference;
        for (unsigned int c = 0; c < n_components; ++c)
          reference[SymmetricTensor<2, dim>::unrolled_to_component_indices(c)] =
            x[node * n_components + c];
        result[node] =
          congruence<dim>(geometry.jacobian, reference, geometry.determinant);
      }
    return result;
  }



  template <int dim>
  SymmetricTensor<2, dim>
  JohnsonKrizekMercierElement<dim>::value(const Geometry    &geometry,
                                          const Field       &field,
                                          const unsigned int s,
                                          const Point<dim>  &point)
  {
    const auto nodes =
      sub_simplex<dim>(geometry.vertices, geometry.centroid, s);
    const auto              gradients = barycentric_gradients<dim>(nodes);
    SymmetricTensor<2, dim> result;
    for (unsigned int j = 0; j < n_vertices; ++j)
      result +=
        (1. + gradients[j] * (point - nodes[j])) * field[node_index(s, j)];
    return result;
  }



  template <int dim>
  double
  JohnsonKrizekMercierElement<dim>::energy(
    const Geometry                &geometry,
    const Field                   &field,
    const SymmetricTensor<2, dim> &tau) const
  {
    // int_T (linear)^2 = |T| / ((d + 1) (d + 2)) (sum_j q_jj + q(sum, sum))
    const auto form = [&](const SymmetricTensor<2, dim> &x,
                          const SymmetricTensor<2, dim> &y) {
      double value = 0.;
      for (unsigned int a = 0; a < n_components; ++a)
        for (unsigned int b = 0; b < n_components; ++b)
          value +=
            x[SymmetricTensor<2, dim>::unrolled_to_component_indices(a)] *
            compliance[a * n_components + b] *
            y[SymmetricTensor<2, dim>::unrolled_to_component_indices(b)];
      return value;
    };
    double result = 0.;
    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        SymmetricTensor<2, dim> sum;
        double                  diagonal = 0.;
        for (unsigned int j = 0; j < n_vertices; ++j)
          {
            const SymmetricTensor<2, dim> difference =
              field[node_index(s, j)] - tau;
            sum += difference;
            diagonal += form(difference, difference);
          }
        result += (diagonal + form(sum, sum));
      }
    return result * geometry.measure /
           (n_vertices * n_vertices * (n_vertices + 1.));
  }



  template <int dim>
  typename JohnsonKrizekMercierElement<dim>::TractionMatrix
  JohnsonKrizekMercierElement<dim>::hessian(const Geometry &geometry) const
  {
    constexpr unsigned int n     = n_traction_values;
    const ComponentMatrix  c_hat = reference_compliance(geometry);
    TractionMatrix         reference{};
    unsigned int           part = 0;
    for (unsigned int a = 0; a < n_components; ++a)
      for (unsigned int b = a; b < n_components; ++b, ++part)
        {
          const double  factor = c_hat[a * n_components + b];
          const double *values = hessian_parts[part].data();
          for (unsigned int i = 0; i < n * n; ++i)
            reference[i] += factor * values[i];
        }
    // H = T^T H^ T / |det B|, T the block diagonal of face_ratio B^-1:
    // first H^ T, then T^T (H^ T)
    TractionMatrix right, result;
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        {
          const unsigned int cj = j / dim, aj = j % dim;
          double             value = 0.;
          for (unsigned int q = 0; q < dim; ++q)
            value += reference[i * n + cj * dim + q] *
                     geometry.inverse_jacobian[q][aj];
          right[i * n + j] = value * geometry.face_ratio[cj / dim];
        }
    for (unsigned int i = 0; i < n; ++i)
      {
        const unsigned int ci = i / dim, ai = i % dim;
        const double       factor =
          geometry.face_ratio[ci / dim] / geometry.determinant;
        for (unsigned int j = 0; j < n; ++j)
          {
            double value = 0.;
            for (unsigned int p = 0; p < dim; ++p)
              value += geometry.inverse_jacobian[p][ai] *
                       right[(ci * dim + p) * n + j];
            result[i * n + j] = factor * value;
          }
      }
    return result;
  }



  template <int dim>
  std::pair<typename JohnsonKrizekMercierElement<dim>::TractionVector, double>
  JohnsonKrizekMercierElement<dim>::linear_part(
    const Geometry                &geometry,
    const BodyForce               &body_force,
    const SymmetricTensor<2, dim> &tau) const
  {
    // y = x^_f - x^_tau, the reference coefficients without tractions
    Coefficients y = reference_coefficients(geometry, Traction(), body_force);
    const SymmetricTensor<2, dim> tau_hat =
      congruence<dim>(geometry.inverse_jacobian,
                      tau,
                      1. / geometry.determinant);
    for (unsigned int node = 0; node < n_nodes; ++node)
      for (unsigned int c = 0; c < n_components; ++c)
        y[node * n_components + c] -=
          tau_hat[SymmetricTensor<2, dim>::unrolled_to_component_indices(c)];
    const Coefficients w = weighted(reference_compliance(geometry), y);
    TractionVector     reference_gradient{};
    double             constant = 0.;
    for (unsigned int i = 0; i < n_coefficients; ++i)
      {
        const double *row = &traction_map[i * n_traction_values];
        for (unsigned int t = 0; t < n_traction_values; ++t)
          reference_gradient[t] += row[t] * w[i];
        constant += y[i] * w[i];
      }
    TractionVector gradient;
    for (unsigned int i = 0; i < n_traction_values; ++i)
      {
        const unsigned int corner = i / dim, a = i % dim;
        double             value = 0.;
        for (unsigned int p = 0; p < dim; ++p)
          value += geometry.inverse_jacobian[p][a] *
                   reference_gradient[corner * dim + p];
        gradient[i] =
          value * geometry.face_ratio[corner / dim] / geometry.determinant;
      }
    return {gradient, constant / geometry.determinant};
  }



  template <int dim>
  Tensor<1, dim>
  JohnsonKrizekMercierElement<dim>::rotation(const unsigned int    k,
                                             const Tensor<1, dim> &v)
  {
    Tensor<1, dim> result;
    if constexpr (dim == 2)
      {
        (void)k;
        result[0] = -v[1];
        result[1] = v[0];
      }
    else
      {
        Tensor<1, dim> axis;
        axis[k] = 1.;
        result  = cross_product_3d(axis, v);
      }
    return result;
  }



  template <int dim>
  typename JohnsonKrizekMercierElement<dim>::BodyForce
  JohnsonKrizekMercierElement<dim>::balanced_body_force(
    const Geometry                                  &geometry,
    const Tensor<1, dim>                            &resultant,
    const std::array<double, (dim * (dim - 1)) / 2> &moments)
  {
    constexpr unsigned int n_rotations = (dim * (dim - 1)) / 2;
    // f_s = resultant / |E| + sum_l omega_l S_l (g_s - g): the rotations
    // carry no resultant since the g_s average to g
    std::array<Tensor<1, dim>, n_vertices> offset;
    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        Point<dim> centroid = geometry.centroid;
        for (unsigned int j = 0; j < n_vertices; ++j)
          if (j != s)
            centroid += geometry.vertices[j];
        offset[s] = centroid / double(n_vertices) - geometry.centroid;
      }
    const double       sub_measure = geometry.measure / n_vertices;
    FullMatrix<double> inertia(n_rotations, n_rotations);
    for (unsigned int k = 0; k < n_rotations; ++k)
      for (unsigned int l = 0; l < n_rotations; ++l)
        for (unsigned int s = 0; s < n_vertices; ++s)
          inertia(k, l) +=
            sub_measure * (rotation(k, offset[s]) * rotation(l, offset[s]));
    Vector<double> omega(n_rotations);
    {
      Vector<double> rhs(n_rotations);
      for (unsigned int k = 0; k < n_rotations; ++k)
        rhs[k] = moments[k];
      inertia.gauss_jordan();
      inertia.vmult(omega, rhs);
    }
    BodyForce result;
    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        result[s] = resultant / geometry.measure;
        for (unsigned int l = 0; l < n_rotations; ++l)
          result[s] += omega[l] * rotation(l, offset[s]);
      }
    return result;
  }



  template <int dim>
  double
  JohnsonKrizekMercierElement<dim>::constraint_defect(
    const Geometry  &geometry,
    const Field     &field,
    const Traction  &traction,
    const BodyForce &body_force)
  {
    // rho = |E| / max |F_s| (a length of the order of the smallest height);
    // |F_s| = face_ratio_s |F^_s|, |F^_0| = sqrt(d) / (d - 1)!, |F^_k| =
    // 1 / (d - 1)!
    double largest_face = 0.;
    for (unsigned int s = 0; s < n_vertices; ++s)
      largest_face =
        std::max(largest_face,
                 geometry.face_ratio[s] *
                   (s == 0 ? std::sqrt(double(dim)) : 1.) / factorial(dim - 1));
    const double rho   = geometry.measure / largest_face;
    double       scale = 0., defect = 0.;
    for (const auto &t : traction)
      scale = std::max(scale, t.norm());
    for (const auto &f : body_force)
      scale = std::max(scale, rho * f.norm());
    for (const auto &sigma : field)
      scale = std::max(scale, sigma.norm());

    for (unsigned int s = 0; s < n_vertices; ++s)
      {
        const auto gradients = barycentric_gradients<dim>(
          sub_simplex<dim>(geometry.vertices, geometry.centroid, s));
        // continuity across the face shared with T_t
        for (unsigned int t = s + 1; t < n_vertices; ++t)
          {
            const Tensor<1, dim> m = gradients[t] / gradients[t].norm();
            for (unsigned int j = 0; j < n_vertices; ++j)
              if (j != t)
                defect = std::max(defect,
                                  ((field[node_index(s, j)] -
                                    field[node_index(t, j == s ? t : j)]) *
                                   m)
                                    .norm());
          }
        // the tractions of F_s
        for (unsigned int j = 0; j < n_vertices; ++j)
          if (j != s)
            defect = std::max(defect,
                              (field[node_index(s, j)] * geometry.normal[s] -
                               traction[traction_index(s, j, 0) / dim])
                                .norm());
        // the equilibrium of T_s
        Tensor<1, dim> divergence = body_force[s];
        for (unsigned int j = 0; j < n_vertices; ++j)
          divergence += field[node_index(s, j)] * gradients[j];
        defect = std::max(defect, rho * divergence.norm());
      }
    return scale > 0. ? defect / scale : 0.;
  }



  template class JohnsonKrizekMercierElement<2>;
  template class JohnsonKrizekMercierElement<3>;
} // namespace Signorini
