// The Johnson-Krizek-Mercier macro-element (JohnsonKrizekMercierElement) on
// triangles and tetrahedra: a well shaped simplex, one of negative
// orientation, a tiny one and a flat one, in both dimensions.
// 1. the tractions of a constant stress give that stress at every node;
// 2. a linear stress field with its body force -div sigma is reproduced at
//    every node (the field is unique);
// 3. random data in equilibrium (random tractions on the faces, a random
//    body force per sub-simplex made to balance them): the constraints,
//    checked on the simplex itself (continuity of sigma n across the
//    interior faces, sigma n = t on the faces, div sigma + f = 0), hold to
//    round-off, and the resultant and moment of sigma n over the boundary
//    equal those of t;
// 4. the quadratic t^T H t + 2 g^T t + c (hessian(), linear_part()) equals
//    energy() of the field, for random t, f and tau;
// 5. balanced_body_force() returns a constant force unchanged and matches
//    the resultant and moments it is given;
// 6. on triangles the field equals the Johnson-Mercier field of
//    JohnsonMercierElement (an independent implementation) at the
//    centroids of the sub-triangles;
// 7. a sliver is refused.
// The tolerances are 1e-12 times the square of the shape factor diam^d /
// (d! |E|), how the round-off grows on flat simplices.
// Pass/fail lines only.

#include <signorini/estimator/johnson_krizek_mercier_element.h>
#include <signorini/estimator/johnson_mercier_element.h>

#include "tests.h"

#include <random>

using namespace SignoriniTests;

namespace
{
  const char *
  yes_no(const bool ok, unsigned int &failures)
  {
    if (!ok)
      ++failures;
    return ok ? "yes" : "NO";
  }

  template <int dim>
  using Simplex = std::array<Point<dim>, dim + 1>;

  /// The test simplices: well shaped, negative orientation, tiny, flat.
  template <int dim>
  std::vector<std::pair<std::string, Simplex<dim>>>
  simplices()
  {
    Simplex<dim> well;
    for (unsigned int k = 1; k <= dim; ++k)
      for (unsigned int i = 0; i < dim; ++i)
        well[k][i] = (i + 1 == k ? 1. : 0.) + 0.1 * (i + 2 * k) + 0.05 * i;
    well[0]               = Point<dim>();
    well[0][0]            = -0.2;
    Simplex<dim> negative = well;
    std::swap(negative[0], negative[1]);
    Simplex<dim> tiny;
    for (unsigned int v = 0; v <= dim; ++v)
      {
        tiny[v] = Point<dim>() + 1e-7 * (well[v] - Point<dim>());
        tiny[v][0] += 3e-7;
      }
    Simplex<dim> flat = well;
    for (unsigned int v = 0; v <= dim; ++v)
      flat[v][dim - 1] *= 0.02;
    return {{"well shaped", well},
            {"negative orientation", negative},
            {"tiny (1e-7)", tiny},
            {"flat (1:50)", flat}};
  }

  template <int dim>
  SymmetricTensor<2, dim>
  random_stress(std::mt19937 &generator)
  {
    std::uniform_real_distribution<double> uniform(-1., 1.);
    SymmetricTensor<2, dim>                result;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = i; j < dim; ++j)
        result[i][j] = uniform(generator);
    return result;
  }

  /// The integral over each face F_s of l (linear, values @p a at the
  /// corners) times m (values @p b): |F| / (d (d + 1)) (sum a_i b_i +
  /// sum a sum b).
  template <int dim>
  double
  face_product(const double               measure,
               const std::vector<double> &a,
               const std::vector<double> &b)
  {
    double diagonal = 0., sum_a = 0., sum_b = 0.;
    for (unsigned int i = 0; i < a.size(); ++i)
      {
        diagonal += a[i] * b[i];
        sum_a += a[i];
        sum_b += b[i];
      }
    return measure * (diagonal + sum_a * sum_b) / (dim * (dim + 1.));
  }

  /// The resultant and the moments about the centroid of a traction given
  /// at the corners of the faces.
  template <int dim>
  std::pair<Tensor<1, dim>, std::array<double, (dim * (dim - 1)) / 2>>
  traction_loads(
    const typename JohnsonKrizekMercierElement<dim>::Geometry &g,
    const typename JohnsonKrizekMercierElement<dim>::Traction &traction)
  {
    using JKM = JohnsonKrizekMercierElement<dim>;
    Tensor<1, dim>                            resultant;
    std::array<double, (dim * (dim - 1)) / 2> moments{};
    for (unsigned int s = 0; s <= dim; ++s)
      {
        // |F_s| from the outward normal: |F_s| = d |E| |grad lambda_s|, and
        // face_ratio = |F_s| / |F^_s|
        const double measure = g.face_ratio[s] *
                               (s == 0 ? std::sqrt(double(dim)) : 1.) /
                               (dim == 2 ? 1. : 2.);
        for (unsigned int c = 0; c < dim; ++c)
          {
            std::vector<double> t, one, r;
            for (unsigned int j = 0; j <= dim; ++j)
              if (j != s)
                t.push_back(traction[JKM::traction_index(s, j, 0) / dim][c]);
            one.assign(t.size(), 1.);
            resultant[c] += face_product<dim>(measure, t, one);
            for (unsigned int k = 0; k < moments.size(); ++k)
              {
                r.clear();
                for (unsigned int j = 0; j <= dim; ++j)
                  if (j != s)
                    r.push_back(
                      JKM::rotation(k, g.vertices[j] - g.centroid)[c]);
                moments[k] += face_product<dim>(measure, t, r);
              }
          }
      }
    return {resultant, moments};
  }

  template <int dim>
  unsigned int
  check(const LinearElasticMaterial<dim> &material, std::mt19937 &generator)
  {
    using JKM = JohnsonKrizekMercierElement<dim>;
    const JKM                              element(material);
    unsigned int                           failures = 0;
    std::uniform_real_distribution<double> uniform(-1., 1.);
    for (const auto &[name, vertices] : simplices<dim>())
      {
        const auto g = JKM::geometry(vertices);
        deallog << dim << "D, " << name << ':' << std::endl;
        // round-off grows like the square of the aspect ratio
        const double shape = std::pow(g.diameter, double(dim)) /
                             (g.measure * (dim == 2 ? 2. : 6.));
        const double tolerance = 1e-12 * shape * shape;

        // 1. a constant stress
        const SymmetricTensor<2, dim> sigma0 = random_stress<dim>(generator);
        typename JKM::Traction        traction;
        typename JKM::BodyForce       no_force;
        for (unsigned int s = 0; s <= dim; ++s)
          for (unsigned int j = 0; j <= dim; ++j)
            if (j != s)
              traction[JKM::traction_index(s, j, 0) / dim] =
                sigma0 * g.normal[s];
        double error = 0.;
        for (const auto &value : element.field(g, traction, no_force))
          error = std::max(error, (value - sigma0).norm() / sigma0.norm());
        deallog << "   constant stress reproduced: "
                << yes_no(error < tolerance, failures) << std::endl;

        // 2. a linear stress sigma0 + sum_k (x - g)_k A_k, f = -div sigma
        std::array<SymmetricTensor<2, dim>, dim> slope;
        for (auto &a : slope)
          a = random_stress<dim>(generator) / g.diameter;
        const auto linear = [&](const Point<dim> &x) {
          SymmetricTensor<2, dim> value = sigma0;
          for (unsigned int k = 0; k < dim; ++k)
            value += (x - g.centroid)[k] * slope[k];
          return value;
        };
        Tensor<1, dim> divergence;
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = 0; b < dim; ++b)
            divergence[a] += slope[b][a][b];
        typename JKM::BodyForce force;
        for (auto &f : force)
          f = -divergence;
        for (unsigned int s = 0; s <= dim; ++s)
          for (unsigned int j = 0; j <= dim; ++j)
            if (j != s)
              traction[JKM::traction_index(s, j, 0) / dim] =
                linear(vertices[j]) * g.normal[s];
        const auto field = element.field(g, traction, force);
        error            = 0.;
        for (unsigned int s = 0; s <= dim; ++s)
          for (unsigned int j = 0; j <= dim; ++j)
            error = std::max(error,
                             (field[JKM::node_index(s, j)] -
                              linear(j == s ? g.centroid : vertices[j]))
                                 .norm() /
                               sigma0.norm());
        deallog << "   linear stress reproduced: "
                << yes_no(error < tolerance, failures) << std::endl;

        // 3. random data in equilibrium
        for (auto &t : traction)
          for (unsigned int c = 0; c < dim; ++c)
            t[c] = uniform(generator);
        for (auto &f : force)
          for (unsigned int c = 0; c < dim; ++c)
            f[c] = uniform(generator) / g.diameter;
        {
          // keep the self-equilibrated part of the random force, and add
          // the force that balances the tractions
          const auto [resultant, moments] = traction_loads<dim>(g, traction);
          Tensor<1, dim>                            force_resultant;
          std::array<double, (dim * (dim - 1)) / 2> force_moments{};
          for (unsigned int s = 0; s <= dim; ++s)
            {
              Point<dim> centre = g.centroid;
              for (unsigned int j = 0; j <= dim; ++j)
                if (j != s)
                  centre += vertices[j];
              centre /= dim + 1.;
              force_resultant += g.measure / (dim + 1.) * force[s];
              for (unsigned int k = 0; k < force_moments.size(); ++k)
                force_moments[k] +=
                  g.measure / (dim + 1.) *
                  (force[s] * JKM::rotation(k, centre - g.centroid));
            }
          const auto removed =
            JKM::balanced_body_force(g, force_resultant, force_moments);
          std::array<double, (dim * (dim - 1)) / 2> minus_moments;
          for (unsigned int k = 0; k < moments.size(); ++k)
            minus_moments[k] = -moments[k];
          const auto balancing =
            JKM::balanced_body_force(g, -resultant, minus_moments);
          for (unsigned int s = 0; s <= dim; ++s)
            force[s] += balancing[s] - removed[s];
        }
        const auto   random_field = element.field(g, traction, force);
        const double defect =
          JKM::constraint_defect(g, random_field, traction, force);
        // the tractions of the field carry the loads of the data
        typename JKM::Traction field_traction;
        for (unsigned int s = 0; s <= dim; ++s)
          for (unsigned int j = 0; j <= dim; ++j)
            if (j != s)
              field_traction[JKM::traction_index(s, j, 0) / dim] =
                random_field[JKM::node_index(s, j)] * g.normal[s];
        const auto data_loads  = traction_loads<dim>(g, traction);
        const auto field_loads = traction_loads<dim>(g, field_traction);
        double     load_error  = (data_loads.first - field_loads.first).norm();
        double     load_scale  = data_loads.first.norm();
        for (unsigned int k = 0; k < data_loads.second.size(); ++k)
          {
            load_error =
              std::max(load_error,
                       std::abs(data_loads.second[k] - field_loads.second[k]) /
                         g.diameter);
            load_scale =
              std::max(load_scale, std::abs(data_loads.second[k]) / g.diameter);
          }
        deallog << "   random data in equilibrium: constraints hold: "
                << yes_no(defect < tolerance, failures)
                << ", loads of sigma n = loads of t: "
                << yes_no(load_error < tolerance * load_scale, failures)
                << std::endl;

        // 4. the quadratic in the tractions
        const SymmetricTensor<2, dim> tau     = random_stress<dim>(generator);
        const auto                    hessian = element.hessian(g);
        const auto [gradient, constant]  = element.linear_part(g, force, tau);
        constexpr unsigned int n         = JKM::n_traction_values;
        double                 quadratic = constant;
        for (unsigned int i = 0; i < n; ++i)
          {
            const double t_i = traction[i / dim][i % dim];
            quadratic += 2. * gradient[i] * t_i;
            for (unsigned int j = 0; j < n; ++j)
              quadratic +=
                t_i * hessian[i * n + j] * traction[j / dim][j % dim];
          }
        const double energy = element.energy(g, random_field, tau);
        deallog << "   quadratic = energy: "
                << yes_no(std::abs(quadratic - energy) < tolerance * energy,
                          failures)
                << std::endl;

        // 5. the balanced body force
        const Tensor<1, dim>                      constant_force = force[0];
        std::array<double, (dim * (dim - 1)) / 2> no_moment{};
        const auto                                same =
          JKM::balanced_body_force(g, g.measure * constant_force, no_moment);
        double difference = 0.;
        for (const auto &f : same)
          difference =
            std::max(difference,
                     (f - constant_force).norm() / constant_force.norm());
        deallog << "   constant body force kept: "
                << yes_no(difference < 1e-13, failures) << std::endl;

        // 6. the Johnson-Mercier field of the triangle code
        if constexpr (dim == 2)
          {
            const JohnsonMercierElement jm(
              JohnsonMercierElement::compliance_matrix(material));
            // T_e of JohnsonMercierElement = (g, x_e, x_e+1) carries edge e,
            // the face opposite x_(e+2): our T_s, s = e + 2
            Vector<double>                   jm_traction(12);
            JohnsonMercierElement::BodyForce jm_force;
            for (unsigned int e = 0; e < 3; ++e)
              {
                const unsigned int s = (e + 2) % 3;
                jm_force[e]          = force[s];
                for (unsigned int k = 0; k < 2; ++k)
                  for (unsigned int c = 0; c < 2; ++c)
                    jm_traction[JohnsonMercierElement::traction_index(
                      e, k, c)] =
                      traction[JKM::traction_index(s, (e + k) % 3, 0) / 2][c];
              }
            const auto     response = jm.response(vertices);
            Vector<double> coefficients(27), force_vector(6);
            for (unsigned int e = 0; e < 3; ++e)
              for (unsigned int c = 0; c < 2; ++c)
                force_vector[2 * e + c] = jm_force[e][c];
            response.stress_of_traction.vmult(coefficients, jm_traction);
            response.stress_of_body_force.vmult_add(coefficients, force_vector);
            double jm_difference = 0., size = 0.;
            for (unsigned int e = 0; e < 3; ++e)
              {
                const unsigned int s = (e + 2) % 3;
                const Point<2>     centre(
                  (g.centroid[0] + vertices[e][0] + vertices[(e + 1) % 3][0]) /
                    3.,
                  (g.centroid[1] + vertices[e][1] + vertices[(e + 1) % 3][1]) /
                    3.);
                const auto ours   = JKM::value(g, random_field, s, centre);
                const auto theirs = JohnsonMercierElement::value(vertices,
                                                                 coefficients,
                                                                 e,
                                                                 centre);
                jm_difference = std::max(jm_difference, (ours - theirs).norm());
                size          = std::max(size, ours.norm());
              }
            deallog << "   equal to the Johnson-Mercier field: "
                    << yes_no(jm_difference < tolerance * size, failures)
                    << std::endl;
          }
      }

    // 7. a sliver
    Simplex<dim> sliver = simplices<dim>()[0].second;
    sliver[dim]         = sliver[0] + 1e-7 * (sliver[1] - sliver[0]);
    for (unsigned int k = 1; k < dim; ++k)
      sliver[dim] += 1e-4 * (sliver[k] - sliver[0]);
    bool refused = false;
    try
      {
        JKM::geometry(sliver);
      }
    catch (const std::exception &)
      {
        refused = true;
      }
    deallog << dim << "D sliver refused: " << yes_no(refused, failures)
            << std::endl;
    return failures;
  }
} // namespace

int
main()
{
  initlog();
  std::mt19937             generator(2026);
  LinearElasticMaterial<2> plane;
  plane.set(1., 0.3, LinearElasticMaterial<2>::PlaneState::plane_strain);
  LinearElasticMaterial<3> solid;
  solid.set(1., 0.3, LinearElasticMaterial<3>::PlaneState::plane_strain);
  const unsigned int failures =
    check<2>(plane, generator) + check<3>(solid, generator);
  deallog << (failures == 0 ? "all checks pass" : "SOME CHECKS FAIL")
          << std::endl;
  return failures == 0 ? 0 : 1;
}
