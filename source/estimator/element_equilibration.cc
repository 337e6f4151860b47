#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/thread_local_storage.h>
#include <deal.II/base/work_stream.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <signorini/estimator/element_equilibration.h>

#include <array>
#include <map>
#include <mutex>
#include <tuple>

namespace Signorini
{
  namespace
  {
    /**
     * Vector polynomials of total degree <= k in scaled coordinates
     * xi = (x - x_c) / h on a triangle, without rigid motions: every
     * monomial of degree >= 2 times e_x and e_y, and the linear fields
     * xi e_x, eta e_y, eta e_x + xi e_y.
     */
    class LocalBasis
    {
    public:
      explicit LocalBasis(const unsigned int degree = 3)
      {
        for (unsigned int d = 0; d <= degree; ++d)
          for (unsigned int q = 0; q <= d; ++q)
            exponents.push_back({{d - q, q}});
        // monomial numbers: 0 -> 1, 1 -> xi, 2 -> eta
        functions.push_back({{1, 0, 1.}});
        functions.push_back({{2, 1, 1.}});
        functions.push_back({{2, 0, 1.}, {1, 1, 1.}});
        for (unsigned int m = 3; m < exponents.size(); ++m)
          for (unsigned int c = 0; c < 2; ++c)
            functions.push_back({{m, c, 1.}});
        xi_power.resize(degree + 1);
        eta_power.resize(degree + 1);
        m.resize(exponents.size());
        dm.resize(exponents.size());
      }

      unsigned int
      size() const
      {
        return functions.size();
      }

      /// values (2 components) and gradients (w.r.t. x) of all functions
      void
      evaluate(const Point<2>                     &x,
               const Point<2>                     &center,
               const double                        h,
               std::vector<Tensor<1, 2>>          &values,
               std::vector<SymmetricTensor<2, 2>> &strains) const
      {
        const double xi = (x[0] - center[0]) / h, eta = (x[1] - center[1]) / h;
        // powers 0..degree of xi and eta, then the monomials and gradients
        xi_power[0] = eta_power[0] = 1.;
        for (unsigned int p = 1; p < xi_power.size(); ++p)
          {
            xi_power[p]  = xi_power[p - 1] * xi;
            eta_power[p] = eta_power[p - 1] * eta;
          }
        for (unsigned int i = 0; i < exponents.size(); ++i)
          {
            const auto [p, q] = exponents[i];
            m[i]              = xi_power[p] * eta_power[q];
            dm[i][0] = (p > 0 ? p * xi_power[p - 1] * eta_power[q] : 0.) / h;
            dm[i][1] = (q > 0 ? q * xi_power[p] * eta_power[q - 1] : 0.) / h;
          }
        values.resize(functions.size());
        strains.resize(functions.size());
        for (unsigned int f = 0; f < functions.size(); ++f)
          {
            Tensor<1, 2> v;
            Tensor<2, 2> grad;
            for (const auto &[monomial, component, coefficient] : functions[f])
              {
                v[component] += coefficient * m[monomial];
                grad[component] += coefficient * dm[monomial];
              }
            values[f]  = v;
            strains[f] = symmetrize(grad);
          }
      }

    private:
      std::vector<std::array<unsigned int, 2>> exponents;
      struct Term
      {
        unsigned int monomial, component;
        double       coefficient;
      };
      std::vector<std::vector<Term>> functions;
      // work space of evaluate()
      mutable std::vector<double>       xi_power, eta_power, m;
      mutable std::vector<Tensor<1, 2>> dm;
    };

    enum class FaceKind
    {
      interior,
      loaded, // traction part, contact part, or free (zero traction)
      dirichlet
    };

    struct FaceData
    {
      unsigned int                first_cell  = numbers::invalid_unsigned_int;
      unsigned int                second_cell = numbers::invalid_unsigned_int;
      std::array<unsigned int, 2> vertices;
      double                      length = 0.;
      Tensor<1, 2>                normal; // outward from the first cell
      FaceKind                    kind              = FaceKind::interior;
      std::array<bool, 2>         unknown_component = {{true, true}};
      // b(i) = int_G F phi_i for the two vertices, per component
      std::array<Tensor<1, 2>, 2> projection;
      std::array<Tensor<1, 2>, 2> density; // nodal values of the linear F
    };
  } // namespace



  template <int dim>
  ElementEquilibration<dim>::ElementEquilibration(
    const unsigned int local_degree,
    const bool         optimise_densities)
    : local_degree(local_degree)
    , optimise_densities(optimise_densities)
  {}



  template <int dim>
  std::string
  ElementEquilibration<dim>::name() const
  {
    return "element equilibration";
  }



  template <int dim>
  double
  ElementEquilibration<dim>::equilibrium_defect() const
  {
    return max_equilibrium_defect;
  }



  template <int dim>
  double
  ElementEquilibration<dim>::prolongation_defect() const
  {
    return max_prolongation_defect;
  }



  template <int dim>
  void
  ElementEquilibration<dim>::compute(const EquilibrationInput<dim> &input,
                                     const LA::Vector &admissible_displacement,
                                     Vector<double>   &error_squared,
                                     Vector<double>   &sum_squared)
  {
    static_assert(dim == 2,
                  "the element equilibration is written for triangles");
    const auto &dof_handler   = input.dof_handler;
    const auto &triangulation = dof_handler.get_triangulation();
    const auto &fe            = dof_handler.get_fe();
    const auto &material      = input.material;
    const auto &bc            = input.boundary_conditions;
    AssertThrow(!triangulation.has_hanging_nodes(),
                ExcMessage(
                  "the element equilibration needs a conforming mesh"));

    const unsigned int n_cells = triangulation.n_active_cells();
    error_squared.reinit(n_cells);
    sum_squared.reinit(n_cells);
    max_equilibrium_defect  = 0.;
    max_prolongation_defect = 0.;

    // --- 1. per cell: sigma_h, strain of U^, Q_E(i) --------------------
    const QGaussSimplex<dim>         quadrature(3); // as in the assembly
    const QGaussSimplex<dim - 1>     face_quadrature(3);
    FEValues<dim>                    fe_values(input.mapping,
                            fe,
                            quadrature,
                            update_values | update_gradients |
                              update_quadrature_points | update_JxW_values);
    FEFaceValues<dim>                fe_face_values(input.mapping,
                                     fe,
                                     face_quadrature,
                                     update_values | update_quadrature_points |
                                       update_JxW_values |
                                       update_normal_vectors);
    const FEValuesExtractors::Vector displacement(0);

    std::vector<SymmetricTensor<2, dim>>       sigma_h(n_cells);
    std::vector<SymmetricTensor<2, dim>>       strain_hat(n_cells);
    std::vector<std::array<Tensor<1, dim>, 3>> Q(n_cells);
    std::vector<std::array<unsigned int, 3>>   cell_vertices(n_cells);
    std::vector<std::array<unsigned int, 3>>   cell_faces(n_cells);
    std::vector<SymmetricTensor<2, dim>>       strain_values(quadrature.size());
    std::vector<Vector<double>> force(quadrature.size(), Vector<double>(dim));

    std::vector<FaceData> faces(triangulation.n_raw_faces());
    std::map<types::boundary_id,
             const typename BoundaryConditions<dim>::DirichletPart *>
      dirichlet_of_id;
    for (const auto &part : bc.dirichlet)
      for (const auto id : part.ids)
        dirichlet_of_id[id] = &part;
    std::map<types::boundary_id,
             const typename BoundaryConditions<dim>::TractionPart *>
      traction_of_id;
    for (const auto &part : bc.tractions)
      for (const auto id : part.ids)
        traction_of_id[id] = &part;
    const Tensor<1, dim> nu_c = input.contact_boundary.direction();

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const unsigned int E = cell->active_cell_index();
        fe_values.reinit(cell);
        fe_values[displacement].get_function_symmetric_gradients(
          input.equilibrated_displacement, strain_values);
        sigma_h[E] = material.stress(strain_values[0]);
        fe_values[displacement].get_function_symmetric_gradients(
          admissible_displacement, strain_values);
        strain_hat[E] = strain_values[0];
        bc.body_force->vector_value_list(fe_values.get_quadrature_points(),
                                         force);
        for (const unsigned int v : cell->vertex_indices())
          {
            cell_vertices[E][v] = cell->vertex_index(v);
            for (unsigned int c = 0; c < dim; ++c)
              {
                const unsigned int i       = fe.component_to_system_index(c, v);
                double             q_value = 0.;
                for (const unsigned int q :
                     fe_values.quadrature_point_indices())
                  q_value +=
                    ((sigma_h[E] * fe_values.shape_grad_component(i, q, c))[c] -
                     force[q][c] * fe_values.shape_value_component(i, q, c)) *
                    fe_values.JxW(q);
                Q[E][v][c] = q_value;
              }
          }

        for (const unsigned int f : cell->face_indices())
          {
            const auto face  = cell->face(f);
            FaceData  &data  = faces[face->index()];
            cell_faces[E][f] = face->index();
            if (data.first_cell != numbers::invalid_unsigned_int)
              {
                data.second_cell = E;
                continue;
              }
            data.first_cell = E;
            data.vertices   = {{face->vertex_index(0), face->vertex_index(1)}};
            data.length     = face->measure();
            fe_face_values.reinit(cell, f);
            data.normal = fe_face_values.normal_vector(0);
            if (!face->at_boundary())
              continue;

            // boundary face: known traction projections unless Dirichlet
            data.kind              = FaceKind::loaded;
            data.unknown_component = {{false, false}};
            const auto id          = face->boundary_id();
            if (dirichlet_of_id.count(id) != 0)
              for (unsigned int c = 0; c < dim; ++c)
                if (dirichlet_of_id[id]->mask[c])
                  {
                    data.kind                 = FaceKind::dirichlet;
                    data.unknown_component[c] = true;
                  }
            // cell-local numbers of the face vertices
            std::array<unsigned int, 2> local_vertex;
            for (unsigned int k = 0; k < 2; ++k)
              for (const unsigned int w : cell->vertex_indices())
                if (cell->vertex_index(w) == data.vertices[k])
                  local_vertex[k] = w;
            if (traction_of_id.count(id) != 0)
              {
                std::vector<Vector<double>> traction(face_quadrature.size(),
                                                     Vector<double>(dim));
                traction_of_id[id]->traction->vector_value_list(
                  fe_face_values.get_quadrature_points(), traction);
                for (unsigned int k = 0; k < 2; ++k)
                  for (unsigned int c = 0; c < dim; ++c)
                    {
                      const unsigned int i =
                        fe.component_to_system_index(c, local_vertex[k]);
                      for (const unsigned int q :
                           fe_face_values.quadrature_point_indices())
                        data.projection[k][c] +=
                          traction[q][c] *
                          fe_face_values.shape_value_component(i, q, c) *
                          fe_face_values.JxW(q);
                    }
              }
            if (input.contact_boundary.boundary_ids().count(id) != 0)
              {
                // R^ = R^_n nu_c, linear on the edge: int R^_n psi_k exactly
                const double r0 =
                  input.normal_reaction[input.contact_boundary.node_index(
                    data.vertices[0])];
                const double r1 =
                  input.normal_reaction[input.contact_boundary.node_index(
                    data.vertices[1])];
                data.projection[0] += data.length / 6. * (2. * r0 + r1) * nu_c;
                data.projection[1] += data.length / 6. * (r0 + 2. * r1) * nu_c;
              }
          }
      }

    // --- 2. vertex patches: edge projections b_G(i) ----------------------
    struct FreeDirection
    {
      unsigned int vertex, component;
      std::vector<std::tuple<unsigned int, unsigned int, double>> entries;
    };
    std::vector<FreeDirection>             free_directions;
    std::vector<std::vector<unsigned int>> cells_of_vertex(
      triangulation.n_vertices());
    for (unsigned int E = 0; E < n_cells; ++E)
      for (unsigned int v = 0; v < 3; ++v)
        cells_of_vertex[cell_vertices[E][v]].push_back(E);

    for (unsigned int vertex = 0; vertex < cells_of_vertex.size(); ++vertex)
      {
        const auto &patch = cells_of_vertex[vertex];
        if (patch.empty())
          continue;
        // faces of the patch incident to the vertex, and which end it is
        std::vector<std::pair<unsigned int, unsigned int>> patch_faces;
        for (const unsigned int E : patch)
          for (const unsigned int f : cell_faces[E])
            {
              const FaceData &data = faces[f];
              for (unsigned int k = 0; k < 2; ++k)
                if (data.vertices[k] == vertex &&
                    std::find(patch_faces.begin(),
                              patch_faces.end(),
                              std::make_pair(f, k)) == patch_faces.end())
                  patch_faces.emplace_back(f, k);
            }
        for (unsigned int c = 0; c < dim; ++c)
          {
            std::vector<unsigned int> unknown; // positions in patch_faces
            for (unsigned int p = 0; p < patch_faces.size(); ++p)
              if (faces[patch_faces[p].first].unknown_component[c])
                unknown.push_back(p);
            const unsigned int n_eq = patch.size(), n_un = unknown.size();
            FullMatrix<double> A(n_eq, std::max(n_un, 1u));
            Vector<double>     rhs(n_eq), b_bar(std::max(n_un, 1u));
            for (unsigned int e = 0; e < n_eq; ++e)
              {
                const unsigned int E = patch[e];
                unsigned int       v = 0;
                while (cell_vertices[E][v] != vertex)
                  ++v;
                rhs[e] = Q[E][v][c];
                for (unsigned int p = 0; p < patch_faces.size(); ++p)
                  {
                    const auto &[f, k]   = patch_faces[p];
                    const FaceData &data = faces[f];
                    if (data.first_cell != E && data.second_cell != E)
                      continue;
                    const double eta = (data.first_cell == E) ? 1. : -1.;
                    const auto   it =
                      std::find(unknown.begin(), unknown.end(), p);
                    if (it != unknown.end())
                      A(e, it - unknown.begin()) = eta;
                    else
                      rhs[e] -= eta * data.projection[k][c];
                  }
              }
            for (unsigned int u = 0; u < n_un; ++u)
              {
                const auto &[f, k]   = patch_faces[unknown[u]];
                const FaceData &data = faces[f];
                Tensor<1, dim>  t    = sigma_h[data.first_cell] * data.normal;
                if (data.second_cell != numbers::invalid_unsigned_int)
                  t = 0.5 * (t + sigma_h[data.second_cell] * data.normal);
                b_bar[u] = t[c] * data.length / 2.;
              }
            Vector<double> b(b_bar);
            if (n_un > 0)
              {
                // b = b_bar + A^T (A A^T)^+ (rhs - A b_bar)
                Vector<double> defect(n_eq);
                A.vmult(defect, b_bar);
                defect.sadd(-1., 1., rhs);
                LAPACKFullMatrix<double> AAt(n_eq, n_eq);
                for (unsigned int i = 0; i < n_eq; ++i)
                  for (unsigned int j = 0; j < n_eq; ++j)
                    for (unsigned int u = 0; u < n_un; ++u)
                      AAt(i, j) += A(i, u) * A(j, u);
                AAt.compute_inverse_svd(1e-10);
                Vector<double> lambda(n_eq);
                AAt.vmult(lambda, defect);
                Vector<double> correction(n_un);
                A.Tvmult(correction, lambda);
                for (unsigned int u = 0; u < n_un; ++u)
                  {
                    b[u] += correction[u];
                    const auto &[f, k]        = patch_faces[unknown[u]];
                    faces[f].projection[k][c] = b[u];
                  }
              }
            // directions b -> b + t z, A z = 0, that keep the prolongation
            // condition: the free parameters of the patch
            if (optimise_densities && n_un > 0)
              {
                LAPACKFullMatrix<double> A_svd(n_eq, n_un);
                for (unsigned int i = 0; i < n_eq; ++i)
                  for (unsigned int u = 0; u < n_un; ++u)
                    A_svd(i, u) = A(i, u);
                A_svd.compute_svd();
                double       largest = 0.;
                unsigned int rank    = 0;
                for (unsigned int i = 0; i < std::min(n_eq, n_un); ++i)
                  largest = std::max(largest, A_svd.singular_value(i));
                for (unsigned int i = 0; i < std::min(n_eq, n_un); ++i)
                  rank += (A_svd.singular_value(i) > 1e-10 * largest) ? 1 : 0;
                const auto &vt = A_svd.get_svd_vt();
                for (unsigned int r = rank; r < n_un; ++r)
                  {
                    FreeDirection direction;
                    direction.vertex    = vertex;
                    direction.component = c;
                    for (unsigned int u = 0; u < n_un; ++u)
                      if (std::abs(vt(r, u)) > 1e-14)
                        direction.entries.emplace_back(
                          patch_faces[unknown[u]].first,
                          patch_faces[unknown[u]].second,
                          vt(r, u));
                    free_directions.push_back(direction);
                  }
              }
            // prolongation condition residual of this patch
            Vector<double> check(n_eq);
            if (n_un > 0)
              A.vmult(check, b);
            check -= rhs;
            max_prolongation_defect =
              std::max(max_prolongation_defect, check.linfty_norm());
          }
      }

    double q_scale = 0.;
    for (const auto &q_cell : Q)
      for (const auto &q_vertex : q_cell)
        q_scale = std::max(q_scale, q_vertex.norm());
    if (q_scale > 0.)
      max_prolongation_defect /= q_scale;

    // --- 3. linear densities from the two projections of each edge --------
    // [b0, b1] = L/6 [[2, 1], [1, 2]] [F0, F1]
    const auto update_densities = [&]() {
      for (auto &data : faces)
        if (data.first_cell != numbers::invalid_unsigned_int)
          for (unsigned int c = 0; c < dim; ++c)
            {
              const double b0    = data.projection[0][c],
                           b1    = data.projection[1][c];
              data.density[0][c] = 2. / data.length * (2. * b0 - b1);
              data.density[1][c] = 2. / data.length * (2. * b1 - b0);
            }
    };
    update_densities();

    // --- 4. local Neumann problems -----------------------------------------
    // The local basis keeps work space: one copy per thread.
    Threads::ThreadLocalStorage<LocalBasis> basis_of_thread{
      LocalBasis(local_degree)};
    const unsigned int                n = basis_of_thread.get().size();
    std::mutex                        defect_mutex;
    const QWitherdenVincentSimplex<2> cell_rule(4);
    const QGauss<1>                   edge_rule(4);

    struct Geometry
    {
      Point<2>     x0, center;
      Tensor<2, 2> J;
      double       det, h;
    };
    const auto geometry = [&](const auto &cell) {
      Geometry g;
      g.x0 = cell->vertex(0);
      for (unsigned int d = 0; d < 2; ++d)
        {
          g.J[d][0] = cell->vertex(1)[d] - g.x0[d];
          g.J[d][1] = cell->vertex(2)[d] - g.x0[d];
        }
      g.det    = std::abs(determinant(g.J));
      g.center = cell->center();
      g.h      = 0.;
      for (const unsigned int f : cell->face_indices())
        g.h =
          std::max(g.h, faces[cell_faces[cell->active_cell_index()][f]].length);
      return g;
    };

    // factorised local stiffness matrix
    const auto local_matrix = [&](const Geometry &g) {
      const LocalBasis                  &basis = basis_of_thread.get();
      std::vector<Tensor<1, 2>>          values;
      std::vector<SymmetricTensor<2, 2>> strains;
      LAPACKFullMatrix<double>           stiffness(n, n);
      for (unsigned int q = 0; q < cell_rule.size(); ++q)
        {
          const Point<2> x = g.x0 + g.J * cell_rule.point(q);
          basis.evaluate(x, g.center, g.h, values, strains);
          const double JxW = cell_rule.weight(q) * g.det;
          for (unsigned int a = 0; a < n; ++a)
            {
              const SymmetricTensor<2, 2> sigma_a = material.stress(strains[a]);
              for (unsigned int b = 0; b < n; ++b)
                stiffness(a, b) += (sigma_a * strains[b]) * JxW;
            }
        }
      stiffness.set_property(LAPACKSupport::symmetric);
      stiffness.compute_cholesky_factorization();
      return stiffness;
    };

    // load of a linear density (nodal values) on face f of cell E
    const auto add_edge_load = [&](const unsigned int                 E,
                                   const Geometry                    &g,
                                   const FaceData                    &data,
                                   const std::array<Tensor<1, 2>, 2> &density,
                                   Vector<double>                    &load,
                                   Tensor<1, 2>                      *resultant,
                                   double                            *moment) {
      const LocalBasis                  &basis = basis_of_thread.get();
      std::vector<Tensor<1, 2>>          values;
      std::vector<SymmetricTensor<2, 2>> strains;
      const double   eta = (data.first_cell == E) ? 1. : -1.;
      const Point<2> a   = triangulation.get_vertices()[data.vertices[0]];
      const Point<2> b   = triangulation.get_vertices()[data.vertices[1]];
      for (unsigned int q = 0; q < edge_rule.size(); ++q)
        {
          const double       s = edge_rule.point(q)[0];
          const Point<2>     x = a + s * (b - a);
          const Tensor<1, 2> F = eta * ((1. - s) * density[0] + s * density[1]);
          const double       JxW = edge_rule.weight(q) * data.length;
          if (resultant != nullptr)
            {
              *resultant += F * JxW;
              *moment += cross_product_2d(x - g.center) * F * JxW;
            }
          basis.evaluate(x, g.center, g.h, values, strains);
          for (unsigned int k = 0; k < n; ++k)
            load[k] += (F * values[k]) * JxW;
        }
    };

    // full load of a cell (body force with the rule of the assembly, so
    // that the element data are in equilibrium to round-off), and checks
    const auto local_load = [&](const auto &cell, const Geometry &g) {
      const LocalBasis                  &basis = basis_of_thread.get();
      const unsigned int                 E     = cell->active_cell_index();
      std::vector<Tensor<1, 2>>          values;
      std::vector<SymmetricTensor<2, 2>> strains;
      Vector<double>                     load(n);
      Tensor<1, 2>                       resultant;
      double                             moment = 0., data_scale = 0.;
      std::vector<Point<2>>              points(quadrature.size());
      std::vector<Vector<double>>        f_values(quadrature.size(),
                                           Vector<double>(2));
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        points[q] = g.x0 + g.J * quadrature.point(q);
      bc.body_force->vector_value_list(points, f_values);
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        {
          const double JxW = quadrature.weight(q) * g.det;
          basis.evaluate(points[q], g.center, g.h, values, strains);
          const Tensor<1, 2> f({f_values[q][0], f_values[q][1]});
          resultant += f * JxW;
          moment += cross_product_2d(points[q] - g.center) * f * JxW;
          data_scale += f.norm() * JxW;
          for (unsigned int a = 0; a < n; ++a)
            load[a] += (f * values[a]) * JxW;
        }
      for (const unsigned int f : cell->face_indices())
        {
          const FaceData &data = faces[cell_faces[E][f]];
          add_edge_load(E, g, data, data.density, load, &resultant, &moment);
          data_scale += 0.5 *
                        (data.density[0].norm() + data.density[1].norm()) *
                        data.length;
        }
      std::lock_guard<std::mutex> lock(defect_mutex);
      if (data_scale > 0.)
        max_equilibrium_defect =
          std::max({max_equilibrium_defect,
                    resultant.norm() / data_scale,
                    std::abs(moment) / (data_scale * g.h)});
      return load;
    };

    // coefficients of U^ (its strain) in the local basis: xi e_x, eta e_y,
    // eta e_x + xi e_y carry h eps_xx, h eps_yy, h eps_xy
    const auto admissible_coefficients = [&](const unsigned int E,
                                             const Geometry    &g) {
      Vector<double> u_hat(n);
      u_hat[0] = g.h * strain_hat[E][0][0];
      u_hat[1] = g.h * strain_hat[E][1][1];
      u_hat[2] = g.h * strain_hat[E][0][1];
      return u_hat;
    };

    // --- 5. optional: the error-minimising choice in the admissible family -
    // J(t) = sum_E ||w_E + sum_d t_d s_Ed||^2_{K_E}, w_E = v_E - U^_E the
    // local error field, s_Ed = K_E^{-1} dload_Ed the response of E to the
    // free direction d: minimise by CG on H t = -g with
    // H_dd' = sum_E dload_Ed . s_Ed', g_d = sum_E w_E . dload_Ed.
    if (optimise_densities && !free_directions.empty())
      {
        const unsigned int n_directions = free_directions.size();
        std::vector<std::vector<unsigned int>> directions_of_cell(n_cells);
        for (unsigned int d = 0; d < n_directions; ++d)
          for (const unsigned int E :
               cells_of_vertex[free_directions[d].vertex])
            directions_of_cell[E].push_back(d);
        DynamicSparsityPattern dsp(n_directions, n_directions);
        for (const auto &directions : directions_of_cell)
          for (const unsigned int d : directions)
            for (const unsigned int e : directions)
              dsp.add(d, e);
        SparsityPattern sparsity;
        sparsity.copy_from(dsp);
        SparseMatrix<double> H(sparsity);
        Vector<double>       g(n_directions);

        for (const auto &cell : dof_handler.active_cell_iterators())
          {
            const unsigned int E          = cell->active_cell_index();
            const auto        &directions = directions_of_cell[E];
            if (directions.empty())
              continue;
            const Geometry           geo       = geometry(cell);
            LAPACKFullMatrix<double> stiffness = local_matrix(geo);
            Vector<double>           w         = local_load(cell, geo);
            stiffness.solve(w);
            w -= admissible_coefficients(E, geo);
            std::vector<Vector<double>> delta_load(directions.size(),
                                                   Vector<double>(n));
            std::vector<Vector<double>> response(directions.size());
            for (unsigned int i = 0; i < directions.size(); ++i)
              {
                const auto &direction = free_directions[directions[i]];
                for (const auto &[f, k, value] : direction.entries)
                  {
                    const FaceData &data = faces[f];
                    if (data.first_cell != E && data.second_cell != E)
                      continue;
                    std::array<Tensor<1, 2>, 2> density;
                    density[k][direction.component] = 4. / data.length * value;
                    density[1 - k][direction.component] =
                      -2. / data.length * value;
                    add_edge_load(
                      E, geo, data, density, delta_load[i], nullptr, nullptr);
                  }
                response[i] = delta_load[i];
                stiffness.solve(response[i]);
                g[directions[i]] += w * delta_load[i];
              }
            for (unsigned int i = 0; i < directions.size(); ++i)
              for (unsigned int j = 0; j < directions.size(); ++j)
                H.add(directions[i],
                      directions[j],
                      delta_load[i] * response[j]);
          }
        Vector<double> t(n_directions);
        g *= -1.;
        SolverControl            control(10 * n_directions + 100,
                              1e-10 * g.l2_norm(),
                              false,
                              false);
        SolverCG<Vector<double>> cg(control);
        PreconditionJacobi<SparseMatrix<double>> jacobi;
        jacobi.initialize(H);
        try
          {
            cg.solve(H, t, g, jacobi);
          }
        catch (const SolverControl::NoConvergence &)
          {
            // keep the partial minimisation: every t stays admissible
          }
        for (unsigned int d = 0; d < n_directions; ++d)
          for (const auto &[f, k, value] : free_directions[d].entries)
            faces[f].projection[k][free_directions[d].component] +=
              t[d] * value;
        update_densities();
      }

    // --- 6. sigma^ = K eps(v) and the error per element (cells in parallel)
    struct NoScratch
    {};
    struct NoCopy
    {};
    const auto element_error =
      [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
          NoScratch &,
          NoCopy &) {
        const LocalBasis                  &basis = basis_of_thread.get();
        std::vector<Tensor<1, 2>>          values;
        std::vector<SymmetricTensor<2, 2>> strains;
        const unsigned int                 E = cell->active_cell_index();
        const Geometry                     g = geometry(cell);
        Vector<double>                     v = local_load(cell, g);
        local_matrix(g).solve(v);
        // ||sigma^ -/+ K eps(U^)||^2 = int (eps(v) -/+ eps(U^)) : K : (...)
        double error = 0., sum = 0.;
        for (unsigned int q = 0; q < cell_rule.size(); ++q)
          {
            const Point<2> x   = g.x0 + g.J * cell_rule.point(q);
            const double   JxW = cell_rule.weight(q) * g.det;
            basis.evaluate(x, g.center, g.h, values, strains);
            SymmetricTensor<2, 2> eps_v;
            for (unsigned int a = 0; a < n; ++a)
              eps_v += v[a] * strains[a];
            const SymmetricTensor<2, 2> minus = eps_v - strain_hat[E];
            const SymmetricTensor<2, 2> plus  = eps_v + strain_hat[E];
            error += (material.stress(minus) * minus) * JxW;
            sum += (material.stress(plus) * plus) * JxW;
          }
        error_squared[E] = error; // each cell writes its own entries
        sum_squared[E]   = sum;
      };
    WorkStream::run(
      dof_handler.begin_active(),
      dof_handler.end(),
      element_error,
      [](const NoCopy &) {},
      NoScratch(),
      NoCopy());
  }

  template class ElementEquilibration<2>;
} // namespace Signorini
