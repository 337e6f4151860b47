#include <deal.II/base/mpi.h>
#include <deal.II/base/parallel.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/work_stream.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <signorini/estimator/element_equilibration.h>
#include <signorini/estimator/local_loops.h>
#include <signorini/input_error.h>

#include <array>
#include <atomic>
#include <exception>
#include <mutex>
#include <tuple>

namespace Signorini
{
  namespace
  {
    /**
     * The space of the local Neumann problems on a triangle E = x0 + J T
     * (T the reference triangle): vector polynomials of total degree <= k
     * without rigid motions, spanned by
     * - the linear fields l_0 e_x, l_1 e_y, l_1 e_x + l_0 e_y with
     *   l = (x - x0) / h (constant strains, so that U^ has coefficients
     *   h eps^_xx, h eps^_yy, h eps^_xy);
     * - m e_x and m e_y for the monomials m of degree 2..k in the reference
     *   coordinates (xi, eta).
     * With the reference monomials of degree 1..k as a common basis of the
     * scalar parts, every integral the local problems need is a reference
     * integral times powers of J^-1: they are tabulated once, and an element
     * costs a few small dense products instead of a quadrature with basis
     * evaluations (this part dominated the estimator).
     */
    class LocalSpace
    {
    public:
      /// @p body_quadrature: the rule of the body-force loads
      LocalSpace(const unsigned int   degree,
                 const Quadrature<2> &body_quadrature)
      {
        for (unsigned int d = 1; d <= degree; ++d)
          for (unsigned int q = 0; q <= d; ++q)
            exponents.push_back({{d - q, q}});
        n_monomials = exponents.size();
        // scalar parts: l_0, l_1, then the monomials of degree >= 2
        n_scalars = 2 + n_monomials - 2;
        functions.push_back({{0, 0, 1.}});
        functions.push_back({{1, 1, 1.}});
        functions.push_back({{1, 0, 1.}, {0, 1, 1.}});
        for (unsigned int j = 2; j < n_scalars; ++j)
          for (unsigned int c = 0; c < 2; ++c)
            functions.push_back({{j, c, 1.}});

        // G^ab_rs = int_T d_a m_r d_b m_s
        const QWitherdenVincentSimplex<2> rule(std::max(2u, degree));
        for (auto &g : gradient_products)
          g.reinit(n_monomials, n_monomials);
        for (unsigned int q = 0; q < rule.size(); ++q)
          {
            const auto grad = gradients(rule.point(q));
            for (unsigned int a = 0; a < 2; ++a)
              for (unsigned int r = 0; r < n_monomials; ++r)
                for (unsigned int b = 0; b < 2; ++b)
                  for (unsigned int t = 0; t < n_monomials; ++t)
                    gradient_products[2 * a + b](r, t) +=
                      grad[r][a] * grad[t][b] * rule.weight(q);
          }
        // E^e_rm = int_0^1 m_r(edge e at s) psi_m(s) ds, psi = (1 - s, s);
        // edge e runs from reference vertex e to vertex e + 1 (mod 3)
        const std::array<Point<2>, 3> corner = {
          {Point<2>(0, 0), Point<2>(1, 0), Point<2>(0, 1)}};
        const QGauss<1> edge_rule(degree + 1);
        for (unsigned int e = 0; e < 3; ++e)
          {
            edge_moments[e].reinit(n_monomials, 2);
            for (unsigned int q = 0; q < edge_rule.size(); ++q)
              {
                const double   s = edge_rule.point(q)[0];
                const Point<2> xi =
                  corner[e] + s * (corner[(e + 1) % 3] - corner[e]);
                const auto value = values(xi);
                for (unsigned int r = 0; r < n_monomials; ++r)
                  {
                    edge_moments[e](r, 0) +=
                      value[r] * (1. - s) * edge_rule.weight(q);
                    edge_moments[e](r, 1) += value[r] * s * edge_rule.weight(q);
                  }
              }
          }
        for (unsigned int q = 0; q < body_quadrature.size(); ++q)
          {
            body_values.push_back(values(body_quadrature.point(q)));
            body_weights.push_back(body_quadrature.weight(q));
          }
      }

      unsigned int
      size() const
      {
        return functions.size();
      }

      /// m_r at a reference point
      std::vector<double>
      values(const Point<2> &xi) const
      {
        std::vector<double> result(n_monomials);
        for (unsigned int r = 0; r < n_monomials; ++r)
          result[r] =
            std::pow(xi[0], exponents[r][0]) * std::pow(xi[1], exponents[r][1]);
        return result;
      }

      /// reference gradients of m_r
      std::vector<Tensor<1, 2>>
      gradients(const Point<2> &xi) const
      {
        std::vector<Tensor<1, 2>> result(n_monomials);
        for (unsigned int r = 0; r < n_monomials; ++r)
          {
            const auto [p, q] = exponents[r];
            result[r][0] =
              p > 0 ? p * std::pow(xi[0], p - 1) * std::pow(xi[1], q) : 0.;
            result[r][1] =
              q > 0 ? q * std::pow(xi[0], p) * std::pow(xi[1], q - 1) : 0.;
          }
        return result;
      }

      /// The coefficients of the scalar parts in the monomials on an element
      /// (l_i = sum_a J_ia xi_a / h): T_jr, the identity but for rows 0 and
      /// 1 (stiffness() relies on this pattern).
      FullMatrix<double>
      scalar_coefficients(const Tensor<2, 2> &J, const double h) const
      {
        FullMatrix<double> T(n_scalars, n_monomials);
        for (unsigned int i = 0; i < 2; ++i)
          for (unsigned int a = 0; a < 2; ++a)
            T(i, a) = J[i][a] / h;
        for (unsigned int j = 2; j < n_scalars; ++j)
          T(j, j) = 1.;
        return T;
      }

      /**
       * The local stiffness matrix int_E eps(phi_g) : C : eps(phi_f) from
       * the physical gradient products H^de_jk = int_E d_d s_j d_e s_k and
       * the constant elasticity matrix D (Voigt, engineering shear).
       */
      FullMatrix<double>
      stiffness(const FullMatrix<double> &T,
                const Tensor<2, 2>       &J_inverse,
                const double              det,
                const FullMatrix<double> &D) const
      {
        std::array<FullMatrix<double>, 4> H;
        FullMatrix<double>                monomial(n_monomials, n_monomials);
        for (unsigned int d = 0; d < 2; ++d)
          for (unsigned int e = 0; e < 2; ++e)
            {
              monomial = 0.;
              for (unsigned int a = 0; a < 2; ++a)
                for (unsigned int b = 0; b < 2; ++b)
                  monomial.add(det * J_inverse[a][d] * J_inverse[b][e],
                               gradient_products[2 * a + b]);
              // H = T M T^T, with T the identity but for rows 0 and 1
              FullMatrix<double> &h = H[2 * d + e];
              h.reinit(n_scalars, n_scalars);
              const auto range = [](const unsigned int j) {
                return j < 2 ? std::make_pair(0u, 2u) :
                               std::make_pair(j, j + 1);
              };
              for (unsigned int j = 0; j < n_scalars; ++j)
                for (unsigned int k = 0; k < n_scalars; ++k)
                  for (unsigned int r = range(j).first; r < range(j).second;
                       ++r)
                    for (unsigned int t = range(k).first; t < range(k).second;
                         ++t)
                      h(j, k) += T(j, r) * T(k, t) * monomial(r, t);
            }
        // A^cc'_de = (B_c^T D B_c')_de, eps_voigt(s e_c) = B_c grad s
        static constexpr double B[2][3][2]    = {{{1, 0}, {0, 0}, {0, 1}},
                                                 {{0, 0}, {0, 1}, {1, 0}}};
        double                  A[2][2][2][2] = {};
        for (unsigned int c = 0; c < 2; ++c)
          for (unsigned int c2 = 0; c2 < 2; ++c2)
            for (unsigned int d = 0; d < 2; ++d)
              for (unsigned int e = 0; e < 2; ++e)
                for (unsigned int I = 0; I < 3; ++I)
                  for (unsigned int K = 0; K < 3; ++K)
                    A[c][c2][d][e] += B[c][I][d] * D(I, K) * B[c2][K][e];

        const unsigned int n = size();
        FullMatrix<double> K(n, n);
        for (unsigned int f = 0; f < n; ++f)
          for (unsigned int g = f; g < n; ++g)
            {
              double value = 0.;
              for (const auto &[j, c, alpha] : functions[f])
                for (const auto &[k, c2, beta] : functions[g])
                  for (unsigned int d = 0; d < 2; ++d)
                    for (unsigned int e = 0; e < 2; ++e)
                      value +=
                        alpha * beta * A[c][c2][d][e] * H[2 * d + e](j, k);
              K(f, g) = K(g, f) = value;
            }
        return K;
      }

      /// int_edge F . phi_f for F linear with values F_start, F_end at the
      /// ends of reference edge e (of physical length @p length)
      void
      add_edge_load(const FullMatrix<double>          &T,
                    const unsigned int                 e,
                    const double                       length,
                    const std::array<Tensor<1, 2>, 2> &F,
                    Vector<double>                    &load) const
      {
        // per scalar part and component: length sum_m F_m[c] (T E^e)_jm
        std::vector<std::array<double, 2>> scalar_load(n_scalars);
        for (unsigned int j = 0; j < n_scalars; ++j)
          for (unsigned int m = 0; m < 2; ++m)
            {
              double moment = 0.;
              for (unsigned int r = 0; r < n_monomials; ++r)
                moment += T(j, r) * edge_moments[e](r, m);
              for (unsigned int c = 0; c < 2; ++c)
                scalar_load[j][c] += length * F[m][c] * moment;
            }
        for (unsigned int f = 0; f < size(); ++f)
          for (const auto &[j, c, alpha] : functions[f])
            load[f] += alpha * scalar_load[j][c];
      }

      /// sum_q w_q f(x_q) . phi_f(x_q) |det| for a reference quadrature
      void
      add_body_load(const FullMatrix<double>          &T,
                    const std::vector<Vector<double>> &force,
                    const double                       det,
                    Vector<double>                    &load) const
      {
        for (unsigned int q = 0; q < body_weights.size(); ++q)
          {
            const std::vector<double> &m = body_values[q];
            std::vector<double>        s(n_scalars, 0.);
            for (unsigned int j = 0; j < n_scalars; ++j)
              for (unsigned int r = 0; r < n_monomials; ++r)
                s[j] += T(j, r) * m[r];
            const double JxW = body_weights[q] * det;
            for (unsigned int f = 0; f < size(); ++f)
              for (const auto &[j, c, alpha] : functions[f])
                load[f] += alpha * s[j] * force[q][c] * JxW;
          }
      }

    private:
      std::vector<std::array<unsigned int, 2>> exponents;
      unsigned int                             n_monomials = 0;
      unsigned int                             n_scalars   = 0;
      struct Term
      {
        unsigned int scalar, component;
        double       coefficient;
      };
      std::vector<std::vector<Term>>    functions;
      std::array<FullMatrix<double>, 4> gradient_products;
      std::array<FullMatrix<double>, 3> edge_moments;
      // m_r at the points of the body-force rule, and its weights
      std::vector<std::vector<double>> body_values;
      std::vector<double>              body_weights;
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
  void
  ElementEquilibration<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Local degree",
                      "3",
                      Patterns::Integer(2, 6),
                      "Polynomial degree p + k of the element problems "
                      "(p = 1; the paper's k = 2 or 3).");
    prm.declare_entry("Traction densities",
                      "least squares",
                      Patterns::Selection("least squares|minimised"),
                      "Choice of the free parameters of the equilibrated "
                      "traction densities: 'least squares' towards the "
                      "averaged FE tractions (classical EET) or 'minimised' "
                      "error measure (one extra sparse global solve).");
  }



  template <int dim>
  ElementEquilibration<dim>::ElementEquilibration(ParameterHandler &prm)
    : local_degree(prm.get_integer("Local degree"))
    , optimise_densities(prm.get("Traction densities") == "minimised")
  {}



  template <int dim>
  std::string
  ElementEquilibration<dim>::name() const
  {
    return "element equilibration";
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

    const unsigned int n_cells      = triangulation.n_active_cells();
    const MPI_Comm     communicator = triangulation.get_communicator();
    if (optimise_densities && Utilities::MPI::n_mpi_processes(communicator) > 1)
      throw InputError("Error estimator/Element equilibration/Traction "
                       "densities = minimised runs "
                       "on one MPI rank only (its free parameters form one "
                       "global system); use least squares");

    // Under MPI every rank holds the whole mesh and treats the cells it
    // owns; their local problems need the densities at their vertices, so
    // the patches of these vertices, so the cells around them ("needed").
    std::vector<bool>       vertex_of_owned_cell;
    const std::vector<bool> needed =
      cells_around_owned_cells(triangulation, vertex_of_owned_cell);

    error_squared.reinit(n_cells);
    sum_squared.reinit(n_cells);
    this->max_equilibrium_defect  = 0.;
    this->max_prolongation_defect = 0.;

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

    std::vector<FaceData> faces(triangulation.n_raw_faces());
    const Tensor<1, dim>  nu_c = input.contact_boundary.direction();

    // the cell quantities, cells in parallel (each writes its own entries)
    struct CellScratch
    {
      FEValues<dim>                        fe_values;
      std::vector<SymmetricTensor<2, dim>> strain_values;
      std::vector<Vector<double>>          force;
      CellScratch(const FEValues<dim> &prototype)
        : fe_values(prototype.get_mapping(),
                    prototype.get_fe(),
                    prototype.get_quadrature(),
                    prototype.get_update_flags())
        , strain_values(prototype.n_quadrature_points)
        , force(prototype.n_quadrature_points, Vector<double>(dim))
      {}
      CellScratch(const CellScratch &other)
        : CellScratch(other.fe_values)
      {}
    };
    std::atomic<bool> body_force_present{false};
    for_each_cell(
      dof_handler,
      [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
          CellScratch                                          &scratch) {
        const unsigned int E = cell->active_cell_index();
        if (!needed[E])
          return;
        FEValues<dim> &fe_values     = scratch.fe_values;
        auto          &strain_values = scratch.strain_values;
        auto          &force         = scratch.force;
        fe_values.reinit(cell);
        fe_values[displacement].get_function_symmetric_gradients(
          input.equilibrated_displacement, strain_values);
        sigma_h[E] = material.stress(strain_values[0]);
        fe_values[displacement].get_function_symmetric_gradients(
          admissible_displacement, strain_values);
        strain_hat[E] = strain_values[0];
        bc.body_force->vector_value_list(fe_values.get_quadrature_points(),
                                         force);
        for (const auto &value : force)
          if (value.l2_norm() != 0.)
            body_force_present = true;
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
          cell_faces[E][f] = cell->face(f)->index();
      },
      CellScratch(fe_values));

    // the faces, in cell order (which cell is "first" must not depend on
    // the thread schedule)
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const unsigned int E = cell->active_cell_index();
        if (!needed[E])
          continue;
        for (const unsigned int f : cell->face_indices())
          {
            const auto face = cell->face(f);
            FaceData  &data = faces[face->index()];
            if (data.first_cell != numbers::invalid_unsigned_int)
              {
                data.second_cell = E;
                continue;
              }
            data.first_cell = E;
            data.vertices   = {{face->vertex_index(0), face->vertex_index(1)}};
            data.length     = face->measure();
            // unit normal of the straight edge, pointing out of the cell
            const Tensor<1, dim> tangent = face->vertex(1) - face->vertex(0);
            data.normal[0]               = tangent[1] / data.length;
            data.normal[1]               = -tangent[0] / data.length;
            if (data.normal * (face->center() - cell->center()) < 0.)
              data.normal *= -1.;
            if (!face->at_boundary())
              continue;

            // boundary face: known traction projections unless Dirichlet
            data.kind              = FaceKind::loaded;
            data.unknown_component = {{false, false}};
            const auto id          = face->boundary_id();
            // all the parts naming the id: the union of their Dirichlet
            // components, the sum of their tractions
            const ComponentMask fixed = bc.dirichlet_mask(id);
            for (unsigned int c = 0; c < dim; ++c)
              if (fixed[c])
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
            if (bc.has_traction(id))
              {
                fe_face_values.reinit(cell, f);
                std::vector<Vector<double>> traction;
                bc.traction_values(id,
                                   fe_face_values.get_quadrature_points(),
                                   traction);
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
      if (needed[E])
        for (unsigned int v = 0; v < 3; ++v)
          cells_of_vertex[cell_vertices[E][v]].push_back(E);

    // Each vertex writes only the projections b_G(i) at its own end of its
    // edges, so the patches are independent (run in parallel below).
    std::mutex patch_mutex;
    const auto process_patch = [&](const unsigned int vertex) {
      const auto &patch = cells_of_vertex[vertex];
      if (patch.empty() || !vertex_of_owned_cell[vertex])
        return;
      double                     patch_defect = 0.;
      std::vector<FreeDirection> patch_directions;
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
                  const auto it = std::find(unknown.begin(), unknown.end(), p);
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
              // lambda = (A A^T)^+ defect. Every column of A has one
              // entry (a Dirichlet edge) or two of opposite signs (an
              // edge shared by two cells of the patch); in the latter
              // case A A^T has the kernel span{1} exactly, which adding
              // 1 1^T removes without changing the solution orthogonal to
              // it (the patch is connected, so there is no other kernel).
              bool all_shared = true;
              for (unsigned int u = 0; u < n_un; ++u)
                {
                  unsigned int entries = 0;
                  for (unsigned int i = 0; i < n_eq; ++i)
                    entries += (A(i, u) != 0.) ? 1 : 0;
                  all_shared &= (entries == 2);
                }
              FullMatrix<double> AAt(n_eq, n_eq);
              for (unsigned int i = 0; i < n_eq; ++i)
                for (unsigned int j = 0; j < n_eq; ++j)
                  {
                    for (unsigned int u = 0; u < n_un; ++u)
                      AAt(i, j) += A(i, u) * A(j, u);
                    if (all_shared)
                      AAt(i, j) += 1.;
                  }
              AAt.gauss_jordan();
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
                  patch_directions.push_back(direction);
                }
            }
          // prolongation condition residual of this patch
          Vector<double> check(n_eq);
          if (n_un > 0)
            A.vmult(check, b);
          check -= rhs;
          patch_defect = std::max(patch_defect, check.linfty_norm());
        }
      std::lock_guard<std::mutex> lock(patch_mutex);
      this->max_prolongation_defect =
        std::max(this->max_prolongation_defect, patch_defect);
      free_directions.insert(free_directions.end(),
                             patch_directions.begin(),
                             patch_directions.end());
    };
    // (serial with the optimised densities, whose free directions must come
    // in a fixed order)
    if (optimise_densities)
      for (unsigned int vertex = 0; vertex < cells_of_vertex.size(); ++vertex)
        process_patch(vertex);
    else
      parallel::apply_to_subranges(
        0u,
        static_cast<unsigned int>(cells_of_vertex.size()),
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int vertex = begin; vertex < end; ++vertex)
            process_patch(vertex);
        },
        256);


    double q_scale = 0.;
    for (const auto &q_cell : Q)
      for (const auto &q_vertex : q_cell)
        q_scale = std::max(q_scale, q_vertex.norm());
    q_scale = Utilities::MPI::max(q_scale, communicator);
    this->max_prolongation_defect =
      Utilities::MPI::max(this->max_prolongation_defect, communicator);
    if (q_scale > 0.)
      this->max_prolongation_defect /= q_scale;

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
    const LocalSpace   space(local_degree, quadrature);
    const unsigned int n = space.size();
    std::mutex         defect_mutex;

    // the elasticity matrix (Voigt, engineering shear): energy = e^T D e
    FullMatrix<double> D(3, 3);
    {
      std::array<SymmetricTensor<2, 2>, 3> unit;
      unit[0][0][0] = 1.;
      unit[1][1][1] = 1.;
      unit[2][0][1] = 0.5; // gamma_xy = 1
      for (unsigned int I = 0; I < 3; ++I)
        for (unsigned int K = 0; K < 3; ++K)
          D(I, K) = material.stress(unit[K]) * unit[I];
    }

    struct Geometry
    {
      Point<2>                    x0, center;
      Tensor<2, 2>                J, J_inverse;
      double                      det, h;
      std::array<unsigned int, 3> vertices;
      FullMatrix<double>          T; // scalar parts in the monomials
    };
    const auto geometry = [&](const auto &cell) {
      Geometry g;
      g.x0 = cell->vertex(0);
      for (unsigned int d = 0; d < 2; ++d)
        {
          g.J[d][0] = cell->vertex(1)[d] - g.x0[d];
          g.J[d][1] = cell->vertex(2)[d] - g.x0[d];
        }
      g.J_inverse = invert(g.J);
      g.det       = std::abs(determinant(g.J));
      g.center    = cell->center();
      g.h         = 0.;
      for (const unsigned int f : cell->face_indices())
        g.h =
          std::max(g.h, faces[cell_faces[cell->active_cell_index()][f]].length);
      for (unsigned int v = 0; v < 3; ++v)
        g.vertices[v] = cell->vertex_index(v);
      g.T = space.scalar_coefficients(g.J, g.h);
      return g;
    };

    const auto local_stiffness = [&](const Geometry &g) {
      return space.stiffness(g.T, g.J_inverse, g.det, D);
    };
    const auto factorised = [&](const FullMatrix<double> &stiffness) {
      LAPACKFullMatrix<double> factor(n, n);
      factor = stiffness;
      factor.set_property(LAPACKSupport::symmetric);
      factor.compute_cholesky_factorization();
      return factor;
    };

    // load of a linear density (nodal values at data.vertices) on the face
    // of cell E, and its contribution to the resultant and moment about
    // the centre (two-point Gauss: exact for the linear integrands)
    const auto add_edge_load = [&](const unsigned int                 E,
                                   const Geometry                    &g,
                                   const FaceData                    &data,
                                   const std::array<Tensor<1, 2>, 2> &density,
                                   Vector<double>                    &load,
                                   Tensor<1, 2>                      *resultant,
                                   double                            *moment) {
      const double sign = (data.first_cell == E) ? 1. : -1.;
      // the reference edge e joins cell vertices e and e + 1
      unsigned int e        = 0;
      bool         reversed = false;
      for (; e < 3; ++e)
        {
          const unsigned int a = g.vertices[e], b = g.vertices[(e + 1) % 3];
          if (a == data.vertices[0] && b == data.vertices[1])
            break;
          if (b == data.vertices[0] && a == data.vertices[1])
            {
              reversed = true;
              break;
            }
        }
      Assert(e < 3, ExcInternalError());
      std::array<Tensor<1, 2>, 2> F = {{sign * density[0], sign * density[1]}};
      if (reversed)
        std::swap(F[0], F[1]);
      space.add_edge_load(g.T, e, data.length, F, load);
      if (resultant != nullptr)
        {
          const Point<2> a = triangulation.get_vertices()[data.vertices[0]];
          const Point<2> b = triangulation.get_vertices()[data.vertices[1]];
          for (const double s :
               {0.5 - 0.5 / std::sqrt(3.), 0.5 + 0.5 / std::sqrt(3.)})
            {
              const Tensor<1, 2> value =
                sign * ((1. - s) * density[0] + s * density[1]);
              const double JxW = 0.5 * data.length;
              *resultant += value * JxW;
              *moment +=
                cross_product_2d(a + s * (b - a) - g.center) * value * JxW;
            }
        }
    };

    // full load of a cell (body force with the rule of the assembly, so
    // that the element data are in equilibrium to round-off), and checks
    // (the body force is zero in most cases: skip its evaluation then)
    const bool has_body_force = body_force_present;
    const auto local_load     = [&](const auto &cell, const Geometry &g) {
      const unsigned int E = cell->active_cell_index();
      Vector<double>     load(n);
      Tensor<1, 2>       resultant;
      double             moment = 0., data_scale = 0.;
      if (has_body_force)
        {
          std::vector<Point<2>>       points(quadrature.size());
          std::vector<Vector<double>> f_values(quadrature.size(),
                                               Vector<double>(2));
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            points[q] = g.x0 + g.J * quadrature.point(q);
          bc.body_force->vector_value_list(points, f_values);
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              const double       JxW = quadrature.weight(q) * g.det;
              const Tensor<1, 2> f({f_values[q][0], f_values[q][1]});
              resultant += f * JxW;
              moment += cross_product_2d(points[q] - g.center) * f * JxW;
              data_scale += f.norm() * JxW;
            }
          space.add_body_load(g.T, f_values, g.det, load);
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
        this->max_equilibrium_defect =
          std::max({this->max_equilibrium_defect,
                    resultant.norm() / data_scale,
                    std::abs(moment) / (data_scale * g.h)});
      return load;
    };

    // coefficients of U^ (its strain) in the local space: l_0 e_x, l_1 e_y,
    // l_1 e_x + l_0 e_y carry h eps_xx, h eps_yy, h eps_xy
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
            const Geometry           geo = geometry(cell);
            LAPACKFullMatrix<double> stiffness =
              factorised(local_stiffness(geo));
            Vector<double> w = local_load(cell, geo);
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
    const auto element_error =
      [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
          NoScratch &) {
        if (!cell->is_locally_owned())
          return;
        const unsigned int E = cell->active_cell_index();
        const Geometry     g = geometry(cell);
        // ||sigma^ -/+ K eps(U^)||^2 = (v -/+ u^)^T K_E (v -/+ u^)
        const FullMatrix<double> stiffness = local_stiffness(g);
        Vector<double>           v         = local_load(cell, g);
        factorised(stiffness).solve(v);
        const Vector<double> u_hat = admissible_coefficients(E, g);
        Vector<double>       minus(v), plus(v);
        minus -= u_hat;
        plus += u_hat;
        error_squared[E] = stiffness.matrix_norm_square(minus);
        sum_squared[E]   = stiffness.matrix_norm_square(plus);
      };
    for_each_cell(dof_handler, element_error, NoScratch());
    this->max_equilibrium_defect =
      Utilities::MPI::max(this->max_equilibrium_defect, communicator);
  }

  template class ElementEquilibration<2>;
} // namespace Signorini
