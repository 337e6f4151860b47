#include <deal.II/base/aligned_vector.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <signorini/estimator/density_enhancement.h>
#include <signorini/estimator/element_equilibration.h>
#include <signorini/estimator/johnson_mercier_element.h>
#include <signorini/estimator/local_loops.h>
#include <signorini/estimator/simplex_element_equilibration.h>
#include <signorini/estimator/small_matrices.h>
#include <signorini/estimator/vertex_patches.h>
#include <signorini/input_error.h>
#include <signorini/registry.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <mutex>
#include <tuple>
#include <utility>

namespace Signorini
{
  namespace
  {
    /// The default of Element equilibration/Local degree.
    constexpr const char *default_local_degree = "3";

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
        for (auto &products : gradient_products)
          products.reinit(n_monomials, n_monomials);
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

      /// The number of (vector) basis functions.
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
        FullMatrix<double> coefficients(n_scalars, n_monomials);
        for (unsigned int i = 0; i < 2; ++i)
          for (unsigned int a = 0; a < 2; ++a)
            coefficients(i, a) = J[i][a] / h;
        for (unsigned int j = 2; j < n_scalars; ++j)
          coefficients(j, j) = 1.;
        return coefficients;
      }

      /**
       * The local stiffness matrix int_E eps(phi_g) : C : eps(phi_f) from
       * the physical gradient products H^de_jk = int_E d_d s_j d_e s_k of
       * the scalar parts (@p coefficients: T of scalar_coefficients()) and
       * the constant elasticity matrix @p elasticity (Voigt, engineering
       * shear).
       */
      FullMatrix<double>
      stiffness(const FullMatrix<double> &coefficients,
                const Tensor<2, 2>       &J_inverse,
                const double              det,
                const FullMatrix<double> &elasticity) const
      {
        std::array<FullMatrix<double>, 4> scalar_products; // H^de
        FullMatrix<double> monomial_products(n_monomials, n_monomials);
        for (unsigned int d = 0; d < 2; ++d)
          for (unsigned int e = 0; e < 2; ++e)
            {
              monomial_products = 0.;
              for (unsigned int a = 0; a < 2; ++a)
                for (unsigned int b = 0; b < 2; ++b)
                  monomial_products.add(det * J_inverse[a][d] * J_inverse[b][e],
                                        gradient_products[2 * a + b]);
              // H = T M T^T, with T the identity but for rows 0 and 1
              FullMatrix<double> &products = scalar_products[2 * d + e];
              products.reinit(n_scalars, n_scalars);
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
                      products(j, k) += coefficients(j, r) *
                                        coefficients(k, t) *
                                        monomial_products(r, t);
            }
        // coupling^cc'_de = (B_c^T D B_c')_de, eps_voigt(s e_c) = B_c grad s
        static constexpr double strain_of_gradient[2][3][2] = {
          {{1, 0}, {0, 0}, {0, 1}}, {{0, 0}, {0, 1}, {1, 0}}};
        double coupling[2][2][2][2] = {};
        for (unsigned int c = 0; c < 2; ++c)
          for (unsigned int c2 = 0; c2 < 2; ++c2)
            for (unsigned int d = 0; d < 2; ++d)
              for (unsigned int e = 0; e < 2; ++e)
                for (unsigned int I = 0; I < 3; ++I)
                  for (unsigned int K = 0; K < 3; ++K)
                    coupling[c][c2][d][e] += strain_of_gradient[c][I][d] *
                                             elasticity(I, K) *
                                             strain_of_gradient[c2][K][e];

        const unsigned int n = size();
        FullMatrix<double> matrix(n, n);
        for (unsigned int f = 0; f < n; ++f)
          for (unsigned int g = f; g < n; ++g)
            {
              double value = 0.;
              for (const auto &[j, c, alpha] : functions[f])
                for (const auto &[k, c2, beta] : functions[g])
                  for (unsigned int d = 0; d < 2; ++d)
                    for (unsigned int e = 0; e < 2; ++e)
                      value += alpha * beta * coupling[c][c2][d][e] *
                               scalar_products[2 * d + e](j, k);
              matrix(f, g) = matrix(g, f) = value;
            }
        return matrix;
      }

      /// int_edge F . phi_f for F linear with values @p density (at the start
      /// and end of reference edge @p e, of physical length @p length)
      void
      add_edge_load(const FullMatrix<double>          &coefficients,
                    const unsigned int                 e,
                    const double                       length,
                    const std::array<Tensor<1, 2>, 2> &density,
                    Vector<double>                    &load) const
      {
        // per scalar part and component: length sum_m F_m[c] (T E^e)_jm
        std::vector<std::array<double, 2>> scalar_load(n_scalars);
        for (unsigned int j = 0; j < n_scalars; ++j)
          for (unsigned int m = 0; m < 2; ++m)
            {
              double moment = 0.;
              for (unsigned int r = 0; r < n_monomials; ++r)
                moment += coefficients(j, r) * edge_moments[e](r, m);
              for (unsigned int c = 0; c < 2; ++c)
                scalar_load[j][c] += length * density[m][c] * moment;
            }
        for (unsigned int f = 0; f < size(); ++f)
          for (const auto &[j, c, alpha] : functions[f])
            load[f] += alpha * scalar_load[j][c];
      }

      /// sum_q w_q f(x_q) . phi_f(x_q) |det| for the body-force rule
      void
      add_body_load(const FullMatrix<double>          &coefficients,
                    const std::vector<Vector<double>> &force,
                    const double                       det,
                    Vector<double>                    &load) const
      {
        for (unsigned int q = 0; q < body_weights.size(); ++q)
          {
            const std::vector<double> &monomials = body_values[q];
            std::vector<double>        scalars(n_scalars, 0.);
            for (unsigned int j = 0; j < n_scalars; ++j)
              for (unsigned int r = 0; r < n_monomials; ++r)
                scalars[j] += coefficients(j, r) * monomials[r];
            const double JxW = body_weights[q] * det;
            for (unsigned int f = 0; f < size(); ++f)
              for (const auto &[j, c, alpha] : functions[f])
                load[f] += alpha * scalars[j] * force[q][c] * JxW;
          }
      }

    private:
      /// Exponents (of xi, eta) of the reference monomials m_r.
      std::vector<std::array<unsigned int, 2>> exponents;
      /// Their number.
      unsigned int n_monomials = 0;
      /// The number of scalar parts s_j (l_0, l_1, the monomials of degree
      /// >= 2).
      unsigned int n_scalars = 0;
      /// One term alpha s_j e_c of a basis function.
      struct Term
      {
        /// j
        unsigned int scalar;
        /// c
        unsigned int component;
        /// alpha
        double coefficient;
      };
      /// The basis functions, as sums of terms.
      std::vector<std::vector<Term>> functions;
      /// G^ab = int_T d_a m_r d_b m_s, at 2 a + b.
      std::array<FullMatrix<double>, 4> gradient_products;
      /// E^e_rm = int_0^1 m_r(edge e at s) psi_m(s) ds.
      std::array<FullMatrix<double>, 3> edge_moments;
      /// m_r at the points of the body-force rule.
      std::vector<std::vector<double>> body_values;
      /// The weights of the body-force rule.
      std::vector<double> body_weights;
    };



    /// The elasticity matrix (Voigt, engineering shear): energy = e^T D e.
    FullMatrix<double>
    elasticity_matrix(const LinearElasticMaterial<2> &material)
    {
      FullMatrix<double>                   elasticity(3, 3);
      std::array<SymmetricTensor<2, 2>, 3> unit;
      unit[0][0][0] = 1.;
      unit[1][1][1] = 1.;
      unit[2][0][1] = 0.5; // gamma_xy = 1
      for (unsigned int I = 0; I < 3; ++I)
        for (unsigned int K = 0; K < 3; ++K)
          elasticity(I, K) = material.stress(unit[K]) * unit[I];
      return elasticity;
    }



    /// What the patch systems and the element problems need of every needed
    /// cell (by active cell index). (These arrays and those of the edges are
    /// AlignedVectors, whose initialisation runs in parallel, as for the
    /// enhancement's arrays; for these no gain above the noise was measured.)
    struct CellQuantities
    {
      /// sigma_h, the (constant) stress of the equilibrated FE displacement.
      AlignedVector<SymmetricTensor<2, 2>> fe_stress;
      /// eps(U^), constant per cell.
      AlignedVector<SymmetricTensor<2, 2>> admissible_strain;
      /// Q_E(i)[c] = int_E sigma_h : eps(phi_i e_c) - f_d . phi_i e_c for
      /// the cell's vertices i: what the prolongation condition asks of the
      /// densities of E on phi_i e_c.
      AlignedVector<std::array<Tensor<1, 2>, 3>> prolongation_load;
      /// The body force f~ that the Johnson-Mercier field balances: constant
      /// on each sub-triangle of the centroid split, f~_e = mean + kappa
      /// (g_e - g)^perp, with the resultant and the moment about the
      /// centroid g that f_d has with the assembly's quadrature, which the
      /// densities balance (so that the element data are in equilibrium to
      /// round-off; f~ = f_d where f_d is constant on the element).
      AlignedVector<JohnsonMercierElement::BodyForce> split_body_force;
      /// Whether f_d is non-zero somewhere (mostly not: its evaluation is
      /// skipped then).
      bool body_force_present = false;
    };



    /// The body force f~ of CellQuantities::split_body_force on @p cell
    /// from the values @p force of f_d at the quadrature points @p points
    /// with weights @p JxW.
    JohnsonMercierElement::BodyForce
    split_body_force(const DoFHandler<2>::active_cell_iterator &cell,
                     const std::vector<Point<2>>               &points,
                     const std::vector<double>                 &JxW,
                     const std::vector<Vector<double>>         &force)
    {
      const Point<2> center = cell->center();
      Tensor<1, 2>   resultant;
      double         moment = 0.;
      double         area   = 0.;
      for (unsigned int q = 0; q < points.size(); ++q)
        {
          const Tensor<1, 2> arm = points[q] - center;
          resultant[0] += force[q][0] * JxW[q];
          resultant[1] += force[q][1] * JxW[q];
          moment += (arm[0] * force[q][1] - arm[1] * force[q][0]) * JxW[q];
          area += JxW[q];
        }
      // f~_e = resultant / |E| + kappa (g_e - g)^perp: the arms g_e - g sum
      // to zero (no resultant), and (g_e - g) x (g_e - g)^perp = |g_e - g|^2
      std::array<Tensor<1, 2>, 3> arms;
      double                      arm_square_sum = 0.;
      for (unsigned int e = 0; e < 3; ++e)
        {
          arms[e] =
            (cell->vertex(e) + cell->vertex((e + 1) % 3) - 2. * center) / 3.;
          arm_square_sum += arms[e].norm_square();
        }
      // (divided in this order: |E| |g_e - g|^2 underflows on meshes of
      // 1e-90 units)
      const double kappa =
        moment == 0. ? 0. : (moment / area) / (arm_square_sum / 3.);
      JohnsonMercierElement::BodyForce split;
      for (unsigned int e = 0; e < 3; ++e)
        {
          split[e] = resultant / area;
          split[e][0] -= kappa * arms[e][1];
          split[e][1] += kappa * arms[e][0];
        }
      return split;
    }



    /// sigma_h, eps(U^) and the prolongation loads of the needed cells, in
    /// parallel (each cell writes its own entries), with the @p quadrature
    /// of the assembly so that the prolongation condition holds to round-off.
    /// The P1 gradients and the quadrature points come from the affine map
    /// of each triangle (AffineTriangle), the map of the assembly's mapping
    /// for straight P1 triangles: FEValues were about half of this loop's
    /// samples at 1.6M DoFs (perf).
    CellQuantities
    compute_cell_quantities(const EquilibrationInput<2> &input,
                            const LA::Vector    &admissible_displacement,
                            const VertexPatches &patches,
                            const Quadrature<2> &quadrature)
    {
      const DoFHandler<2> &dof_handler = input.dof_handler;
      const auto          &fe          = dof_handler.get_fe();
      const auto          &bc          = input.boundary_conditions;
      const unsigned int   n_cells =
        dof_handler.get_triangulation().n_active_cells();
      CellQuantities cells;
      cells.fe_stress.resize(n_cells);
      cells.admissible_strain.resize(n_cells);
      cells.prolongation_load.resize(n_cells);
      cells.split_body_force.resize(n_cells);
      // (each rank holds the whole mesh: reading a distributed vector entry
      // by entry cost more than these copies)
      const Vector<double> equilibrated =
        replicate(input.equilibrated_displacement);
      const Vector<double> admissible = replicate(admissible_displacement);

      // the barycentric coordinates lambda_v at the quadrature points
      const unsigned int                 n_points = quadrature.size();
      std::vector<std::array<double, 3>> lambda(n_points);
      for (unsigned int q = 0; q < n_points; ++q)
        {
          const Point<2> &xi = quadrature.point(q);
          lambda[q]          = {{1. - xi[0] - xi[1], xi[0], xi[1]}};
        }
      struct CellScratch
      {
        std::vector<types::global_dof_index> dof_indices;
        std::vector<Point<2>>                points;
        std::vector<double>                  JxW;
        std::vector<Vector<double>>          force;
        explicit CellScratch(const unsigned int n_points)
          : dof_indices(6)
          , points(n_points)
          , JxW(n_points)
          , force(n_points, Vector<double>(2))
        {}
      };
      std::atomic<bool> body_force_present{false};
      for_each_cell(
        dof_handler,
        [&](const DoFHandler<2>::active_cell_iterator &cell,
            CellScratch                               &scratch) {
          const unsigned int index = cell->active_cell_index();
          if (!patches.needed(index))
            return;
          const AffineTriangle map(cell);
          // the gradients of lambda_0, lambda_1, lambda_2
          std::array<Tensor<1, 2>, 3> gradient;
          for (unsigned int d = 0; d < 2; ++d)
            {
              gradient[1][d] = map.inverse_jacobian[0][d];
              gradient[2][d] = map.inverse_jacobian[1][d];
              gradient[0][d] = -gradient[1][d] - gradient[2][d];
            }
          cell->get_dof_indices(scratch.dof_indices);
          const auto strain = [&](const Vector<double> &u) {
            Tensor<2, 2> grad_u;
            for (unsigned int v = 0; v < 3; ++v)
              for (unsigned int c = 0; c < 2; ++c)
                grad_u[c] +=
                  u[scratch.dof_indices[fe.component_to_system_index(c, v)]] *
                  gradient[v];
            return symmetrize(grad_u);
          };
          const SymmetricTensor<2, 2> sigma_h =
            input.material.stress(strain(equilibrated));
          cells.fe_stress[index]         = sigma_h;
          cells.admissible_strain[index] = strain(admissible);

          for (unsigned int q = 0; q < n_points; ++q)
            {
              scratch.points[q] =
                map.origin + map.jacobian * quadrature.point(q);
              scratch.JxW[q] = quadrature.weight(q) * map.determinant;
            }
          auto &force = scratch.force;
          if (!bc.body_force_zero)
            {
              bc.body_force->vector_value_list(scratch.points, force);
              for (const auto &value : force)
                if (value.l2_norm() != 0.)
                  body_force_present = true;
            }
          cells.split_body_force[index] =
            split_body_force(cell, scratch.points, scratch.JxW, force);
          double area = 0.;
          for (const double w : scratch.JxW)
            area += w;
          for (unsigned int v = 0; v < 3; ++v)
            {
              const Tensor<1, 2> traction = sigma_h * gradient[v];
              for (unsigned int c = 0; c < 2; ++c)
                {
                  double value = traction[c] * area;
                  for (unsigned int q = 0; q < n_points; ++q)
                    value -= force[q][c] * lambda[q][v] * scratch.JxW[q];
                  cells.prolongation_load[index][v][c] = value;
                }
            }
        },
        CellScratch(n_points));
      cells.body_force_present = body_force_present;
      return cells;
    }



    /// An edge of the mesh with its traction density F^ (the traction on its
    /// first cell, VertexPatches::cells_of_edge()).
    struct EdgeData
    {
      /// Global vertex numbers, in the face's order (that of the arrays
      /// below).
      std::array<unsigned int, 2> vertices;
      /// Length.
      double length = 0.;
      /// Unit normal, out of the first cell.
      Tensor<1, 2> normal;
      /// The components whose projections the patch systems determine: all
      /// on interior edges, the Dirichlet ones on the boundary (the others
      /// are given by F_d and R^).
      std::array<bool, 2> unknown_component = {{true, true}};
      /// b_G(i) = int_G F^ phi_i for the two vertices i.
      std::array<Tensor<1, 2>, 2> projection;
      /// Values of the linear F^ at the two vertices.
      std::array<Tensor<1, 2>, 2> density;
    };



    /// The edges of the needed cells: geometry, and on the boundary which
    /// projections are known and their values (F_d with the assembly's
    /// @p face_quadrature, R^ exactly).
    AlignedVector<EdgeData>
    describe_edges(const EquilibrationInput<2> &input,
                   const VertexPatches         &patches,
                   const Quadrature<1>         &face_quadrature)
    {
      const DoFHandler<2> &dof_handler = input.dof_handler;
      const auto          &fe          = dof_handler.get_fe();
      const auto          &bc          = input.boundary_conditions;
      const auto          &contact     = input.contact_boundary;
      struct FaceScratch
      {
        FEFaceValues<2> fe_face_values;
        FaceScratch(const Mapping<2>       &mapping,
                    const FiniteElement<2> &fe,
                    const Quadrature<1>    &quadrature)
          : fe_face_values(mapping,
                           fe,
                           quadrature,
                           update_values | update_quadrature_points |
                             update_JxW_values)
        {}
        FaceScratch(const FaceScratch &other)
          : FaceScratch(other.fe_face_values.get_mapping(),
                        other.fe_face_values.get_fe(),
                        other.fe_face_values.get_quadrature())
        {}
      };

      // (in parallel: each edge is written by the first of its cells only)
      AlignedVector<EdgeData> edges(
        dof_handler.get_triangulation().n_raw_faces());
      for_each_cell(
        dof_handler,
        [&](const DoFHandler<2>::active_cell_iterator &cell,
            FaceScratch                               &scratch) {
          const unsigned int index = cell->active_cell_index();
          if (!patches.needed(index))
            return;
          FEFaceValues<2> &fe_face_values = scratch.fe_face_values;
          for (const unsigned int f : cell->face_indices())
            {
              const auto face = cell->face(f);
              if (patches.cells_of_edge(face->index())[0] != index)
                continue;
              EdgeData &edge = edges[face->index()];
              edge.vertices  = {{face->vertex_index(0), face->vertex_index(1)}};
              edge.length    = face->measure();
              // unit normal of the straight edge, pointing out of the cell
              const Tensor<1, 2> tangent = face->vertex(1) - face->vertex(0);
              edge.normal[0]             = tangent[1] / edge.length;
              edge.normal[1]             = -tangent[0] / edge.length;
              if (edge.normal * (face->center() - cell->center()) < 0.)
                edge.normal *= -1.;
              if (!face->at_boundary())
                continue;

              // boundary edge: known traction projections unless Dirichlet;
              // all the parts naming the id give the union of their Dirichlet
              // components and the sum of their tractions
              edge.unknown_component    = {{false, false}};
              const auto          id    = face->boundary_id();
              const ComponentMask fixed = bc.dirichlet_mask(id);
              for (unsigned int c = 0; c < 2; ++c)
                if (fixed[c])
                  edge.unknown_component[c] = true;
              if (bc.has_traction(id))
                {
                  fe_face_values.reinit(cell, f);
                  std::vector<Vector<double>> traction;
                  bc.traction_values(id,
                                     fe_face_values.get_quadrature_points(),
                                     traction);
                  for (unsigned int k = 0; k < 2; ++k)
                    for (unsigned int c = 0; c < 2; ++c)
                      {
                        const unsigned int i = fe.component_to_system_index(
                          c, patches.local_vertex(index, edge.vertices[k]));
                        for (const unsigned int q :
                             fe_face_values.quadrature_point_indices())
                          edge.projection[k][c] +=
                            traction[q][c] *
                            fe_face_values.shape_value_component(i, q, c) *
                            fe_face_values.JxW(q);
                      }
                }
              if (contact.boundary_ids().count(id) != 0)
                {
                  // R^ = R^_n nu_c + R^_t, linear on the edge: int R^ psi_k
                  // exactly
                  const Tensor<1, 2> r0 = input.contact_reaction(
                    contact.node_index(edge.vertices[0]));
                  const Tensor<1, 2> r1 = input.contact_reaction(
                    contact.node_index(edge.vertices[1]));
                  edge.projection[0] += edge.length / 6. * (2. * r0 + r1);
                  edge.projection[1] += edge.length / 6. * (r0 + 2. * r1);
                }
            }
        },
        FaceScratch(input.mapping, fe, face_quadrature));
      return edges;
    }



    /// +1 on the first cell of an edge, -1 on the second: the sign of the
    /// edge's density F^ in the traction of @p cell.
    double
    orientation(const VertexPatches &patches,
                const unsigned int   edge,
                const unsigned int   cell)
    {
      return patches.cells_of_edge(edge)[0] == cell ? 1. : -1.;
    }



    /// A direction of the free parameters of one patch system: changing the
    /// projections by t times the entries keeps the prolongation condition
    /// for every t.
    struct FreeDirection
    {
      /// The vertex i of the patch.
      unsigned int vertex;
      /// The component of the projections it changes.
      unsigned int component;
      /// One projection b_G(i) it changes.
      struct Entry
      {
        /// G (face index).
        unsigned int edge;
        /// Which vertex of G is i (0 or 1).
        unsigned int end;
        /// The change for t = 1.
        double weight;
      };
      /// The projections it changes.
      std::vector<Entry> entries;
    };



    /**
     * The prolongation condition of the patch of a vertex i, for one
     * component, as a linear system for its unknown projections:
     *   sum_G eta_EG b_G(i) = Q_E(i) - (the same sum over the known b_G(i))
     * for every cell E of the patch, the sums over the edges G of E through
     * i, eta_EG = orientation().
     */
    struct PatchSystem
    {
      /// (edge, end) of each unknown projection b_G(i).
      std::vector<std::pair<unsigned int, unsigned int>> unknowns;
      /// eta_EG: a row per cell of the patch, a column per unknown (at least
      /// one column, so that the matrix is never empty).
      FullMatrix<double> signs;
      /// The right-hand sides.
      Vector<double> rhs;
    };



    /// The edges of the patch of @p vertex that end there, as (edge, end)
    /// with edges[edge].vertices[end] == vertex, into @p ends.
    void
    edge_ends_at_vertex(
      const unsigned int                                  vertex,
      const VertexPatches                                &patches,
      const AlignedVector<EdgeData>                      &edges,
      std::vector<std::pair<unsigned int, unsigned int>> &ends)
    {
      ends.clear();
      for (const unsigned int cell : patches.cells_of_vertex(vertex))
        for (const unsigned int edge : patches.edges(cell))
          for (unsigned int end = 0; end < 2; ++end)
            if (edges[edge].vertices[end] == vertex &&
                std::find(ends.begin(),
                          ends.end(),
                          std::make_pair(edge, end)) == ends.end())
              ends.emplace_back(edge, end);
    }



    /// The PatchSystem of @p vertex and @p component into @p system;
    /// @p edge_ends from edge_ends_at_vertex().
    void
    assemble_patch_system(
      const unsigned int                                        vertex,
      const unsigned int                                        component,
      const std::vector<std::pair<unsigned int, unsigned int>> &edge_ends,
      const VertexPatches                                      &patches,
      const CellQuantities                                     &cells,
      const AlignedVector<EdgeData>                            &edges,
      PatchSystem                                              &system)
    {
      const auto &patch = patches.cells_of_vertex(vertex);
      system.unknowns.clear();
      for (const auto &edge_end : edge_ends)
        if (edges[edge_end.first].unknown_component[component])
          system.unknowns.push_back(edge_end);
      const unsigned int n_unknowns = system.unknowns.size();
      system.signs.reinit(patch.size(), std::max(n_unknowns, 1u));
      system.rhs.reinit(patch.size());
      for (unsigned int row = 0; row < patch.size(); ++row)
        {
          const unsigned int cell = patch[row];
          system.rhs[row] =
            cells.prolongation_load[cell][patches.local_vertex(cell, vertex)]
                                   [component];
          unsigned int column = 0; // of the next unknown among edge_ends
          for (const auto &[edge, end] : edge_ends)
            {
              const bool  unknown    = edges[edge].unknown_component[component];
              const auto &edge_cells = patches.cells_of_edge(edge);
              if (edge_cells[0] == cell || edge_cells[1] == cell)
                {
                  const double eta = orientation(patches, edge, cell);
                  if (unknown)
                    system.signs(row, column) = eta;
                  else
                    system.rhs[row] -=
                      eta * edges[edge].projection[end][component];
                }
              if (unknown)
                ++column;
            }
        }
    }



    /// The projections of the averaged FE tractions (sigma_h n on the
    /// boundary) on the unknowns of @p system: the target of the least
    /// squares choice among the solutions, into @p averaged.
    void
    averaged_fe_projections(const PatchSystem             &system,
                            const unsigned int             component,
                            const VertexPatches           &patches,
                            const CellQuantities          &cells,
                            const AlignedVector<EdgeData> &edges,
                            Vector<double>                &averaged)
    {
      averaged.reinit(system.signs.n());
      for (unsigned int u = 0; u < system.unknowns.size(); ++u)
        {
          const EdgeData &edge = edges[system.unknowns[u].first];
          const auto     &edge_cells =
            patches.cells_of_edge(system.unknowns[u].first);
          Tensor<1, 2> traction = cells.fe_stress[edge_cells[0]] * edge.normal;
          if (edge_cells[1] != numbers::invalid_unsigned_int)
            traction =
              0.5 * (traction + cells.fe_stress[edge_cells[1]] * edge.normal);
          averaged[u] = traction[component] * edge.length / 2.;
        }
    }



    /// Work space of the patch systems, one per thread: reused, because
    /// their many small allocations were most of the cost of step 1.
    struct ProjectionScratch
    {
      std::vector<std::pair<unsigned int, unsigned int>> edge_ends;
      PatchSystem                                        system;
      Vector<double>     projections, defect, multiplier, residual;
      FullMatrix<double> gram;
    };



    /// The solution of @p system closest to the target @p solution in the
    /// least squares sense: b = target + A^T (A A^T)^+ (rhs - A target).
    void
    closest_solution(const PatchSystem &system,
                     ProjectionScratch &scratch,
                     Vector<double>    &solution)
    {
      const auto &signs      = system.signs;
      const auto  n_rows     = signs.m();
      const auto  n_unknowns = system.unknowns.size();
      if (n_unknowns == 0)
        return;
      Vector<double> &defect = scratch.defect;
      defect.reinit(n_rows, true);
      signs.vmult(defect, solution);
      defect.sadd(-1., 1., system.rhs);
      // multiplier = (A A^T)^+ defect. Every column of A has one entry (a
      // Dirichlet edge) or two of opposite signs (an edge shared by two cells
      // of the patch); in the latter case A A^T has the kernel span{1}
      // exactly, which adding 1 1^T removes without changing the solution
      // orthogonal to it (the patch is connected: no other kernel).
      bool all_shared = true;
      for (unsigned int u = 0; u < n_unknowns; ++u)
        {
          unsigned int entries = 0;
          for (unsigned int i = 0; i < n_rows; ++i)
            entries += (signs(i, u) != 0.) ? 1 : 0;
          all_shared &= (entries == 2);
        }
      FullMatrix<double> &gram = scratch.gram; // A A^T
      gram.reinit(n_rows, n_rows);
      for (unsigned int i = 0; i < n_rows; ++i)
        for (unsigned int j = 0; j < n_rows; ++j)
          {
            for (unsigned int u = 0; u < n_unknowns; ++u)
              gram(i, j) += signs(i, u) * signs(j, u);
            if (all_shared)
              gram(i, j) += 1.;
          }
      // (by Cholesky: the Gauss-Jordan inverse it replaces was about a
      // tenth of step 1 at 1.6M DoFs; gauss_jordan() on a singular matrix
      // would have failed too)
      AssertThrow(SmallMatrices::cholesky(gram, 1e-12),
                  ExcMessage("a singular patch system of the classical "
                             "densities"));
      Vector<double> &multiplier = scratch.multiplier;
      multiplier                 = defect;
      SmallMatrices::cholesky_solve(gram, multiplier);
      // += A^T multiplier (the columns beyond the unknowns are zero)
      signs.Tvmult_add(solution, multiplier);
    }



    /// The kernel of the matrix of @p system (by SVD): the directions that
    /// keep the prolongation condition, the free parameters of the patch.
    std::vector<FreeDirection>
    free_directions_of(const PatchSystem &system,
                       const unsigned int vertex,
                       const unsigned int component)
    {
      const unsigned int n_rows     = system.signs.m(),
                         n_unknowns = system.unknowns.size();
      LAPACKFullMatrix<double> svd(n_rows, n_unknowns);
      for (unsigned int i = 0; i < n_rows; ++i)
        for (unsigned int u = 0; u < n_unknowns; ++u)
          svd(i, u) = system.signs(i, u);
      svd.compute_svd();
      double       largest = 0.;
      unsigned int rank    = 0;
      for (unsigned int i = 0; i < std::min(n_rows, n_unknowns); ++i)
        largest = std::max(largest, svd.singular_value(i));
      for (unsigned int i = 0; i < std::min(n_rows, n_unknowns); ++i)
        rank += (svd.singular_value(i) > 1e-10 * largest) ? 1 : 0;
      const auto                &right_vectors = svd.get_svd_vt();
      std::vector<FreeDirection> directions;
      for (unsigned int r = rank; r < n_unknowns; ++r)
        {
          FreeDirection direction;
          direction.vertex    = vertex;
          direction.component = component;
          for (unsigned int u = 0; u < n_unknowns; ++u)
            if (std::abs(right_vectors(r, u)) > 1e-14)
              direction.entries.push_back({system.unknowns[u].first,
                                           system.unknowns[u].second,
                                           right_vectors(r, u)});
          directions.push_back(direction);
        }
      return directions;
    }



    /**
     * Step 1 of the element equilibration: on every patch this rank treats,
     * the projections b_G(i) that satisfy the prolongation condition,
     * closest to the averaged FE tractions; with @p find_free_directions also
     * the free parameters of all patches (in vertex order, the patches are
     * then treated serially). Each vertex writes only the projections at its
     * own end of its edges, so the patches are independent and run in
     * parallel. Returns the largest residual of the prolongation condition.
     */
    double
    solve_patch_projections(const VertexPatches        &patches,
                            const CellQuantities       &cells,
                            AlignedVector<EdgeData>    &edges,
                            const bool                  find_free_directions,
                            std::vector<FreeDirection> &free_directions)
    {
      double              max_defect = 0.;
      std::vector<double> defects(find_free_directions ? 0 :
                                                         patches.n_vertices());
      const auto          solve_patch = [&](const unsigned int vertex) {
        double                         patch_defect = 0.;
        std::vector<FreeDirection>     patch_directions;
        thread_local ProjectionScratch scratch;
        const auto                    &edge_ends = scratch.edge_ends;
        edge_ends_at_vertex(vertex, patches, edges, scratch.edge_ends);
        for (unsigned int c = 0; c < 2; ++c)
          {
            const PatchSystem &system = scratch.system;
            assemble_patch_system(
              vertex, c, edge_ends, patches, cells, edges, scratch.system);
            Vector<double> &projections = scratch.projections;
            averaged_fe_projections(
              system, c, patches, cells, edges, projections);
            closest_solution(system, scratch, projections);
            for (unsigned int u = 0; u < system.unknowns.size(); ++u)
              {
                const auto &[edge, end]        = system.unknowns[u];
                edges[edge].projection[end][c] = projections[u];
              }
            if (find_free_directions && !system.unknowns.empty())
              {
                const auto directions = free_directions_of(system, vertex, c);
                patch_directions.insert(patch_directions.end(),
                                        directions.begin(),
                                        directions.end());
              }
            Vector<double> &residual = scratch.residual;
            residual.reinit(system.rhs.size());
            if (!system.unknowns.empty())
              system.signs.vmult(residual, projections);
            residual -= system.rhs;
            patch_defect = std::max(patch_defect, residual.linfty_norm());
          }
        // (in parallel each patch writes only its own defect)
        if (find_free_directions)
          {
            max_defect = std::max(max_defect, patch_defect);
            free_directions.insert(free_directions.end(),
                                   patch_directions.begin(),
                                   patch_directions.end());
          }
        else
          defects[vertex] = patch_defect;
      };
      if (find_free_directions)
        patches.for_each_patch_in_order(solve_patch);
      else
        {
          patches.for_each_patch(solve_patch, 256);
          for (const double defect : defects)
            max_defect = std::max(max_defect, defect);
        }
      return max_defect;
    }



    /// The linear densities from the two projections of each edge:
    /// [b0, b1] = L/6 [[2, 1], [1, 2]] [F0, F1].
    void
    densities_from_projections(const VertexPatches     &patches,
                               AlignedVector<EdgeData> &edges)
    {
      for (unsigned int index = 0; index < edges.size(); ++index)
        if (patches.cells_of_edge(index)[0] != numbers::invalid_unsigned_int)
          {
            EdgeData &edge = edges[index];
            for (unsigned int c = 0; c < 2; ++c)
              {
                const double b0    = edge.projection[0][c],
                             b1    = edge.projection[1][c];
                edge.density[0][c] = 2. / edge.length * (2. * b0 - b1);
                edge.density[1][c] = 2. / edge.length * (2. * b1 - b0);
              }
          }
    }



    /// The largest residual of the prolongation condition over all ranks
    /// (@p residual: this rank's) relative to the largest prolongation load.
    double
    relative_prolongation_defect(const double          residual,
                                 const CellQuantities &cells,
                                 const MPI_Comm        communicator)
    {
      double scale = 0.;
      for (const auto &loads : cells.prolongation_load)
        for (const auto &load : loads)
          scale = std::max(scale, load.norm());
      scale               = Utilities::MPI::max(scale, communicator);
      const double defect = Utilities::MPI::max(residual, communicator);
      return scale > 0. ? defect / scale : defect;
    }



    /// What the local problem of an element needs of its geometry.
    struct ElementGeometry
    {
      /// x = x0 + J xi.
      AffineTriangle map;
      /// The centroid, the point of the moments of the equilibrium check.
      Point<2> center;
      /// The longest edge, the scale h of the linear fields of LocalSpace.
      double diameter;
      /// Global vertex numbers.
      std::array<unsigned int, 3> vertices;
      /// T: the scalar parts of LocalSpace in the reference monomials.
      FullMatrix<double> scalar_coefficients;
    };



    /**
     * Step 2 of the element equilibration: the local Neumann problems
     *   find v_E in the LocalSpace of E with int_E K eps(v_E) : eps(w) =
     *   int_E f_d . w + int_dE eta F^ . w for all w,
     * so that sigma^ = K eps(v_E) on E. The loads read the current densities
     * of the edges (the minimisation changes them). The data of each element
     * are checked for equilibrium (resultant and moment) when its load is
     * built.
     */
    class ElementProblems
    {
    public:
      /// The problems of degree @p degree, the body force integrated with
      /// @p body_quadrature; references to the arguments are kept.
      ElementProblems(const unsigned int             degree,
                      const Quadrature<2>           &body_quadrature,
                      const EquilibrationInput<2>   &input,
                      const VertexPatches           &patches,
                      const CellQuantities          &cells,
                      const AlignedVector<EdgeData> &edges)
        : space(degree, body_quadrature)
        , elasticity(elasticity_matrix(input.material))
        , body_quadrature(body_quadrature)
        , input(input)
        , patches(patches)
        , cells(cells)
        , edges(edges)
      {}

      /// The number of unknowns of a local problem.
      unsigned int
      size() const
      {
        return space.size();
      }

      /// The geometry of a needed cell.
      ElementGeometry
      geometry(const DoFHandler<2>::active_cell_iterator &cell) const
      {
        const unsigned int index    = cell->active_cell_index();
        double             diameter = 0.;
        for (const unsigned int edge : patches.edges(index))
          diameter = std::max(diameter, edges[edge].length);
        const AffineTriangle map(cell);
        return {map,
                cell->center(),
                diameter,
                patches.vertices(index),
                space.scalar_coefficients(map.jacobian, diameter)};
      }

      /// The local stiffness matrix.
      FullMatrix<double>
      stiffness(const ElementGeometry &geometry) const
      {
        return space.stiffness(geometry.scalar_coefficients,
                               geometry.map.inverse_jacobian,
                               geometry.map.determinant,
                               elasticity);
      }

      /// The Cholesky factor of a local stiffness matrix (positive definite:
      /// the space has no rigid motions).
      LAPACKFullMatrix<double>
      factorised(const FullMatrix<double> &stiffness) const
      {
        LAPACKFullMatrix<double> factor(size(), size());
        factor = stiffness;
        factor.set_property(LAPACKSupport::symmetric);
        factor.compute_cholesky_factorization();
        return factor;
      }

      /// Add the load of a linear density (@p density: values at the
      /// vertices of @p edge, in the edge's order, taken with the edge's
      /// orientation on @p cell) to @p load, and if @p resultant is given
      /// its resultant and moment about the centre.
      void
      add_edge_load(const unsigned int                 cell,
                    const ElementGeometry             &geometry,
                    const unsigned int                 edge,
                    const std::array<Tensor<1, 2>, 2> &density,
                    Vector<double>                    &load,
                    Tensor<1, 2>                      *resultant,
                    double                            *moment) const;

      /// The load of a needed cell: its body force (with the rule of the
      /// assembly, so that the element data are in equilibrium to round-off)
      /// and the densities of its edges; records the equilibrium defect.
      Vector<double>
      load(const DoFHandler<2>::active_cell_iterator &cell,
           const ElementGeometry                     &geometry) const;

      /// The coefficients of U^ in the local space: l_0 e_x, l_1 e_y,
      /// l_1 e_x + l_0 e_y carry h eps^_xx, h eps^_yy, h eps^_xy.
      Vector<double>
      admissible_coefficients(const unsigned int     cell,
                              const ElementGeometry &geometry) const
      {
        Vector<double> coefficients(size());
        const auto    &strain = cells.admissible_strain[cell];
        coefficients[0]       = geometry.diameter * strain[0][0];
        coefficients[1]       = geometry.diameter * strain[1][1];
        coefficients[2]       = geometry.diameter * strain[0][1];
        return coefficients;
      }

      /// The largest relative defect of the equilibrium of the element data
      /// (resultant, moment) of the loads built so far.
      double
      equilibrium_defect() const
      {
        return max_equilibrium_defect;
      }

    private:
      /// The local space and its reference integrals.
      const LocalSpace space;
      /// The elasticity matrix (Voigt).
      const FullMatrix<double> elasticity;
      /// The rule of the body-force loads.
      const Quadrature<2> body_quadrature;
      /// The data of the reconstruction.
      const EquilibrationInput<2> &input;
      /// The cells and edges of the patches.
      const VertexPatches &patches;
      /// sigma_h, eps(U^) and whether there is a body force.
      const CellQuantities &cells;
      /// The densities.
      const AlignedVector<EdgeData> &edges;
      /// Guards max_equilibrium_defect (loads are built on worker threads).
      mutable std::mutex defect_mutex;
      /// See equilibrium_defect().
      mutable double max_equilibrium_defect = 0.;
    };



    void
    ElementProblems::add_edge_load(const unsigned int                 cell,
                                   const ElementGeometry             &geometry,
                                   const unsigned int                 edge,
                                   const std::array<Tensor<1, 2>, 2> &density,
                                   Vector<double>                    &load,
                                   Tensor<1, 2>                      *resultant,
                                   double *moment) const
    {
      const EdgeData &data = edges[edge];
      const double    sign = orientation(patches, edge, cell);
      // the reference edge e joins cell vertices e and e + 1
      unsigned int reference_edge = 0;
      bool         reversed       = false;
      for (; reference_edge < 3; ++reference_edge)
        {
          const unsigned int a = geometry.vertices[reference_edge],
                             b = geometry.vertices[(reference_edge + 1) % 3];
          if (a == data.vertices[0] && b == data.vertices[1])
            break;
          if (b == data.vertices[0] && a == data.vertices[1])
            {
              reversed = true;
              break;
            }
        }
      Assert(reference_edge < 3, ExcInternalError());
      std::array<Tensor<1, 2>, 2> traction = {
        {sign * density[0], sign * density[1]}};
      if (reversed)
        std::swap(traction[0], traction[1]);
      space.add_edge_load(geometry.scalar_coefficients,
                          reference_edge,
                          data.length,
                          traction,
                          load);
      if (resultant == nullptr)
        return;
      // two-point Gauss: exact for the linear integrands
      const auto &vertices =
        input.dof_handler.get_triangulation().get_vertices();
      const Point<2> a = vertices[data.vertices[0]];
      const Point<2> b = vertices[data.vertices[1]];
      for (const double s :
           {0.5 - 0.5 / std::sqrt(3.), 0.5 + 0.5 / std::sqrt(3.)})
        {
          const Tensor<1, 2> value =
            sign * ((1. - s) * density[0] + s * density[1]);
          const double JxW = 0.5 * data.length;
          *resultant += value * JxW;
          *moment +=
            cross_product_2d(a + s * (b - a) - geometry.center) * value * JxW;
        }
    }



    Vector<double>
    ElementProblems::load(const DoFHandler<2>::active_cell_iterator &cell,
                          const ElementGeometry &geometry) const
    {
      const unsigned int index = cell->active_cell_index();
      Vector<double>     load(size());
      Tensor<1, 2>       resultant;
      double             moment = 0., data_scale = 0.;
      if (cells.body_force_present)
        {
          const unsigned int          n_points = body_quadrature.size();
          std::vector<Point<2>>       points(n_points);
          std::vector<Vector<double>> force(n_points, Vector<double>(2));
          for (unsigned int q = 0; q < n_points; ++q)
            points[q] = geometry.map.origin +
                        geometry.map.jacobian * body_quadrature.point(q);
          input.boundary_conditions.body_force->vector_value_list(points,
                                                                  force);
          for (unsigned int q = 0; q < n_points; ++q)
            {
              const double JxW =
                body_quadrature.weight(q) * geometry.map.determinant;
              const Tensor<1, 2> f({force[q][0], force[q][1]});
              resultant += f * JxW;
              moment += cross_product_2d(points[q] - geometry.center) * f * JxW;
              data_scale += f.norm() * JxW;
            }
          space.add_body_load(geometry.scalar_coefficients,
                              force,
                              geometry.map.determinant,
                              load);
        }
      for (const unsigned int edge : patches.edges(index))
        {
          const EdgeData &data = edges[edge];
          add_edge_load(
            index, geometry, edge, data.density, load, &resultant, &moment);
          data_scale += 0.5 *
                        (data.density[0].norm() + data.density[1].norm()) *
                        data.length;
        }
      std::lock_guard<std::mutex> lock(defect_mutex);
      if (data_scale > 0.)
        max_equilibrium_defect =
          std::max({max_equilibrium_defect,
                    resultant.norm() / data_scale,
                    std::abs(moment) / (data_scale * geometry.diameter)});
      return load;
    }



    /**
     * The optional choice of the free parameters t that minimises the error
     * measure over the admissible densities (one rank only):
     *   J(t) = sum_E ||w_E + sum_d t_d s_Ed||^2_{K_E},
     * w_E = v_E - U^_E the local error field, s_Ed = K_E^-1 dload_Ed the
     * response of E to the free direction d. CG on H t = -g with
     * H_dd' = sum_E dload_Ed . s_Ed' and g_d = sum_E w_E . dload_Ed; the
     * projections are moved by t (the densities are then to be updated).
     */
    void
    minimise_densities(const ElementProblems            &problems,
                       const VertexPatches              &patches,
                       const std::vector<FreeDirection> &free_directions,
                       const DoFHandler<2>              &dof_handler,
                       AlignedVector<EdgeData>          &edges)
    {
      const unsigned int n_directions = free_directions.size();
      std::vector<std::vector<unsigned int>> directions_of_cell(
        dof_handler.get_triangulation().n_active_cells());
      for (unsigned int d = 0; d < n_directions; ++d)
        for (const unsigned int cell :
             patches.cells_of_vertex(free_directions[d].vertex))
          directions_of_cell[cell].push_back(d);
      DynamicSparsityPattern dsp(n_directions, n_directions);
      for (const auto &directions : directions_of_cell)
        for (const unsigned int d : directions)
          for (const unsigned int e : directions)
            dsp.add(d, e);
      SparsityPattern sparsity;
      sparsity.copy_from(dsp);
      SparseMatrix<double> hessian(sparsity);
      Vector<double>       gradient(n_directions);

      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          const unsigned int index      = cell->active_cell_index();
          const auto        &directions = directions_of_cell[index];
          if (directions.empty())
            continue;
          const ElementGeometry    geometry = problems.geometry(cell);
          LAPACKFullMatrix<double> stiffness =
            problems.factorised(problems.stiffness(geometry));
          Vector<double> error_field = problems.load(cell, geometry);
          stiffness.solve(error_field);
          error_field -= problems.admissible_coefficients(index, geometry);
          std::vector<Vector<double>> delta_load(
            directions.size(), Vector<double>(problems.size()));
          std::vector<Vector<double>> response(directions.size());
          for (unsigned int i = 0; i < directions.size(); ++i)
            {
              const auto &direction = free_directions[directions[i]];
              for (const auto &[edge, end, weight] : direction.entries)
                {
                  const auto &edge_cells = patches.cells_of_edge(edge);
                  if (edge_cells[0] != index && edge_cells[1] != index)
                    continue;
                  // the density of the projection change weight at end
                  const double                length = edges[edge].length;
                  std::array<Tensor<1, 2>, 2> density;
                  density[end][direction.component]     = 4. / length * weight;
                  density[1 - end][direction.component] = -2. / length * weight;
                  problems.add_edge_load(index,
                                         geometry,
                                         edge,
                                         density,
                                         delta_load[i],
                                         nullptr,
                                         nullptr);
                }
              response[i] = delta_load[i];
              stiffness.solve(response[i]);
              gradient[directions[i]] += error_field * delta_load[i];
            }
          for (unsigned int i = 0; i < directions.size(); ++i)
            for (unsigned int j = 0; j < directions.size(); ++j)
              hessian.add(directions[i],
                          directions[j],
                          delta_load[i] * response[j]);
        }
      Vector<double> step(n_directions);
      gradient *= -1.;
      SolverControl                            control(10 * n_directions + 100,
                            1e-10 * gradient.l2_norm(),
                            false,
                            false);
      SolverCG<Vector<double>>                 cg(control);
      PreconditionJacobi<SparseMatrix<double>> jacobi;
      jacobi.initialize(hessian);
      try
        {
          cg.solve(hessian, step, gradient, jacobi);
        }
      catch (const SolverControl::NoConvergence &)
        {
          // keep the partial minimisation: every step stays admissible
        }
      for (unsigned int d = 0; d < n_directions; ++d)
        for (const auto &[edge, end, weight] : free_directions[d].entries)
          edges[edge].projection[end][free_directions[d].component] +=
            step[d] * weight;
    }



    /// The nodal values (@p values: &EdgeData::density or ::projection) of
    /// the edges of the needed cells as density slots (DensityEnhancement),
    /// with @p computed_only only those at the vertices whose patch this
    /// rank computes (zero elsewhere).
    std::vector<double>
    to_slots(const VertexPatches           &patches,
             const DensityEnhancement      &enhancement,
             const AlignedVector<EdgeData> &edges,
             std::array<Tensor<1, 2>, 2> EdgeData::*values,
             const bool                             computed_only)
    {
      std::vector<double> slots(4 * edges.size(), 0.);
      for (unsigned int edge = 0; edge < edges.size(); ++edge)
        if (patches.cells_of_edge(edge)[0] != numbers::invalid_unsigned_int)
          {
            // the EdgeData values are the tractions on the first cell
            const double sign =
              enhancement.sign(edge, patches.cells_of_edge(edge)[0]);
            for (unsigned int end = 0; end < 2; ++end)
              if (!computed_only ||
                  patches.computes_patch(edges[edge].vertices[end]))
                for (unsigned int c = 0; c < 2; ++c)
                  slots[DensityEnhancement::slot(edge, end, c)] =
                    sign * (edges[edge].*values)[end][c];
          }
      return slots;
    }



    /// The inverse of to_slots() (all ends).
    template <typename Slots>
    void
    from_slots(const VertexPatches        &patches,
               const DensityEnhancement   &enhancement,
               const Slots                &slots,
               std::array<Tensor<1, 2>, 2> EdgeData::*values,
               AlignedVector<EdgeData>               &edges)
    {
      for (unsigned int edge = 0; edge < edges.size(); ++edge)
        if (patches.cells_of_edge(edge)[0] != numbers::invalid_unsigned_int)
          {
            const double sign =
              enhancement.sign(edge, patches.cells_of_edge(edge)[0]);
            for (unsigned int end = 0; end < 2; ++end)
              for (unsigned int c = 0; c < 2; ++c)
                (edges[edge].*values)[end][c] =
                  sign * slots[DensityEnhancement::slot(edge, end, c)];
          }
    }



    /**
     * Under MPI a rank has the projections b_G(i) only at the vertices i of
     * its patches; the enhancement needs the densities of every edge of the
     * needed cells. Each projection is taken from the rank that computes
     * the patch of its vertex and summed over the ranks.
     */
    void
    gather_projections(const VertexPatches      &patches,
                       const DensityEnhancement &enhancement,
                       const MPI_Comm            communicator,
                       AlignedVector<EdgeData>  &edges)
    {
      const std::vector<double> slots =
        to_slots(patches, enhancement, edges, &EdgeData::projection, true);
      std::vector<double> sum(slots.size());
      Utilities::MPI::sum(make_array_view(slots),
                          communicator,
                          make_array_view(sum));
      from_slots(patches, enhancement, sum, &EdgeData::projection, edges);
    }



    /**
     * The quadratic of the error of the element problem of @p cell in the
     * density slots of its edges: v_E = A^-1 (l + B F), w_E = v_E - U^_E,
     * J_E = 1/2 w_E^T A w_E has the gradient B^T w_E and the Hessian
     * B^T A^-1 B.
     */
    DensityEnhancement::ElementQuadratic
    element_problem_quadratic(const ElementProblems    &problems,
                              const VertexPatches      &patches,
                              const DensityEnhancement &enhancement,
                              const DoFHandler<2>::active_cell_iterator &cell)
    {
      const unsigned int       index    = cell->active_cell_index();
      const ElementGeometry    geometry = problems.geometry(cell);
      LAPACKFullMatrix<double> stiffness =
        problems.factorised(problems.stiffness(geometry));
      Vector<double> error_field = problems.load(cell, geometry);
      stiffness.solve(error_field);
      error_field -= problems.admissible_coefficients(index, geometry);

      const unsigned int          n = problems.size();
      std::vector<Vector<double>> load(12, Vector<double>(n));
      for (unsigned int e = 0; e < 3; ++e)
        {
          const unsigned int edge = patches.edges(index)[e];
          const double       sign =
            enhancement.sign(edge, patches.cells_of_edge(edge)[0]);
          for (unsigned int j = 0; j < 4; ++j)
            {
              std::array<Tensor<1, 2>, 2> density;
              density[j / 2][j % 2] = sign;
              problems.add_edge_load(index,
                                     geometry,
                                     edge,
                                     density,
                                     load[4 * e + j],
                                     nullptr,
                                     nullptr);
            }
        }
      DensityEnhancement::ElementQuadratic quadratic;
      for (unsigned int a = 0; a < 12; ++a)
        {
          Vector<double> response = load[a];
          stiffness.solve(response);
          quadratic.gradient[a] = load[a] * error_field;
          for (unsigned int b = 0; b < 12; ++b)
            quadratic.hessian[12 * b + a] = load[b] * response;
        }
      return quadratic;
    }



    /**
     * Step 2 with "Element stress = equilibrated": sigma^ on each element is
     * the Johnson-Mercier field of its data (JohnsonMercierElement), a
     * piecewise linear stress on the centroid split in exact equilibrium
     * with the traction densities and the body force f~ of
     * CellQuantities::split_body_force (f_d itself where f_d is constant on
     * the element). The fields come from the reference triangle's maps
     * (JohnsonMercierElement::field()), exact for such data.
     */
    class EquilibratedElements
    {
    public:
      /// The coefficients of a field of the element.
      using Coefficients =
        std::array<double, JohnsonMercierElement::n_coefficients>;

      /// The fields of the elements from the data of @p input and @p cells
      /// and the densities of @p edges (read when a field is asked for).
      EquilibratedElements(const EquilibrationInput<2>   &input,
                           const VertexPatches           &patches,
                           const CellQuantities          &cells,
                           const AlignedVector<EdgeData> &edges)
        : element(JohnsonMercierElement::compliance_matrix(input.material))
        , input(input)
        , patches(patches)
        , cells(cells)
        , edges(edges)
      {}

      /// What one element gives: its map, data and field.
      struct Field
      {
        /// The map from the reference triangle.
        JohnsonMercierElement::AffineMap map;
        /// The vertices, in the cell's order.
        std::array<Point<2>, 3> vertices;
        /// The tractions on the element (JohnsonMercierElement's order).
        std::array<double, JohnsonMercierElement::n_traction_values> traction;
        /// The body force, constant on each sub-triangle
        /// (CellQuantities::split_body_force).
        JohnsonMercierElement::BodyForce body_force;
        /// sigma^, as coefficients.
        Coefficients coefficients;
        /// K eps(U^), as coefficients.
        Coefficients admissible;
      };

      /// The field of a needed cell at the current densities.
      Field
      field(const DoFHandler<2>::active_cell_iterator &cell) const
      {
        const unsigned int index = cell->active_cell_index();
        Field              result;
        for (const unsigned int v : cell->vertex_indices())
          result.vertices[v] = cell->vertex(v);
        result.map = JohnsonMercierElement::affine_map(result.vertices);
        for (unsigned int e = 0; e < 3; ++e)
          {
            const unsigned int edge = patches.edges(index)[e];
            const double       sign = orientation(patches, edge, index);
            for (unsigned int k = 0; k < 2; ++k)
              for (unsigned int c = 0; c < 2; ++c)
                result
                  .traction[JohnsonMercierElement::traction_index(e, k, c)] =
                  sign * edges[edge].density[end_of(index, e, k)][c];
          }
        result.body_force = cells.split_body_force[index];
        result.coefficients =
          element.field(result.map, result.traction, result.body_force);
        const SymmetricTensor<2, 2> admissible =
          input.material.stress(cells.admissible_strain[index]);
        for (unsigned int node = 0; node < 9; ++node)
          {
            result.admissible[3 * node]     = admissible[0][0];
            result.admissible[3 * node + 1] = admissible[1][1];
            result.admissible[3 * node + 2] = admissible[0][1];
          }
        return result;
      }

      /**
       * J_E = 1/2 (x - x_U)^T W (x - x_U) for the coefficients x = R t + x_f
       * of sigma^ and x_U of K eps(U^), in the density slots t = P F of
       * the cell's edges: gradient P^T R^T W (x - x_U), Hessian
       * P^T R^T W R P (JohnsonMercierElement::traction_quadratic() in the
       * tractions t, P the signed permutation of the slots).
       */
      DensityEnhancement::ElementQuadratic
      quadratic(const DoFHandler<2>::active_cell_iterator &cell,
                const DensityEnhancement                  &enhancement) const
      {
        const unsigned int index   = cell->active_cell_index();
        const Field        current = field(cell);
        // (work space of the thread: allocating them per cell was about a
        // tenth of this step at 1.6M DoFs)
        thread_local FullMatrix<double> traction_hessian;
        thread_local Vector<double>     traction_gradient;
        element.traction_quadratic(current.map,
                                   difference(current),
                                   traction_hessian,
                                   traction_gradient);
        // the slot position and sign of each traction value
        std::array<unsigned int, 12> slot;
        std::array<double, 12>       sign;
        for (unsigned int e = 0; e < 3; ++e)
          {
            const double s = enhancement.sign(patches.edges(index)[e], index);
            for (unsigned int k = 0; k < 2; ++k)
              for (unsigned int c = 0; c < 2; ++c)
                {
                  const unsigned int t =
                    JohnsonMercierElement::traction_index(e, k, c);
                  slot[t] = 4 * e + 2 * end_of(index, e, k) + c;
                  sign[t] = s;
                }
          }
        DensityEnhancement::ElementQuadratic result;
        for (unsigned int t = 0; t < 12; ++t)
          {
            result.gradient[slot[t]] = sign[t] * traction_gradient[t];
            for (unsigned int u = 0; u < 12; ++u)
              result.hessian[12 * slot[t] + slot[u]] =
                sign[t] * sign[u] * traction_hessian(t, u);
          }
        return result;
      }

      /// The relative defect of the constraints of a field (only the final
      /// fields are checked: the enhancement's are intermediate).
      double
      defect(const Field &field) const
      {
        return element.constraint_defect(
          field.vertices,
          ArrayView<const double>(field.coefficients.data(),
                                  field.coefficients.size()),
          ArrayView<const double>(field.traction.data(), field.traction.size()),
          field.body_force);
      }

      /// ||sigma^ - K eps(U^)||^2_E and ||sigma^ + K eps(U^)||^2_E.
      std::pair<double, double>
      norm_squares(const Field &field) const
      {
        Coefficients sum;
        for (unsigned int i = 0; i < sum.size(); ++i)
          sum[i] = field.coefficients[i] + field.admissible[i];
        return {element.energy(field.map, difference(field)),
                element.energy(field.map, sum)};
      }

    private:
      /// sigma^ minus K eps(U^), as coefficients.
      static Coefficients
      difference(const Field &field)
      {
        Coefficients result;
        for (unsigned int i = 0; i < result.size(); ++i)
          result[i] = field.coefficients[i] - field.admissible[i];
        return result;
      }

      /// The end of edge @p e of @p cell (in the edge's order) at the
      /// cell's vertex e + k.
      unsigned int
      end_of(const unsigned int cell,
             const unsigned int e,
             const unsigned int k) const
      {
        const unsigned int edge   = patches.edges(cell)[e];
        const unsigned int vertex = patches.vertices(cell)[(e + k) % 3];
        return edges[edge].vertices[0] == vertex ? 0 : 1;
      }

      /// The macro-element.
      const JohnsonMercierElement element;
      /// The data of the reconstruction.
      const EquilibrationInput<2> &input;
      /// The cells and edges of the patches.
      const VertexPatches &patches;
      /// eps(U^) and whether there is a body force.
      const CellQuantities &cells;
      /// The densities.
      const AlignedVector<EdgeData> &edges;
    };



    /// The terms of e [14] of the locally owned cells from the
    /// Johnson-Mercier fields; returns the largest defect of their
    /// constraints.
    double
    assemble_equilibrated_errors(const EquilibratedElements &elements,
                                 const DoFHandler<2>        &dof_handler,
                                 Vector<double>             &error_squared,
                                 Vector<double>             &sum_squared)
    {
      // (the defects per cell, then their maximum: no lock per cell)
      Vector<double> defects(error_squared.size());
      struct NoScratch
      {};
      for_each_cell(
        dof_handler,
        [&](const DoFHandler<2>::active_cell_iterator &cell, NoScratch &) {
          if (!cell->is_locally_owned())
            return;
          const unsigned int index = cell->active_cell_index();
          const auto         field = elements.field(cell);
          std::tie(error_squared[index], sum_squared[index]) =
            elements.norm_squares(field);
          defects[index] = elements.defect(field);
        },
        NoScratch());
      return defects.linfty_norm();
    }



    /**
     * The enhanced densities (DensityEnhancement): under MPI the classical
     * densities of all edges of the needed cells first, then the
     * minimisation of the error of the element fields whose quadratic
     * @p element_quadratic(cell, enhancement) gives; the densities of
     * @p edges are replaced.
     */
    template <typename ElementQuadratic>
    void
    enhance_densities(const VertexPatches         &patches,
                      const std::vector<Point<2>> &vertices,
                      const MPI_Comm               communicator,
                      const ElementQuadratic      &element_quadratic,
                      const unsigned int           max_iterations,
                      const double                 tolerance,
                      const DensityEnhancement::RegionSettings &regions,
                      AlignedVector<EdgeData>                  &edges)
    {
      std::vector<std::array<unsigned int, 2>> edge_vertices(edges.size());
      std::vector<std::array<bool, 2>>         free_components(edges.size());
      for (unsigned int edge = 0; edge < edges.size(); ++edge)
        {
          edge_vertices[edge]   = edges[edge].vertices;
          free_components[edge] = edges[edge].unknown_component;
        }
      const DensityEnhancement enhancement(
        patches, vertices, edge_vertices, free_components, communicator);
      if (Utilities::MPI::n_mpi_processes(communicator) > 1)
        {
          gather_projections(patches, enhancement, communicator, edges);
          densities_from_projections(patches, edges);
        }
      const std::vector<double> initial =
        to_slots(patches, enhancement, edges, &EdgeData::density, false);
      Vector<double> slots(initial.begin(), initial.end());
      enhancement.run(
        [&](const unsigned int cell) {
          return element_quadratic(cell, enhancement);
        },
        max_iterations,
        tolerance,
        regions,
        slots);
      from_slots(patches, enhancement, slots, &EdgeData::density, edges);
    }



    /// sigma^ = K eps(v_E) on the locally owned cells (in parallel) and
    /// ||sigma^ -/+ K eps(U^)||^2_E = (v_E -/+ u^)^T K_E (v_E -/+ u^).
    void
    assemble_errors(const ElementProblems &problems,
                    const DoFHandler<2>   &dof_handler,
                    Vector<double>        &error_squared,
                    Vector<double>        &sum_squared)
    {
      struct NoScratch
      {};
      for_each_cell(
        dof_handler,
        [&](const DoFHandler<2>::active_cell_iterator &cell, NoScratch &) {
          if (!cell->is_locally_owned())
            return;
          const unsigned int       index     = cell->active_cell_index();
          const ElementGeometry    geometry  = problems.geometry(cell);
          const FullMatrix<double> stiffness = problems.stiffness(geometry);
          Vector<double>           solution  = problems.load(cell, geometry);
          problems.factorised(stiffness).solve(solution);
          const Vector<double> admissible =
            problems.admissible_coefficients(index, geometry);
          Vector<double> minus(solution), plus(solution);
          minus -= admissible;
          plus += admissible;
          error_squared[index] = stiffness.matrix_norm_square(minus);
          sum_squared[index]   = stiffness.matrix_norm_square(plus);
        },
        NoScratch());
    }

    /// The names of the values of "Traction densities".
    template <int dim>
    const NamedValues<typename ElementEquilibration<dim>::TractionDensities> &
    traction_densities_names()
    {
      using TractionDensities =
        typename ElementEquilibration<dim>::TractionDensities;
      static const NamedValues<TractionDensities> names(
        {{"enhanced", TractionDensities::enhanced, ""},
         {"least squares", TractionDensities::least_squares, ""},
         {"minimised", TractionDensities::minimised, ""}});
      return names;
    }

    /// The names of the values of "Element stress".
    template <int dim>
    const NamedValues<typename ElementEquilibration<dim>::ElementStress> &
    element_stress_names()
    {
      using ElementStress = typename ElementEquilibration<dim>::ElementStress;
      // (the first is the default)
      static const NamedValues<ElementStress> names(
        {{"equilibrated", ElementStress::equilibrated, ""},
         {"displacement", ElementStress::displacement, ""}});
      return names;
    }
  } // namespace



  template <int dim>
  void
  ElementEquilibration<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    prm.enter_subsection("Element equilibration");
    prm.declare_entry("Local degree",
                      default_local_degree,
                      Patterns::Integer(2, 6),
                      "Polynomial degree p + k of the element problems "
                      "(p = 1; the paper's k = 2 or 3; 3 or 4 on "
                      "tetrahedra).");
    prm.declare_entry("Traction densities",
                      traction_densities_names<dim>().default_name(),
                      Patterns::Selection(
                        traction_densities_names<dim>().selection()),
                      "Choice of the equilibrated traction densities: "
                      "'least squares' towards the averaged FE tractions "
                      "(classical EET), 'minimised' error measure over the "
                      "free parameters of the prolongation condition (one "
                      "extra sparse global solve), or 'enhanced': the error "
                      "measure minimised under element equilibrium only "
                      "(weak prolongation condition, vertex-patch "
                      "preconditioned CG; minimised: triangles only).");
    prm.declare_entry("Element stress",
                      element_stress_names<dim>().default_name(),
                      Patterns::Selection(
                        element_stress_names<dim>().selection()),
                      "sigma^ on each element from its densities: "
                      "'displacement' (Neumann problem of degree Local "
                      "degree, the paper) or 'equilibrated' "
                      "(Johnson-Krizek-Mercier field, exactly statically "
                      "admissible: e is a guaranteed bound, "
                      "doc/estimator.md).");
    // (on tetrahedra the edge patches precondition less well than the
    // vertex patches on triangles: more iterations, doc/estimator.md)
    prm.declare_entry("Enhancement iterations",
                      dim == 2 ? "50" : "300",
                      Patterns::Integer(0, 10000),
                      "Largest number of conjugate gradient iterations of "
                      "the enhanced densities (every iterate is admissible).");
    prm.declare_entry("Enhancement tolerance",
                      dim == 2 ? "1e-4" : "1e-7",
                      Patterns::Double(0., 1.),
                      "Stop the enhancement when an iteration decreases the "
                      "error measure by at most this fraction of the "
                      "decrease so far.");
    // (a region is one dense factor of about 6 columns per vertex: 12
    // rings, some 470 vertices, already take seconds)
    prm.declare_entry("Enhancement regions",
                      "3",
                      Patterns::Integer(0, 20),
                      "Triangles: at most how many regions the "
                      "preconditioner of the enhancement solves at once "
                      "besides the vertex patches, around the vertices whose "
                      "patch alone would make at least 1/200 of the "
                      "decrease of all patches (singular points).");
    prm.declare_entry("Enhancement region rings",
                      "6",
                      Patterns::Integer(0, 12),
                      "Triangles: the radius of each region, in rings of "
                      "cells around its vertex.");
    prm.declare_entry("Simplex implementation",
                      "false",
                      Patterns::Bool(),
                      "On triangles, compute with the dimension-independent "
                      "implementation that runs on tetrahedra (vertex "
                      "patches, either Element stress): a cross-check of the "
                      "two.");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  void
  ElementEquilibration<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    prm.enter_subsection("Element equilibration");
    local_degree = prm.get_integer("Local degree");
    traction_densities =
      traction_densities_names<dim>().value(prm.get("Traction densities"));
    element_stress =
      element_stress_names<dim>().value(prm.get("Element stress"));
    enhancement_iterations    = prm.get_integer("Enhancement iterations");
    enhancement_tolerance     = prm.get_double("Enhancement tolerance");
    enhancement_regions.count = prm.get_integer("Enhancement regions");
    enhancement_regions.rings = prm.get_integer("Enhancement region rings");
    simplex_implementation    = prm.get_bool("Simplex implementation");
    prm.leave_subsection();
    prm.leave_subsection();

    if (simplex_implementation &&
        traction_densities == TractionDensities::minimised)
      throw InputError(
        "Error estimator/Element equilibration/Simplex implementation = true "
        "has no minimised densities: choose enhanced or least squares");
    // (the minimised densities solve element problems of that degree)
    if (element_stress == ElementStress::equilibrated &&
        traction_densities != TractionDensities::minimised &&
        local_degree != std::stoul(default_local_degree))
      warn_once("local degree",
                "Error estimator/Element equilibration/Local degree = " +
                  std::to_string(local_degree) +
                  " is not used: it is the degree of the element problems, "
                  "which Element stress = equilibrated solves none of "
                  "(nor the densities, unless minimised)",
                MPI_COMM_WORLD);
    if (dim == 3 && traction_densities == TractionDensities::minimised)
      throw InputError(
        "Error estimator/Element equilibration/Traction densities = "
        "minimised is written for triangles; on tetrahedra choose enhanced "
        "or least squares");
    if (dim == 3 && element_stress == ElementStress::displacement &&
        local_degree < 3)
      throw InputError(
        "Error estimator/Element equilibration/Local degree must be at "
        "least 3 on tetrahedra (below, some linear face densities do no "
        "work on the element's displacements)");
    if ((dim == 3 || simplex_implementation) && local_degree > 4)
      throw InputError(
        "Error estimator/Element equilibration/Local degree is at most 4 on "
        "tetrahedra and with Simplex implementation (the quadrature of the "
        "element problems)");
  }



  template <int dim>
  std::string
  ElementEquilibration<dim>::condition() const
  {
    return "the prolongation condition (of the classical densities, which "
           "the enhancement starts from)";
  }



  template <int dim>
  void
  ElementEquilibration<dim>::compute(const EquilibrationInput<dim> &input,
                                     const LA::Vector &admissible_displacement,
                                     Vector<double>   &error_squared,
                                     Vector<double>   &sum_squared)
  {
    static_assert(dim == 2,
                  "this implementation is written for triangles (tetrahedra: "
                  "compute_on_simplices())");
    if (simplex_implementation)
      {
        compute_on_simplices(input,
                             admissible_displacement,
                             error_squared,
                             sum_squared);
        return;
      }
    const auto &triangulation = input.dof_handler.get_triangulation();
    AssertThrow(!triangulation.has_hanging_nodes(),
                ExcMessage(
                  "the element equilibration needs a conforming mesh"));
    const MPI_Comm communicator = triangulation.get_communicator();
    const bool     optimise_densities =
      (traction_densities == TractionDensities::minimised);
    if (optimise_densities && Utilities::MPI::n_mpi_processes(communicator) > 1)
      throw InputError("Error estimator/Element equilibration/Traction "
                       "densities = minimised runs "
                       "on one MPI rank only (its free parameters form one "
                       "global system); use least squares");

    const VertexPatches patches(triangulation);
    error_squared.reinit(triangulation.n_active_cells());
    sum_squared.reinit(triangulation.n_active_cells());

    // 0. the data, with the rules of the assembly so that the prolongation
    //    condition and the equilibrium of the element data hold to round-off
    const QGaussSimplex<dim>     quadrature(3);
    const QGaussSimplex<dim - 1> face_quadrature(3);
    const CellQuantities         cells = compute_cell_quantities(
      input, admissible_displacement, patches, quadrature);
    AlignedVector<EdgeData> edges =
      describe_edges(input, patches, face_quadrature);

    // 1. the traction densities from the patch systems of the prolongation
    //    condition, optionally their free parameters minimising the error
    std::vector<FreeDirection> free_directions;
    const double               prolongation_residual = solve_patch_projections(
      patches, cells, edges, optimise_densities, free_directions);
    this->max_condition_defect =
      relative_prolongation_defect(prolongation_residual, cells, communicator);
    densities_from_projections(patches, edges);
    const ElementProblems problems(
      local_degree, quadrature, input, patches, cells, edges);
    if (optimise_densities && !free_directions.empty())
      {
        minimise_densities(
          problems, patches, free_directions, input.dof_handler, edges);
        densities_from_projections(patches, edges);
      }
    const EquilibratedElements equilibrated(input, patches, cells, edges);
    const bool                 equilibrated_stress =
      (element_stress == ElementStress::equilibrated);
    if (traction_densities == TractionDensities::enhanced)
      {
        std::vector<DoFHandler<2>::active_cell_iterator> cell_of_index(
          triangulation.n_active_cells());
        for (const auto &cell : input.dof_handler.active_cell_iterators())
          cell_of_index[cell->active_cell_index()] = cell;
        enhance_densities(
          patches,
          triangulation.get_vertices(),
          communicator,
          [&](const unsigned int cell, const DensityEnhancement &enhancement) {
            return equilibrated_stress ?
                     equilibrated.quadratic(cell_of_index[cell], enhancement) :
                     element_problem_quadratic(problems,
                                               patches,
                                               enhancement,
                                               cell_of_index[cell]);
          },
          enhancement_iterations,
          enhancement_tolerance,
          enhancement_regions,
          edges);
      }

    // 2. and 3. sigma^ on each element (in equilibrium [2] with the element
    //    data) and the terms of e [14] per element
    double defect = 0.;
    if (equilibrated_stress)
      defect = assemble_equilibrated_errors(equilibrated,
                                            input.dof_handler,
                                            error_squared,
                                            sum_squared);
    else
      {
        assemble_errors(problems,
                        input.dof_handler,
                        error_squared,
                        sum_squared);
        defect = problems.equilibrium_defect();
      }
    this->max_equilibrium_defect = Utilities::MPI::max(defect, communicator);
  }



  template <int dim>
  void
  ElementEquilibration<dim>::compute_on_simplices(
    const EquilibrationInput<dim> &input,
    const LA::Vector              &admissible_displacement,
    Vector<double>                &error_squared,
    Vector<double>                &sum_squared)
  {
    SimplexEquilibrationSettings settings;
    settings.degree = local_degree;
    settings.max_iterations =
      (traction_densities == TractionDensities::enhanced) ?
        enhancement_iterations :
        0;
    settings.tolerance = enhancement_tolerance;
    settings.equilibrated_fields =
      element_stress == ElementStress::equilibrated;
    const SimplexEquilibrationChecks checks =
      compute_simplex_element_equilibration(
        input, admissible_displacement, settings, error_squared, sum_squared);
    this->max_condition_defect   = checks.prolongation;
    this->max_equilibrium_defect = checks.equilibrium;
    this->steps                  = checks.seconds;
  }


  // on tetrahedra: the same steps, written for any simplex
  template <>
  void
  ElementEquilibration<3>::compute(const EquilibrationInput<3> &input,
                                   const LA::Vector &admissible_displacement,
                                   Vector<double>   &error_squared,
                                   Vector<double>   &sum_squared)
  {
    compute_on_simplices(input,
                         admissible_displacement,
                         error_squared,
                         sum_squared);
  }


  template class ElementEquilibration<2>;
  template class ElementEquilibration<3>;

  SIGNORINI_REGISTER_TEMPLATE(
    StressReconstruction,
    ElementEquilibration,
    0,
    "element equilibration",
    "traction densities and element fields: by default enhanced densities "
    "and exactly equilibrated fields, a guaranteed bound; the paper's "
    "technique [LAD 91] with least squares densities and displacement fields");
} // namespace Signorini
