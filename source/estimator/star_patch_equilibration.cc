#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>

#include <deal.II/fe/fe.h>

#include <deal.II/lac/full_matrix.h>

#include <signorini/estimator/lagrange_star_patch.h>
#include <signorini/estimator/local_loops.h>
#include <signorini/estimator/small_matrices.h>
#include <signorini/estimator/star_patch_equilibration.h>
#include <signorini/estimator/vertex_patches.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <utility>

namespace Signorini
{
  namespace
  {
    /// Barycentric coordinates (lambda_0, lambda_1, lambda_2) of a point of a
    /// triangle, or derivatives with respect to them.
    using Barycentric = std::array<double, 3>;

    /**
     * Hierarchical basis of the polynomials of degree <= k on a triangle, in
     * barycentric coordinates (lambda_0, lambda_1, lambda_2) of the cell
     * vertices: the vertex functions lambda_a, for each edge e (deal.II's
     * face e, joining vertices e and e + 1 mod 3) the functions
     * lambda_e lambda_{e+1} (lambda_{e+1} - lambda_e)^m, m = 0..k-2, and
     * the interior bubbles lambda_0 lambda_1^(s+1) lambda_2^(t+1),
     * s + t <= k - 3. An edge function changes sign with the orientation
     * of its edge when m is odd: the global function of an edge runs from
     * its lower to its higher global vertex number, so that traces agree
     * between the two cells of the edge.
     */
    class HierarchicalBasis
    {
    public:
      /// What a basis function is attached to.
      enum class Kind
      {
        vertex,
        edge,
        interior
      };
      /// One basis function.
      struct Function
      {
        /// Its kind.
        Kind kind;
        /// Vertex or edge number; rank among the bubbles.
        unsigned int entity;
        /// The exponents m (edge), s and t (bubble).
        unsigned int m, s, t;
      };

      /// The basis of degree @p degree.
      explicit HierarchicalBasis(const unsigned int degree)
      {
        for (unsigned int v = 0; v < 3; ++v)
          functions.push_back({Kind::vertex, v, 0, 0, 0});
        for (unsigned int e = 0; e < 3; ++e)
          for (unsigned int m = 0; m + 2 <= degree; ++m)
            functions.push_back({Kind::edge, e, m, 0, 0});
        unsigned int rank = 0;
        for (unsigned int d = 0; d + 3 <= degree; ++d)
          for (unsigned int s = 0; s <= d; ++s)
            functions.push_back({Kind::interior, rank++, 0, s, d - s});
      }

      /// The number of functions.
      unsigned int
      size() const
      {
        return functions.size();
      }

      /// Function @p f.
      const Function &
      operator[](const unsigned int f) const
      {
        return functions[f];
      }

      /// The value of function @p f at barycentric coordinates @p l.
      double
      value(const unsigned int f, const Barycentric &l) const
      {
        const Function &fn = functions[f];
        switch (fn.kind)
          {
            case Kind::vertex:
              return l[fn.entity];
              case Kind::edge: {
                const unsigned int a = fn.entity, b = (fn.entity + 1) % 3;
                return l[a] * l[b] * std::pow(l[b] - l[a], fn.m);
              }
            default:
              return l[0] * std::pow(l[1], fn.s + 1) * std::pow(l[2], fn.t + 1);
          }
      }

      /// the partial derivatives with respect to lambda_0, lambda_1,
      /// lambda_2 (gradient = sum_a d_a psi grad lambda_a)
      Barycentric
      derivatives(const unsigned int f, const Barycentric &l) const
      {
        const Function &fn = functions[f];
        Barycentric     d  = {{0., 0., 0.}};
        switch (fn.kind)
          {
            case Kind::vertex:
              d[fn.entity] = 1.;
              break;
              case Kind::edge: {
                const unsigned int a = fn.entity, b = (fn.entity + 1) % 3;
                const double       s = l[b] - l[a];
                const double       p = std::pow(s, fn.m);
                const double dp = fn.m > 0 ? fn.m * std::pow(s, fn.m - 1) : 0.;
                d[a]            = l[b] * p - l[a] * l[b] * dp;
                d[b]            = l[a] * p + l[a] * l[b] * dp;
                break;
              }
            default:
              d[0] = std::pow(l[1], fn.s + 1) * std::pow(l[2], fn.t + 1);
              d[1] = (fn.s + 1) * l[0] * std::pow(l[1], fn.s) *
                     std::pow(l[2], fn.t + 1);
              d[2] = (fn.t + 1) * l[0] * std::pow(l[1], fn.s + 1) *
                     std::pow(l[2], fn.t);
          }
        return d;
      }

      /// sign of function f on a cell whose edges have the given orientation
      double
      sign(const unsigned int f, const std::array<bool, 3> &reversed) const
      {
        const Function &fn = functions[f];
        return (fn.kind == Kind::edge && reversed[fn.entity] && fn.m % 2 == 1) ?
                 -1. :
                 1.;
      }

    private:
      /// Vertex, then edge, then interior functions.
      std::vector<Function> functions;
    };



    /**
     * Solve A x = b in place (@p rhs becomes x) for a small symmetric
     * positive definite A (@p matrix), overwritten by its Cholesky factor.
     */
    void
    cholesky_solve(FullMatrix<double> &matrix, Vector<double> &rhs)
    {
      AssertThrow(SmallMatrices::cholesky(matrix),
                  ExcMessage("patch matrix not positive definite"));
      SmallMatrices::cholesky_solve(matrix, rhs);
    }

    /// reference barycentric coordinates of a point of the unit triangle
    Barycentric
    barycentric(const Point<2> &xi)
    {
      return {{1. - xi[0] - xi[1], xi[0], xi[1]}};
    }



    /**
     * The integrals of the hierarchical basis on the reference triangle T
     * from which every cell's stiffness matrix and loads are combined with
     * its barycentric gradients: no quadrature per cell or patch.
     */
    struct ReferenceIntegrals
    {
      /// The tables of degree @p degree.
      explicit ReferenceIntegrals(const unsigned int degree);

      /// The basis psi_i.
      const HierarchicalBasis basis;
      /// The rule of the reference integrals and of the body-force loads.
      const QWitherdenVincentSimplex<2> rule;
      /// The rule of the edge loads.
      const QGauss<1> edge_rule;
      /// derivative_products[a][b](i, j) = int_T d_a psi_i d_b psi_j.
      std::array<std::array<FullMatrix<double>, 3>, 3> derivative_products;
      /// weighted_derivatives[v][a](i) = int_T d_a (lambda_v psi_i).
      std::array<std::array<Vector<double>, 3>, 3> weighted_derivatives;
      /// weighted_values[v](q, i) = lambda_v psi_i at the points of the rule.
      std::array<FullMatrix<double>, 3> weighted_values;
      /// edge_values[e](q, i) = psi_i along edge e at the points of the edge
      /// rule (from vertex e).
      std::array<FullMatrix<double>, 3> edge_values;
    };



    ReferenceIntegrals::ReferenceIntegrals(const unsigned int degree)
      : basis(degree)
      , rule(degree + 1)
      , edge_rule(degree + 2)
    {
      const unsigned int n   = basis.size();
      const unsigned int n_q = rule.size();
      for (auto &row : derivative_products)
        for (auto &products : row)
          products.reinit(n, n);
      for (auto &row : weighted_derivatives)
        for (auto &integrals : row)
          integrals.reinit(n);
      for (auto &values : weighted_values)
        values.reinit(n_q, n);
      for (unsigned int q = 0; q < n_q; ++q)
        {
          const Barycentric        lambda = barycentric(rule.point(q));
          const double             weight = rule.weight(q);
          std::vector<double>      value(n);
          std::vector<Barycentric> derivative(n);
          for (unsigned int i = 0; i < n; ++i)
            {
              value[i]      = basis.value(i, lambda);
              derivative[i] = basis.derivatives(i, lambda);
            }
          for (unsigned int a = 0; a < 3; ++a)
            for (unsigned int b = 0; b < 3; ++b)
              for (unsigned int i = 0; i < n; ++i)
                for (unsigned int j = 0; j < n; ++j)
                  derivative_products[a][b](i, j) +=
                    weight * derivative[i][a] * derivative[j][b];
          for (unsigned int v = 0; v < 3; ++v)
            for (unsigned int i = 0; i < n; ++i)
              {
                weighted_values[v](q, i) = lambda[v] * value[i];
                for (unsigned int a = 0; a < 3; ++a)
                  weighted_derivatives[v][a][i] +=
                    weight *
                    ((a == v ? value[i] : 0.) + lambda[v] * derivative[i][a]);
              }
        }
      for (unsigned int e = 0; e < 3; ++e)
        {
          edge_values[e].reinit(edge_rule.size(), n);
          for (unsigned int q = 0; q < edge_rule.size(); ++q)
            {
              Barycentric lambda  = {{0., 0., 0.}};
              lambda[e]           = 1. - edge_rule.point(q)[0];
              lambda[(e + 1) % 3] = edge_rule.point(q)[0];
              for (unsigned int i = 0; i < n; ++i)
                edge_values[e](q, i) = basis.value(i, lambda);
            }
        }
    }



    /// What the patches need of a cell.
    struct CellData
    {
      /// Whether edge e runs from the higher to the lower global vertex
      /// number (the sign of its odd edge functions).
      std::array<bool, 3> reversed;
      /// The gradients of the barycentric coordinates.
      std::array<Tensor<1, 2>, 3> grad_lambda;
      /// |det J|, twice the area.
      double det = 0.;
      /// sigma_h of U_h (or U~_h).
      SymmetricTensor<2, 2> sigma_h;
      /// Nodal values of U~_h - U^.
      std::array<Tensor<1, 2>, 3> difference;
      /// Nodal values of U~_h + U^.
      std::array<Tensor<1, 2>, 3> sum;
    };



    /// The needed cells' data, and their body force at the points of the
    /// reference rule (empty where f_d vanishes), by active cell index.
    struct CellQuantities
    {
      /// See CellData.
      std::vector<CellData> data;
      /// f_d at the points of ReferenceIntegrals::rule.
      std::vector<std::vector<Tensor<1, 2>>> body_force;
    };



    /// The CellQuantities of the needed cells, in parallel (each cell writes
    /// its own entries).
    CellQuantities
    compute_cell_quantities(const EquilibrationInput<2> &input,
                            const LA::Vector         &admissible_displacement,
                            const VertexPatches      &patches,
                            const ReferenceIntegrals &reference)
    {
      const DoFHandler<2> &dof_handler = input.dof_handler;
      const auto          &fe          = dof_handler.get_fe();
      const unsigned int   n_cells =
        dof_handler.get_triangulation().n_active_cells();
      const unsigned int n_q = reference.rule.size();
      CellQuantities     cells;
      cells.data.resize(n_cells);
      cells.body_force.resize(n_cells);
      struct CellScratch
      {
        Vector<double>              equilibrated, admissible;
        std::vector<Vector<double>> force;
      };
      for_each_cell(
        dof_handler,
        [&](const DoFHandler<2>::active_cell_iterator &cell,
            CellScratch                               &scratch) {
          const unsigned int index = cell->active_cell_index();
          if (!patches.needed(index))
            return;
          CellData            &data = cells.data[index];
          const AffineTriangle map(cell);
          data.det = map.determinant;
          for (unsigned int d = 0; d < 2; ++d)
            {
              data.grad_lambda[1][d] = map.inverse_jacobian[0][d];
              data.grad_lambda[2][d] = map.inverse_jacobian[1][d];
            }
          data.grad_lambda[0]  = -data.grad_lambda[1] - data.grad_lambda[2];
          const auto &vertices = patches.vertices(index);
          for (unsigned int e = 0; e < 3; ++e)
            data.reversed[e] = vertices[e] > vertices[(e + 1) % 3];

          scratch.equilibrated.reinit(fe.n_dofs_per_cell());
          scratch.admissible.reinit(fe.n_dofs_per_cell());
          cell->get_dof_values(input.equilibrated_displacement,
                               scratch.equilibrated);
          cell->get_dof_values(admissible_displacement, scratch.admissible);
          SymmetricTensor<2, 2> strain;
          for (unsigned int v = 0; v < 3; ++v)
            {
              Tensor<1, 2> u_tilde, u_hat;
              for (unsigned int c = 0; c < 2; ++c)
                {
                  const unsigned int i = fe.component_to_system_index(c, v);
                  u_tilde[c]           = scratch.equilibrated[i];
                  u_hat[c]             = scratch.admissible[i];
                }
              strain += symmetrize(outer_product(u_tilde, data.grad_lambda[v]));
              data.difference[v] = u_tilde - u_hat;
              data.sum[v]        = u_tilde + u_hat;
            }
          data.sigma_h = input.material.stress(strain);

          std::vector<Point<2>> points(n_q);
          for (unsigned int q = 0; q < n_q; ++q)
            points[q] = map.origin + map.jacobian * reference.rule.point(q);
          scratch.force.resize(n_q, Vector<double>(2));
          input.boundary_conditions.body_force->vector_value_list(
            points, scratch.force);
          bool present = false;
          for (const auto &f : scratch.force)
            present = present || (f.l2_norm() != 0.);
          if (present)
            {
              cells.body_force[index].resize(n_q);
              for (unsigned int q = 0; q < n_q; ++q)
                cells.body_force[index][q] =
                  Tensor<1, 2>({scratch.force[q][0], scratch.force[q][1]});
            }
        },
        CellScratch());
      return cells;
    }



    /// What the patches need of a boundary edge.
    struct BoundaryEdge
    {
      /// Whether the edge is on the boundary (the others have no data).
      bool at_boundary = false;
      /// The Dirichlet mask.
      std::array<bool, 2> fixed = {{false, false}};
      /// Length.
      double length = 0.;
      /// The face's vertex 0, where the edge rule starts.
      unsigned int first_vertex = numbers::invalid_unsigned_int;
      /// F_d + R^ at the points of the edge rule, from first_vertex on
      /// (empty without traction or contact).
      std::vector<Tensor<1, 2>> load;
    };



    /// The boundary edges of the needed cells (by face index): Dirichlet
    /// masks and the loads F_d + R^ at the points of @p edge_rule.
    std::vector<BoundaryEdge>
    describe_boundary_edges(const EquilibrationInput<2> &input,
                            const VertexPatches         &patches,
                            const Quadrature<1>         &edge_rule)
    {
      const auto        &triangulation = input.dof_handler.get_triangulation();
      const auto        &bc            = input.boundary_conditions;
      const auto        &contact       = input.contact_boundary;
      const Tensor<1, 2> nu_c          = contact.direction();
      std::vector<BoundaryEdge>   edges(triangulation.n_raw_faces());
      std::vector<Vector<double>> traction;
      for (const auto &cell : triangulation.active_cell_iterators())
        if (patches.needed(cell->active_cell_index()))
          for (const unsigned int f : cell->face_indices())
            {
              const auto face = cell->face(f);
              if (!face->at_boundary())
                continue;
              BoundaryEdge &edge = edges[face->index()];
              if (edge.at_boundary)
                continue;
              edge.at_boundary  = true;
              edge.length       = face->measure();
              edge.first_vertex = face->vertex_index(0);
              const auto id     = face->boundary_id();
              // all the parts naming the id: the union of their Dirichlet
              // components, the sum of their tractions
              const ComponentMask fixed = bc.dirichlet_mask(id);
              for (unsigned int c = 0; c < 2; ++c)
                edge.fixed[c] = fixed[c];
              const bool loaded     = bc.has_traction(id);
              const bool in_contact = contact.boundary_ids().count(id) != 0;
              if (!loaded && !in_contact)
                continue;
              edge.load.assign(edge_rule.size(), Tensor<1, 2>());
              const Point<2>        a = face->vertex(0), b = face->vertex(1);
              std::vector<Point<2>> points(edge_rule.size());
              for (unsigned int q = 0; q < edge_rule.size(); ++q)
                points[q] = a + edge_rule.point(q)[0] * (b - a);
              if (loaded)
                bc.traction_values(id, points, traction);
              for (unsigned int q = 0; q < edge_rule.size(); ++q)
                {
                  const double s = edge_rule.point(q)[0];
                  if (loaded)
                    for (unsigned int c = 0; c < 2; ++c)
                      edge.load[q][c] += traction[q][c];
                  if (in_contact)
                    {
                      // R^ = R^_n nu_c, linear on the edge
                      const double r0 =
                        input.normal_reaction[contact.node_index(
                          face->vertex_index(0))];
                      const double r1 =
                        input.normal_reaction[contact.node_index(
                          face->vertex_index(1))];
                      edge.load[q] += ((1. - s) * r0 + s * r1) * nu_c;
                    }
                }
            }
      return edges;
    }



    /**
     * The local stiffness matrix of a cell, dofs (i, c) -> 2 i + c, built
     * anew by each of the cell's three patches and the error pass (a few
     * hundred flops, cheaper than storing (2n)^2 entries per cell):
     * K = sum_ab M^cc'_ab G[a][b] with M^cc'_ab = det sum_de
     * C^cc'_de d_d lambda_a d_e lambda_b (the basis' barycentric
     * derivatives combined once per cell instead of per quadrature point).
     */
    class CellStiffness
    {
    public:
      /// For the basis of @p reference (kept by reference) and @p material.
      CellStiffness(const ReferenceIntegrals       &reference,
                    const LinearElasticMaterial<2> &material)
        : reference(reference)
      {
        for (unsigned int c = 0; c < 2; ++c)
          for (unsigned int d = 0; d < 2; ++d)
            for (unsigned int c2 = 0; c2 < 2; ++c2)
              for (unsigned int e = 0; e < 2; ++e)
                {
                  SymmetricTensor<2, 2> strain_1, strain_2;
                  // one stored entry for [c][d] and [d][c]
                  strain_1[c][d]        = (c == d) ? 1. : 0.5;
                  strain_2[c2][e]       = (c2 == e) ? 1. : 0.5;
                  coupling[c][c2][d][e] = material.stress(strain_2) * strain_1;
                }
      }

      /// The matrix of a cell.
      FullMatrix<double>
      operator()(const CellData &data) const
      {
        const HierarchicalBasis &basis = reference.basis;
        const unsigned int       n     = basis.size();
        double                   gradient_coupling[2][2][3][3] = {}; // M^cc'_ab
        for (unsigned int c = 0; c < 2; ++c)
          for (unsigned int c2 = 0; c2 < 2; ++c2)
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int b = 0; b < 3; ++b)
                for (unsigned int d = 0; d < 2; ++d)
                  for (unsigned int e = 0; e < 2; ++e)
                    gradient_coupling[c][c2][a][b] +=
                      data.det * coupling[c][c2][d][e] *
                      data.grad_lambda[a][d] * data.grad_lambda[b][e];
        FullMatrix<double> matrix(2 * n, 2 * n);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = i; j < n; ++j)
            {
              const double sign =
                basis.sign(i, data.reversed) * basis.sign(j, data.reversed);
              for (unsigned int c = 0; c < 2; ++c)
                for (unsigned int c2 = 0; c2 < 2; ++c2)
                  {
                    double value = 0.;
                    for (unsigned int a = 0; a < 3; ++a)
                      for (unsigned int b = 0; b < 3; ++b)
                        value += gradient_coupling[c][c2][a][b] *
                                 reference.derivative_products[a][b](i, j);
                    matrix(2 * i + c, 2 * j + c2) =
                      matrix(2 * j + c2, 2 * i + c) = sign * value;
                  }
            }
        return matrix;
      }

    private:
      /// The reference integrals.
      const ReferenceIntegrals &reference;
      /// C^cc'_de = sym(e_c x e_d) : C : sym(e_c' x e_e), so that
      /// int eps(psi e_c) : C : eps(chi e_c') = sum_de C^cc'_de int d_d psi
      /// d_e chi.
      double coupling[2][2][2][2];
    };



    /// z_i restricted to every cell, for each of its three vertices i, in
    /// the cell's basis (dofs 2 f + c): sigma^ - sigma_h = sum_i K eps(z_i).
    class PatchCorrections
    {
    public:
      /// Zero corrections for @p n_cells cells and a basis of @p n_functions.
      PatchCorrections(const unsigned int n_cells,
                       const unsigned int n_functions)
        : dofs_per_cell(2 * n_functions)
        , values(static_cast<std::size_t>(n_cells) * 3 * dofs_per_cell)
      {}

      /// z_i on @p cell, i its vertex @p local_vertex.
      double *
      on_cell(const unsigned int cell, const unsigned int local_vertex)
      {
        return &values[(static_cast<std::size_t>(cell) * 3 + local_vertex) *
                       dofs_per_cell];
      }

      /// sum_i z_i on @p cell (@p sum has dofs_per_cell entries).
      void
      sum_on_cell(const unsigned int cell, Vector<double> &sum) const
      {
        for (unsigned int v = 0; v < 3; ++v)
          for (unsigned int i = 0; i < dofs_per_cell; ++i)
            sum[i] +=
              values[(static_cast<std::size_t>(cell) * 3 + v) * dofs_per_cell +
                     i];
      }

      /// 2 n: the dofs of one cell.
      const unsigned int dofs_per_cell;

    private:
      /// The coefficients, by cell, vertex and dof.
      std::vector<double> values;
    };



    /// The numbering of the scalar basis functions of the cells of a patch:
    /// vertices and edges shared between cells get one number (an edge its
    /// first function's; the others follow), bubbles are the cell's own.
    /// The unknowns are 2 s + c.
    struct PatchNumbering
    {
      /// (global vertex number, patch number) of the vertex functions.
      std::vector<std::pair<unsigned int, unsigned int>> vertex_functions;
      /// (face index, first patch number) of the edge functions.
      std::vector<std::pair<unsigned int, unsigned int>> edge_functions;
      /// index[p][f]: the patch number of function f of the p-th cell.
      std::vector<std::vector<unsigned int>> index;
      /// The number of scalar functions.
      unsigned int n_scalars = 0;
    };



    /// The assembled problem of a patch, before the Dirichlet conditions and
    /// the regularisation.
    struct PatchSystem
    {
      /// int K eps(psi) : eps(chi) over the patch.
      FullMatrix<double> matrix;
      /// R(phi_i psi) on the higher-order functions.
      Vector<double> load;
      /// The unknowns the Dirichlet part fixes.
      std::vector<bool> fixed;
      /// R(phi_i e_c), zero by the FE equilibrium ...
      Tensor<1, 2> galerkin_residual;
      /// ... to round-off relative to the sum of its terms' moduli.
      Tensor<1, 2> galerkin_scale;
    };



    /// The largest relative defects of one patch.
    struct PatchDefects
    {
      /// Residual of the (unregularised) patch system: the equilibrium of
      /// its data.
      double equilibrium = 0.;
      /// R(phi_i e_c) relative to its terms, for the components the
      /// Dirichlet part leaves free.
      double galerkin = 0.;
    };



    /**
     * The problem of the patch omega_i of a vertex i: find z_i of degree k
     * on omega_i, zero on the Dirichlet part, with
     *   int_{omega_i} K eps(z_i) : eps(v) = R(phi_i (v - Pi_h v))
     * for all such v. In the hierarchical basis the data are R(phi_i psi)
     * on the higher-order functions psi and zero on the vertex functions.
     */
    class PatchProblems
    {
    public:
      /// The problems of degree @p degree (references to the arguments are
      /// kept).
      PatchProblems(const unsigned int               degree,
                    const ReferenceIntegrals        &reference,
                    const CellStiffness             &cell_stiffness,
                    const CellQuantities            &cells,
                    const std::vector<BoundaryEdge> &edges,
                    const VertexPatches             &patches,
                    const std::vector<Point<2>>     &vertices)
        : degree(degree)
        , reference(reference)
        , cell_stiffness(cell_stiffness)
        , cells(cells)
        , edges(edges)
        , patches(patches)
        , vertices(vertices)
      {}

      /// Solve the problem of @p vertex and write z_i into @p corrections
      /// (only the entries of this vertex in its cells).
      PatchDefects
      solve(const unsigned int vertex, PatchCorrections &corrections) const;

    private:
      /// The numbering of the patch of @p vertex.
      PatchNumbering
      number_functions(const unsigned int vertex) const;

      /// Matrix, loads, Dirichlet unknowns and R(phi_i e_c) of the patch.
      PatchSystem
      assemble(const unsigned int    vertex,
               const PatchNumbering &numbering) const;

      /// The boundary terms of a cell of the patch (@p v: the patch's
      /// vertex in the cell, @p index and @p sign: the patch numbers and
      /// orientation signs of its functions): Dirichlet conditions on all its
      /// edges, F_d + R^ on those through the vertex.
      void
      add_boundary_terms(const unsigned int               cell,
                         const unsigned int               v,
                         const std::vector<unsigned int> &index,
                         const std::vector<double>       &sign,
                         PatchSystem                     &system) const;

      /// The solution on the unknowns the Dirichlet part leaves free (their
      /// patch numbers into @p free), of the system regularised by the rigid
      /// motions that part leaves free (the kernel of the matrix); @p defect
      /// receives the residual of the unregularised system relative to its
      /// load.
      Vector<double>
      solve_without_rigid_motions(const unsigned int         vertex,
                                  const PatchNumbering      &numbering,
                                  const PatchSystem         &system,
                                  std::vector<unsigned int> &free,
                                  double                    &defect) const;

      /// The local degree.
      const unsigned int degree;
      /// The reference integrals.
      const ReferenceIntegrals &reference;
      /// The stiffness matrices of the cells.
      const CellStiffness &cell_stiffness;
      /// The cells' data.
      const CellQuantities &cells;
      /// The boundary edges.
      const std::vector<BoundaryEdge> &edges;
      /// The patches.
      const VertexPatches &patches;
      /// The mesh vertices.
      const std::vector<Point<2>> &vertices;
    };



    PatchNumbering
    PatchProblems::number_functions(const unsigned int vertex) const
    {
      const auto &patch = patches.cells_of_vertex(vertex);
      const auto &basis = reference.basis;
      // the first patch number of a shared entity, numbered on first sight
      const auto number = [](auto              &numbered,
                             const unsigned int key,
                             const unsigned int count,
                             unsigned int      &n_numbered) {
        for (const auto &[k, first] : numbered)
          if (k == key)
            return first;
        numbered.emplace_back(key, n_numbered);
        n_numbered += count;
        return numbered.back().second;
      };
      const unsigned int n_bubbles = (degree - 1) * (degree - 2) / 2;
      PatchNumbering     numbering;
      numbering.index.assign(patch.size(),
                             std::vector<unsigned int>(basis.size()));
      for (unsigned int p = 0; p < patch.size(); ++p)
        {
          const unsigned int bubble_start = numbering.n_scalars;
          numbering.n_scalars += n_bubbles;
          for (unsigned int f = 0; f < basis.size(); ++f)
            {
              const auto &fn = basis[f];
              if (fn.kind == HierarchicalBasis::Kind::vertex)
                numbering.index[p][f] =
                  number(numbering.vertex_functions,
                         patches.vertices(patch[p])[fn.entity],
                         1,
                         numbering.n_scalars);
              else if (fn.kind == HierarchicalBasis::Kind::edge)
                numbering.index[p][f] =
                  number(numbering.edge_functions,
                         patches.edges(patch[p])[fn.entity],
                         degree - 1,
                         numbering.n_scalars) +
                  fn.m;
              else
                numbering.index[p][f] = bubble_start + fn.entity;
            }
        }
      return numbering;
    }



    PatchSystem
    PatchProblems::assemble(const unsigned int    vertex,
                            const PatchNumbering &numbering) const
    {
      const auto        &patch  = patches.cells_of_vertex(vertex);
      const auto        &basis  = reference.basis;
      const unsigned int n      = basis.size();
      const unsigned int n_q    = reference.rule.size();
      const unsigned int n_dofs = 2 * numbering.n_scalars;
      PatchSystem        system;
      system.matrix.reinit(n_dofs, n_dofs);
      system.load.reinit(n_dofs);
      system.fixed.assign(n_dofs, false);
      std::vector<double> sign(n);
      for (unsigned int p = 0; p < patch.size(); ++p)
        {
          const unsigned int       cell  = patch[p];
          const CellData          &data  = cells.data[cell];
          const auto              &index = numbering.index[p];
          const unsigned int       v     = patches.local_vertex(cell, vertex);
          const FullMatrix<double> cell_matrix = cell_stiffness(data);
          for (unsigned int i = 0; i < 2 * n; ++i)
            for (unsigned int j = 0; j < 2 * n; ++j)
              system.matrix(2 * index[i / 2] + i % 2,
                            2 * index[j / 2] + j % 2) += cell_matrix(i, j);
          for (unsigned int f = 0; f < n; ++f)
            sign[f] = basis.sign(f, data.reversed);

          // - int sigma_h : eps(lambda_v psi e_c) + int f_d . lambda_v psi
          const auto &body_force = cells.body_force[cell];
          for (unsigned int f = 0; f < n; ++f)
            for (unsigned int c = 0; c < 2; ++c)
              {
                double value = 0.;
                for (unsigned int d = 0; d < 2; ++d)
                  for (unsigned int a = 0; a < 3; ++a)
                    value -= data.sigma_h[c][d] * data.grad_lambda[a][d] *
                             reference.weighted_derivatives[v][a][f];
                if (!body_force.empty())
                  for (unsigned int q = 0; q < n_q; ++q)
                    value += reference.rule.weight(q) * body_force[q][c] *
                             reference.weighted_values[v](q, f);
                value *= data.det;
                // R(phi_i e_c) = sum over the vertex functions
                if (basis[f].kind == HierarchicalBasis::Kind::vertex)
                  {
                    system.galerkin_residual[c] += value;
                    system.galerkin_scale[c] += std::abs(value);
                  }
                else
                  system.load[2 * index[f] + c] += sign[f] * value;
              }
          add_boundary_terms(cell, v, index, sign, system);
        }
      return system;
    }



    void
    PatchProblems::add_boundary_terms(const unsigned int               cell,
                                      const unsigned int               v,
                                      const std::vector<unsigned int> &index,
                                      const std::vector<double>       &sign,
                                      PatchSystem &system) const
    {
      const auto        &basis     = reference.basis;
      const auto        &edge_rule = reference.edge_rule;
      const unsigned int n         = basis.size();
      for (unsigned int e = 0; e < 3; ++e)
        {
          const BoundaryEdge &edge = edges[patches.edges(cell)[e]];
          if (!edge.at_boundary)
            continue;
          for (unsigned int c = 0; c < 2; ++c)
            if (edge.fixed[c])
              for (unsigned int f = 0; f < n; ++f)
                {
                  const auto &fn = basis[f];
                  if ((fn.kind == HierarchicalBasis::Kind::vertex &&
                       (fn.entity == e || fn.entity == (e + 1) % 3)) ||
                      (fn.kind == HierarchicalBasis::Kind::edge &&
                       fn.entity == e))
                    system.fixed[2 * index[f] + c] = true;
                }
          if (edge.load.empty() || (v != e && v != (e + 1) % 3))
            continue;
          const bool same_direction =
            edge.first_vertex == patches.vertices(cell)[e];
          const unsigned int n_e = edge_rule.size();
          for (unsigned int q = 0; q < n_e; ++q)
            {
              // edge_values run from vertex e, edge.load from first_vertex
              const Tensor<1, 2> &traction =
                edge.load[same_direction ? q : n_e - 1 - q];
              const double lambda_v =
                (v == e) ? 1. - edge_rule.point(q)[0] : edge_rule.point(q)[0];
              const double JxW = edge_rule.weight(q) * edge.length;
              for (unsigned int f = 0; f < n; ++f)
                for (unsigned int c = 0; c < 2; ++c)
                  {
                    const double value = traction[c] * lambda_v *
                                         reference.edge_values[e](q, f) * JxW;
                    if (basis[f].kind == HierarchicalBasis::Kind::vertex)
                      {
                        system.galerkin_residual[c] += value;
                        system.galerkin_scale[c] += std::abs(value);
                      }
                    else
                      system.load[2 * index[f] + c] += sign[f] * value;
                  }
            }
        }
    }



    Vector<double>
    PatchProblems::solve_without_rigid_motions(const unsigned int    vertex,
                                               const PatchNumbering &numbering,
                                               const PatchSystem    &system,
                                               std::vector<unsigned int> &free,
                                               double &defect) const
    {
      const unsigned int n_dofs = 2 * numbering.n_scalars;
      // the rigid motions about the vertex, scaled by the patch size
      const Point<2> &centre = vertices[vertex];
      double          size   = 0.;
      for (const auto &[w, s] : numbering.vertex_functions)
        size = std::max(size, centre.distance(vertices[w]));
      std::array<Vector<double>, 3> rigid;
      for (auto &r : rigid)
        r.reinit(n_dofs);
      for (const auto &[w, s] : numbering.vertex_functions)
        {
          const Point<2> &x   = vertices[w];
          rigid[0][2 * s]     = 1.;
          rigid[1][2 * s + 1] = 1.;
          rigid[2][2 * s]     = -(x[1] - centre[1]) / size;
          rigid[2][2 * s + 1] = (x[0] - centre[0]) / size;
        }
      SymmetricTensor<2, 3> constraint_gram;
      for (unsigned int i = 0; i < n_dofs; ++i)
        if (system.fixed[i])
          for (unsigned int a = 0; a < 3; ++a)
            for (unsigned int b = a; b < 3; ++b)
              constraint_gram[a][b] += rigid[a][i] * rigid[b][i];
      for (unsigned int i = 0; i < n_dofs; ++i)
        if (!system.fixed[i])
          free.push_back(i);
      const unsigned int n_free = free.size();
      FullMatrix<double> free_matrix(n_free, n_free);
      Vector<double>     rhs(n_free);
      double             diagonal = 0.;
      for (unsigned int i = 0; i < n_free; ++i)
        {
          rhs[i] = system.load[free[i]];
          for (unsigned int j = 0; j < n_free; ++j)
            free_matrix(i, j) = system.matrix(free[i], free[j]);
          diagonal += free_matrix(i, i) / n_free;
        }
      FullMatrix<double> factor(free_matrix);
      // (no Dirichlet part: all three motions; else those the constraints
      // leave, from the kernel of their Gram matrix)
      std::vector<Tensor<1, 3>> free_motions;
      if (trace(constraint_gram) == 0.)
        free_motions = {Tensor<1, 3>({1., 0., 0.}),
                        Tensor<1, 3>({0., 1., 0.}),
                        Tensor<1, 3>({0., 0., 1.})};
      else
        for (const auto &[value, direction] : eigenvectors(constraint_gram))
          if (value <= 1e-10 * trace(constraint_gram))
            free_motions.push_back(direction);
      for (const auto &direction : free_motions)
        {
          Vector<double> motion(n_free);
          for (unsigned int i = 0; i < n_free; ++i)
            for (unsigned int a = 0; a < 3; ++a)
              motion[i] += direction[a] * rigid[a][free[i]];
          const double weight = diagonal / (motion * motion);
          for (unsigned int i = 0; i < n_free; ++i)
            for (unsigned int j = 0; j < n_free; ++j)
              factor(i, j) += weight * motion[i] * motion[j];
        }
      Vector<double> solution(rhs);
      cholesky_solve(factor, solution);

      // residual of the unregularised problem: the data's equilibrium
      Vector<double> residual(n_free);
      free_matrix.vmult(residual, solution);
      residual -= rhs;
      defect = rhs.l2_norm() > 0. ? residual.l2_norm() / rhs.l2_norm() : 0.;
      return solution;
    }



    PatchDefects
    PatchProblems::solve(const unsigned int vertex,
                         PatchCorrections  &corrections) const
    {
      const auto               &patch     = patches.cells_of_vertex(vertex);
      const PatchNumbering      numbering = number_functions(vertex);
      const PatchSystem         system    = assemble(vertex, numbering);
      PatchDefects              defects;
      std::vector<unsigned int> free;
      const Vector<double>      solution = solve_without_rigid_motions(
        vertex, numbering, system, free, defects.equilibrium);

      Vector<double> z_patch(2 * numbering.n_scalars);
      for (unsigned int i = 0; i < free.size(); ++i)
        z_patch[free[i]] = solution[i];
      for (unsigned int p = 0; p < patch.size(); ++p)
        {
          double *z_cell =
            corrections.on_cell(patch[p],
                                patches.local_vertex(patch[p], vertex));
          for (unsigned int f = 0; f < reference.basis.size(); ++f)
            for (unsigned int c = 0; c < 2; ++c)
              z_cell[2 * f + c] = z_patch[2 * numbering.index[p][f] + c];
        }

      for (const auto &[w, s] : numbering.vertex_functions)
        if (w == vertex)
          for (unsigned int c = 0; c < 2; ++c)
            if (!system.fixed[2 * s + c] && system.galerkin_scale[c] > 0.)
              defects.galerkin =
                std::max(defects.galerkin,
                         std::abs(system.galerkin_residual[c]) /
                           system.galerkin_scale[c]);
      return defects;
    }



    /// The problems of all the patches this rank treats, on the worker
    /// threads (each writes only its own vertex's part of @p corrections);
    /// returns the largest defects.
    PatchDefects
    solve_patch_problems(const PatchProblems &problems,
                         const VertexPatches &patches,
                         PatchCorrections    &corrections)
    {
      PatchDefects max_defects;
      std::mutex   defect_mutex;
      patches.for_each_patch(
        [&](const unsigned int vertex) {
          const PatchDefects defects = problems.solve(vertex, corrections);
          std::lock_guard<std::mutex> lock(defect_mutex);
          max_defects.equilibrium =
            std::max(max_defects.equilibrium, defects.equilibrium);
          max_defects.galerkin =
            std::max(max_defects.galerkin, defects.galerkin);
        },
        64);
      return max_defects;
    }



    /// sigma^ -/+ K eps(U^) = K eps(U~_h -/+ U^ + sum_i z_i) on the locally
    /// owned cells (in parallel), and its squared energy norms.
    void
    assemble_errors(const CellStiffness    &cell_stiffness,
                    const CellQuantities   &cells,
                    const PatchCorrections &corrections,
                    const DoFHandler<2>    &dof_handler,
                    Vector<double>         &error_squared,
                    Vector<double>         &sum_squared)
    {
      struct NoScratch
      {};
      for_each_cell(
        dof_handler,
        [&](const DoFHandler<2>::active_cell_iterator &cell, NoScratch &) {
          if (!cell->is_locally_owned())
            return;
          const unsigned int       index  = cell->active_cell_index();
          const CellData          &data   = cells.data[index];
          const FullMatrix<double> matrix = cell_stiffness(data);
          Vector<double>           correction(corrections.dofs_per_cell);
          corrections.sum_on_cell(index, correction);
          Vector<double> minus(correction), plus(correction);
          for (unsigned int v = 0; v < 3; ++v)
            for (unsigned int c = 0; c < 2; ++c)
              {
                // the vertex function of v is basis function v
                minus[2 * v + c] += data.difference[v][c];
                plus[2 * v + c] += data.sum[v][c];
              }
          error_squared[index] = matrix.matrix_norm_square(minus);
          sum_squared[index]   = matrix.matrix_norm_square(plus);
        },
        NoScratch());
    }
  } // namespace



  template <int dim>
  void
  StarPatchEquilibration<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    prm.enter_subsection("Star patch");
    prm.declare_entry("Local degree",
                      "2",
                      Patterns::Integer(2, 6),
                      "Polynomial degree of the vertex-patch problems (p + 1 "
                      "= 2 by default; higher degrees approach the exact "
                      "patch solutions and a larger effectivity, see "
                      "doc/estimator.md); 2 on tetrahedra.");
    prm.declare_entry("Lagrange elements",
                      "false",
                      Patterns::Bool(),
                      "Solve the patch problems of triangles with deal.II's "
                      "Lagrange elements, as on tetrahedra, instead of the "
                      "written-out basis: the same estimate, slower (a "
                      "cross-check of the two implementations).");
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  void
  StarPatchEquilibration<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    prm.enter_subsection("Star patch");
    local_degree      = prm.get_integer("Local degree");
    lagrange_elements = (dim == 3 || prm.get_bool("Lagrange elements"));
    prm.leave_subsection();
    prm.leave_subsection();

    // deal.II 9.4's FE_SimplexP fails on tetrahedra beyond degree 2, and
    // up to degree 3 on triangles
    const unsigned int highest = (dim == 3) ? 2 : 3;
    if (lagrange_elements && local_degree > highest)
      throw InputError(
        "Error estimator/Star patch/Local degree = " +
        std::to_string(local_degree) + ": at most " + std::to_string(highest) +
        (dim == 3 ? " on tetrahedra" : " with Lagrange elements = true"));
  }



  template <int dim>
  std::string
  StarPatchEquilibration<dim>::condition() const
  {
    return "the finite element equilibrium R(phi_i e_c) = 0 of the patch data";
  }



  template <int dim>
  void
  StarPatchEquilibration<dim>::compute(
    const EquilibrationInput<dim> &input,
    const LA::Vector              &admissible_displacement,
    Vector<double>                &error_squared,
    Vector<double>                &sum_squared)
  {
    static_assert(dim == 2,
                  "the star-patch equilibration is written for "
                  "triangles");
    if (lagrange_elements)
      {
        compute_with_lagrange_elements(input,
                                       admissible_displacement,
                                       error_squared,
                                       sum_squared);
        return;
      }
    const auto &triangulation = input.dof_handler.get_triangulation();
    AssertThrow(!triangulation.has_hanging_nodes(),
                ExcMessage("the star-patch equilibration needs a conforming "
                           "mesh"));
    const unsigned int n_cells = triangulation.n_active_cells();

    const VertexPatches patches(triangulation);
    error_squared.reinit(n_cells);
    sum_squared.reinit(n_cells);

    // the data: per cell sigma_h, U~_h -/+ U^ and f_d; F_d + R^ on the
    // boundary edges
    const ReferenceIntegrals reference(local_degree);
    const CellStiffness      cell_stiffness(reference, input.material);
    const CellQuantities     cells = compute_cell_quantities(
      input, admissible_displacement, patches, reference);
    const std::vector<BoundaryEdge> edges =
      describe_boundary_edges(input, patches, reference.edge_rule);

    // the patch problems z_i
    const PatchProblems problems(local_degree,
                                 reference,
                                 cell_stiffness,
                                 cells,
                                 edges,
                                 patches,
                                 triangulation.get_vertices());
    PatchCorrections    corrections(n_cells, reference.basis.size());
    const PatchDefects  max_defects =
      solve_patch_problems(problems, patches, corrections);

    // sigma^ = sigma_h + sum_i K eps(z_i) and the terms of e [14] per cell
    assemble_errors(cell_stiffness,
                    cells,
                    corrections,
                    input.dof_handler,
                    error_squared,
                    sum_squared);

    const MPI_Comm communicator = triangulation.get_communicator();
    this->max_equilibrium_defect =
      Utilities::MPI::max(max_defects.equilibrium, communicator);
    this->max_condition_defect =
      Utilities::MPI::max(max_defects.galerkin, communicator);
  }



  template <int dim>
  void
  StarPatchEquilibration<dim>::compute_with_lagrange_elements(
    const EquilibrationInput<dim> &input,
    const LA::Vector              &admissible_displacement,
    Vector<double>                &error_squared,
    Vector<double>                &sum_squared)
  {
    const StarPatchDefects defects = compute_lagrange_star_patch(
      input, admissible_displacement, local_degree, error_squared, sum_squared);
    const MPI_Comm communicator =
      input.dof_handler.get_triangulation().get_communicator();
    this->max_equilibrium_defect =
      Utilities::MPI::max(defects.equilibrium, communicator);
    this->max_condition_defect =
      Utilities::MPI::max(defects.galerkin, communicator);
  }



  // on tetrahedra: the same construction with deal.II's Lagrange elements
  template <>
  void
  StarPatchEquilibration<3>::compute(const EquilibrationInput<3> &input,
                                     const LA::Vector &admissible_displacement,
                                     Vector<double>   &error_squared,
                                     Vector<double>   &sum_squared)
  {
    compute_with_lagrange_elements(input,
                                   admissible_displacement,
                                   error_squared,
                                   sum_squared);
  }

  template class StarPatchEquilibration<2>;
  template class StarPatchEquilibration<3>;

  SIGNORINI_REGISTER_TEMPLATE(StressReconstruction,
                              StarPatchEquilibration,
                              1,
                              "star patch",
                              "flux-free vertex-patch problems");
} // namespace Signorini
