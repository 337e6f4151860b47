#include <deal.II/base/mpi.h>
#include <deal.II/base/parallel.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>

#include <deal.II/fe/fe.h>

#include <deal.II/lac/full_matrix.h>

#include <signorini/estimator/local_loops.h>
#include <signorini/estimator/star_patch_equilibration.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>

namespace Signorini
{
  namespace
  {
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
      enum class Kind
      {
        vertex,
        edge,
        interior
      };
      struct Function
      {
        Kind         kind;
        unsigned int entity; // vertex or edge number; rank among bubbles
        unsigned int m, s, t;
      };

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

      unsigned int
      size() const
      {
        return functions.size();
      }

      const Function &
      operator[](const unsigned int f) const
      {
        return functions[f];
      }

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
      std::vector<Function> functions;
    };

    /**
     * Solve A x = b in place (@p b becomes x) for a small symmetric positive
     * definite A, overwritten by its Cholesky factor. Written out because
     * the patch systems are tiny (tens of unknowns) and solved by the
     * hundred thousand on the worker threads.
     */
    void
    cholesky_solve(FullMatrix<double> &A, Vector<double> &b)
    {
      const unsigned int n = A.m();
      for (unsigned int j = 0; j < n; ++j)
        {
          double d = A(j, j);
          for (unsigned int k = 0; k < j; ++k)
            d -= A(j, k) * A(j, k);
          AssertThrow(d > 0., ExcMessage("patch matrix not positive definite"));
          A(j, j) = std::sqrt(d);
          for (unsigned int i = j + 1; i < n; ++i)
            {
              double v = A(i, j);
              for (unsigned int k = 0; k < j; ++k)
                v -= A(i, k) * A(j, k);
              A(i, j) = v / A(j, j);
            }
        }
      for (unsigned int i = 0; i < n; ++i)
        {
          for (unsigned int k = 0; k < i; ++k)
            b[i] -= A(i, k) * b[k];
          b[i] /= A(i, i);
        }
      for (unsigned int i = n; i-- > 0;)
        {
          for (unsigned int k = i + 1; k < n; ++k)
            b[i] -= A(k, i) * b[k];
          b[i] /= A(i, i);
        }
    }

    /// reference barycentric coordinates of a point of the unit triangle
    Barycentric
    barycentric(const Point<2> &xi)
    {
      return {{1. - xi[0] - xi[1], xi[0], xi[1]}};
    }

    /// what the patches need of a cell
    struct CellData
    {
      std::array<unsigned int, 3> vertices; // global vertex numbers
      std::array<unsigned int, 3> edges;    // face e joins vertices e, e + 1
      std::array<bool, 3>         reversed; // edge runs from higher to lower
      std::array<Tensor<1, 2>, 3> grad_lambda;
      double                      det = 0.; // twice the area
      Point<2>                    x0;
      Tensor<2, 2>                J;
      SymmetricTensor<2, 2>       sigma_h;
      // nodal values of U~_h - U^ and U~_h + U^
      std::array<Tensor<1, 2>, 3> difference, sum;

      /// 0, 1 or 2: the cell's number of one of its vertices
      unsigned int
      local_vertex(const unsigned int vertex) const
      {
        return std::find(vertices.begin(), vertices.end(), vertex) -
               vertices.begin();
      }
    };

    /// what the patches need of a boundary edge
    struct BoundaryEdge
    {
      bool                at_boundary  = false;
      std::array<bool, 2> fixed        = {{false, false}}; // Dirichlet mask
      double              length       = 0.;
      unsigned int        first_vertex = numbers::invalid_unsigned_int;
      // F_d + R^ at the points of the edge rule, from first_vertex on
      std::vector<Tensor<1, 2>> load;
    };
  } // namespace



  template <int dim>
  void
  StarPatchEquilibration<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Local degree",
                      "2",
                      Patterns::Integer(2, 6),
                      "Polynomial degree of the vertex-patch problems (p + 1 "
                      "= 2 by default; higher degrees approach the exact "
                      "patch solutions and a larger effectivity, see "
                      "doc/estimator.md).");
  }



  template <int dim>
  StarPatchEquilibration<dim>::StarPatchEquilibration(ParameterHandler &prm)
    : local_degree(prm.get_integer("Local degree"))
  {}



  template <int dim>
  std::string
  StarPatchEquilibration<dim>::name() const
  {
    return "star patch";
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
    const auto &dof_handler   = input.dof_handler;
    const auto &triangulation = dof_handler.get_triangulation();
    const auto &fe            = dof_handler.get_fe();
    const auto &material      = input.material;
    const auto &bc            = input.boundary_conditions;
    AssertThrow(!triangulation.has_hanging_nodes(),
                ExcMessage("the star-patch equilibration needs a conforming "
                           "mesh"));
    const unsigned int n_cells      = triangulation.n_active_cells();
    const MPI_Comm     communicator = triangulation.get_communicator();

    // Under MPI every rank treats the patches of the vertices of its cells,
    // which cover the cells around them ("needed").
    std::vector<bool>       vertex_of_owned_cell;
    const std::vector<bool> needed =
      cells_around_owned_cells(triangulation, vertex_of_owned_cell);

    error_squared.reinit(n_cells);
    sum_squared.reinit(n_cells);
    this->max_equilibrium_defect  = 0.;
    this->max_prolongation_defect = 0.;

    // --- reference tables ---------------------------------------------------
    const HierarchicalBasis           basis(local_degree);
    const unsigned int                n = basis.size();
    const QWitherdenVincentSimplex<2> rule(local_degree + 1);
    const QGauss<1>                   edge_rule(local_degree + 2);
    const unsigned int                n_q = rule.size();
    // G[a][b](i, j) = int_T d_a psi_i d_b psi_j
    std::array<std::array<FullMatrix<double>, 3>, 3> G;
    // L[v][a](i) = int_T d_a (lambda_v psi_i)
    std::array<std::array<Vector<double>, 3>, 3> L;
    // lambda_v psi_i at the points of the rule, and lambda at them
    std::array<FullMatrix<double>, 3> body_values;
    for (auto &row : G)
      for (auto &g : row)
        g.reinit(n, n);
    for (auto &row : L)
      for (auto &l : row)
        l.reinit(n);
    for (auto &b : body_values)
      b.reinit(n_q, n);
    for (unsigned int q = 0; q < n_q; ++q)
      {
        const Barycentric        l = barycentric(rule.point(q));
        const double             w = rule.weight(q);
        std::vector<double>      value(n);
        std::vector<Barycentric> d(n);
        for (unsigned int i = 0; i < n; ++i)
          {
            value[i] = basis.value(i, l);
            d[i]     = basis.derivatives(i, l);
          }
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j < n; ++j)
                G[a][b](i, j) += w * d[i][a] * d[j][b];
        for (unsigned int v = 0; v < 3; ++v)
          for (unsigned int i = 0; i < n; ++i)
            {
              body_values[v](q, i) = l[v] * value[i];
              for (unsigned int a = 0; a < 3; ++a)
                L[v][a][i] += w * ((a == v ? value[i] : 0.) + l[v] * d[i][a]);
            }
      }
    // psi_i along edge e at the points of the edge rule (from vertex e)
    std::array<FullMatrix<double>, 3> edge_values;
    for (unsigned int e = 0; e < 3; ++e)
      {
        edge_values[e].reinit(edge_rule.size(), n);
        for (unsigned int q = 0; q < edge_rule.size(); ++q)
          {
            Barycentric l  = {{0., 0., 0.}};
            l[e]           = 1. - edge_rule.point(q)[0];
            l[(e + 1) % 3] = edge_rule.point(q)[0];
            for (unsigned int i = 0; i < n; ++i)
              edge_values[e](q, i) = basis.value(i, l);
          }
      }

    // A[c][c2][d][e] = sym(e_c x e_d) : C : sym(e_c2 x e_e), so that
    // int eps(psi e_c) : C : eps(chi e_c2) = sum_de A int d_d psi d_e chi
    double A[2][2][2][2];
    for (unsigned int c = 0; c < 2; ++c)
      for (unsigned int d = 0; d < 2; ++d)
        for (unsigned int c2 = 0; c2 < 2; ++c2)
          for (unsigned int e = 0; e < 2; ++e)
            {
              SymmetricTensor<2, 2> strain_1, strain_2;
              // one stored entry for [c][d] and [d][c]
              strain_1[c][d]  = (c == d) ? 1. : 0.5;
              strain_2[c2][e] = (c2 == e) ? 1. : 0.5;
              A[c][c2][d][e]  = material.stress(strain_2) * strain_1;
            }

    // --- cells ---------------------------------------------------------------
    std::vector<CellData>                  cells(n_cells);
    std::vector<std::vector<Tensor<1, 2>>> body_force(n_cells);
    struct CellScratch
    {
      Vector<double>              equilibrated, admissible;
      std::vector<Vector<double>> force;
    };
    for_each_cell(
      dof_handler,
      [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
          CellScratch                                          &scratch) {
        const unsigned int E = cell->active_cell_index();
        if (!needed[E])
          return;
        CellData &data = cells[E];
        data.x0        = cell->vertex(0);
        for (unsigned int d = 0; d < 2; ++d)
          {
            data.J[d][0] = cell->vertex(1)[d] - data.x0[d];
            data.J[d][1] = cell->vertex(2)[d] - data.x0[d];
          }
        data.det                     = std::abs(determinant(data.J));
        const Tensor<2, 2> J_inverse = invert(data.J);
        for (unsigned int d = 0; d < 2; ++d)
          {
            data.grad_lambda[1][d] = J_inverse[0][d];
            data.grad_lambda[2][d] = J_inverse[1][d];
          }
        data.grad_lambda[0] = -data.grad_lambda[1] - data.grad_lambda[2];
        for (unsigned int v = 0; v < 3; ++v)
          data.vertices[v] = cell->vertex_index(v);
        for (unsigned int e = 0; e < 3; ++e)
          {
            const auto face = cell->face(e);
            data.edges[e]   = face->index();
            Assert((face->vertex_index(0) == data.vertices[e] &&
                    face->vertex_index(1) == data.vertices[(e + 1) % 3]) ||
                     (face->vertex_index(1) == data.vertices[e] &&
                      face->vertex_index(0) == data.vertices[(e + 1) % 3]),
                   ExcInternalError());
            data.reversed[e] = data.vertices[e] > data.vertices[(e + 1) % 3];
          }

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
        data.sigma_h = material.stress(strain);

        std::vector<Point<2>> points(n_q);
        for (unsigned int q = 0; q < n_q; ++q)
          points[q] = data.x0 + data.J * rule.point(q);
        scratch.force.resize(n_q, Vector<double>(2));
        bc.body_force->vector_value_list(points, scratch.force);
        bool present = false;
        for (const auto &f : scratch.force)
          present = present || (f.l2_norm() != 0.);
        if (present)
          {
            body_force[E].resize(n_q);
            for (unsigned int q = 0; q < n_q; ++q)
              body_force[E][q] =
                Tensor<1, 2>({scratch.force[q][0], scratch.force[q][1]});
          }
      },
      CellScratch());

    // --- boundary edges: Dirichlet masks and loads F_d + R^ ------------------
    const auto          &contact = input.contact_boundary;
    const Tensor<1, dim> nu_c    = contact.direction();

    std::vector<BoundaryEdge>   edges(triangulation.n_raw_faces());
    std::vector<Vector<double>> traction;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (needed[cell->active_cell_index()])
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
                    const double r0 = input.normal_reaction[contact.node_index(
                      face->vertex_index(0))];
                    const double r1 = input.normal_reaction[contact.node_index(
                      face->vertex_index(1))];
                    edge.load[q] += ((1. - s) * r0 + s * r1) * nu_c;
                  }
              }
          }

    std::vector<std::vector<unsigned int>> cells_of_vertex(
      triangulation.n_vertices());
    for (unsigned int E = 0; E < n_cells; ++E)
      if (needed[E])
        for (unsigned int v = 0; v < 3; ++v)
          cells_of_vertex[cells[E].vertices[v]].push_back(E);

    // the local stiffness matrix of a cell, dofs (i, c) -> 2 i + c (built
    // anew by each of the cell's three patches and the final pass: a few
    // hundred flops, cheaper than storing (2n)^2 entries per cell):
    // K = sum_ab M^cc'_ab G[a][b] with M^cc'_ab = det sum_de A^cc'_de
    // d_d lambda_a d_e lambda_b (the basis' barycentric derivatives
    // combined once per cell instead of per quadrature point)
    const auto cell_stiffness = [&](const CellData &data) {
      double M[2][2][3][3] = {};
      for (unsigned int c = 0; c < 2; ++c)
        for (unsigned int c2 = 0; c2 < 2; ++c2)
          for (unsigned int a = 0; a < 3; ++a)
            for (unsigned int b = 0; b < 3; ++b)
              for (unsigned int d = 0; d < 2; ++d)
                for (unsigned int e = 0; e < 2; ++e)
                  M[c][c2][a][b] += data.det * A[c][c2][d][e] *
                                    data.grad_lambda[a][d] *
                                    data.grad_lambda[b][e];
      FullMatrix<double> K(2 * n, 2 * n);
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
                      value += M[c][c2][a][b] * G[a][b](i, j);
                  K(2 * i + c, 2 * j + c2) = K(2 * j + c2, 2 * i + c) =
                    sign * value;
                }
          }
      return K;
    };

    // z_i restricted to a cell, for each of its three vertices i, in the
    // cell's basis (dofs 2 f + c)
    const unsigned int  n_z = 2 * n; // per cell and vertex
    std::vector<double> z(static_cast<std::size_t>(n_cells) * 3 * n_z);
    std::mutex          defect_mutex;

    // --- the patch problems --------------------------------------------------
    const auto process_patch = [&](const unsigned int vertex) {
      const auto &patch = cells_of_vertex[vertex];
      if (patch.empty() || !vertex_of_owned_cell[vertex])
        return;
      // patch numbering of the scalar functions of every cell: vertices
      // and edges shared between cells get one number (the first edge
      // function; the others follow), bubbles are the cell's own
      std::vector<std::pair<unsigned int, unsigned int>> vertex_functions,
        edge_functions; // (global number, first patch number)
      const auto number = [&](auto              &numbered,
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
      const unsigned int n_bubbles =
        (local_degree - 1) * (local_degree - 2) / 2;
      std::vector<std::vector<unsigned int>> index(
        patch.size(), std::vector<unsigned int>(n));
      unsigned int n_scalars = 0;
      for (unsigned int p = 0; p < patch.size(); ++p)
        {
          const CellData    &data         = cells[patch[p]];
          const unsigned int bubble_start = n_scalars;
          n_scalars += n_bubbles;
          for (unsigned int f = 0; f < n; ++f)
            {
              const auto &fn = basis[f];
              if (fn.kind == HierarchicalBasis::Kind::vertex)
                index[p][f] = number(vertex_functions,
                                     data.vertices[fn.entity],
                                     1,
                                     n_scalars);
              else if (fn.kind == HierarchicalBasis::Kind::edge)
                index[p][f] = number(edge_functions,
                                     data.edges[fn.entity],
                                     local_degree - 1,
                                     n_scalars) +
                              fn.m;
              else
                index[p][f] = bubble_start + fn.entity;
            }
        }
      const unsigned int N = 2 * n_scalars;

      // assembly; the loads R(phi_i psi) on the higher-order functions
      FullMatrix<double>  K(N, N);
      Vector<double>      load(N);
      std::vector<bool>   fixed(N, false);
      Tensor<1, 2>        galerkin, galerkin_scale;
      std::vector<double> sign(n);
      for (unsigned int p = 0; p < patch.size(); ++p)
        {
          const unsigned int       E    = patch[p];
          const CellData          &data = cells[E];
          const unsigned int       v    = data.local_vertex(vertex);
          const FullMatrix<double> K_E  = cell_stiffness(data);
          for (unsigned int i = 0; i < 2 * n; ++i)
            for (unsigned int j = 0; j < 2 * n; ++j)
              K(2 * index[p][i / 2] + i % 2, 2 * index[p][j / 2] + j % 2) +=
                K_E(i, j);
          for (unsigned int f = 0; f < n; ++f)
            sign[f] = basis.sign(f, data.reversed);

          // - int sigma_h : eps(lambda_v psi e_c) + int f_d . lambda_v psi
          for (unsigned int f = 0; f < n; ++f)
            for (unsigned int c = 0; c < 2; ++c)
              {
                double value = 0.;
                for (unsigned int d = 0; d < 2; ++d)
                  for (unsigned int a = 0; a < 3; ++a)
                    value -=
                      data.sigma_h[c][d] * data.grad_lambda[a][d] * L[v][a][f];
                if (!body_force[E].empty())
                  for (unsigned int q = 0; q < n_q; ++q)
                    value += rule.weight(q) * body_force[E][q][c] *
                             body_values[v](q, f);
                value *= data.det;
                // R(phi_i e_c) = sum over the vertex functions
                if (basis[f].kind == HierarchicalBasis::Kind::vertex)
                  {
                    galerkin[c] += value;
                    galerkin_scale[c] += std::abs(value);
                  }
                else
                  load[2 * index[p][f] + c] += sign[f] * value;
              }

          // the edges of the cell: loads on those through the vertex,
          // Dirichlet conditions on all of them
          for (unsigned int e = 0; e < 3; ++e)
            {
              const BoundaryEdge &edge = edges[data.edges[e]];
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
                        fixed[2 * index[p][f] + c] = true;
                    }
              if (edge.load.empty() || (v != e && v != (e + 1) % 3))
                continue;
              const bool same_direction = edge.first_vertex == data.vertices[e];
              const unsigned int n_e    = edge_rule.size();
              for (unsigned int q = 0; q < n_e; ++q)
                {
                  // edge_values run from vertex e, edge.load from first_vertex
                  const Tensor<1, 2> &t =
                    edge.load[same_direction ? q : n_e - 1 - q];
                  const double lambda_v = (v == e) ?
                                            1. - edge_rule.point(q)[0] :
                                            edge_rule.point(q)[0];
                  const double JxW      = edge_rule.weight(q) * edge.length;
                  for (unsigned int f = 0; f < n; ++f)
                    for (unsigned int c = 0; c < 2; ++c)
                      {
                        const double value =
                          t[c] * lambda_v * edge_values[e](q, f) * JxW;
                        if (basis[f].kind == HierarchicalBasis::Kind::vertex)
                          {
                            galerkin[c] += value;
                            galerkin_scale[c] += std::abs(value);
                          }
                        else
                          load[2 * index[p][f] + c] += sign[f] * value;
                      }
                }
            }
        }
      // the rigid motions about the vertex that the Dirichlet conditions
      // leave free span the kernel of K: regularise with them
      const Point<2> &centre = triangulation.get_vertices()[vertex];
      double          size   = 0.;
      for (const auto &[w, s] : vertex_functions)
        size = std::max(size, centre.distance(triangulation.get_vertices()[w]));
      std::array<Vector<double>, 3> rigid;
      for (auto &r : rigid)
        r.reinit(N);
      for (const auto &[w, s] : vertex_functions)
        {
          const Point<2> &x   = triangulation.get_vertices()[w];
          rigid[0][2 * s]     = 1.;
          rigid[1][2 * s + 1] = 1.;
          rigid[2][2 * s]     = -(x[1] - centre[1]) / size;
          rigid[2][2 * s + 1] = (x[0] - centre[0]) / size;
        }
      SymmetricTensor<2, 3> constraint_gram;
      for (unsigned int i = 0; i < N; ++i)
        if (fixed[i])
          for (unsigned int a = 0; a < 3; ++a)
            for (unsigned int b = a; b < 3; ++b)
              constraint_gram[a][b] += rigid[a][i] * rigid[b][i];
      std::vector<unsigned int> free;
      for (unsigned int i = 0; i < N; ++i)
        if (!fixed[i])
          free.push_back(i);
      const unsigned int n_free = free.size();
      FullMatrix<double> K_free(n_free, n_free);
      Vector<double>     rhs(n_free);
      double             diagonal = 0.;
      for (unsigned int i = 0; i < n_free; ++i)
        {
          rhs[i] = load[free[i]];
          for (unsigned int j = 0; j < n_free; ++j)
            K_free(i, j) = K(free[i], free[j]);
          diagonal += K_free(i, i) / n_free;
        }
      FullMatrix<double> factor(K_free);
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
          Vector<double> r(n_free);
          for (unsigned int i = 0; i < n_free; ++i)
            for (unsigned int a = 0; a < 3; ++a)
              r[i] += direction[a] * rigid[a][free[i]];
          const double weight = diagonal / (r * r);
          for (unsigned int i = 0; i < n_free; ++i)
            for (unsigned int j = 0; j < n_free; ++j)
              factor(i, j) += weight * r[i] * r[j];
        }
      Vector<double> solution(rhs);
      cholesky_solve(factor, solution);

      // residual of the unregularised problem: the data's equilibrium
      Vector<double> residual(n_free);
      K_free.vmult(residual, solution);
      residual -= rhs;
      const double defect =
        rhs.l2_norm() > 0. ? residual.l2_norm() / rhs.l2_norm() : 0.;

      Vector<double> z_patch(N);
      for (unsigned int i = 0; i < n_free; ++i)
        z_patch[free[i]] = solution[i];
      for (unsigned int p = 0; p < patch.size(); ++p)
        {
          const unsigned int E    = patch[p];
          const CellData    &data = cells[E];
          const unsigned int v    = data.local_vertex(vertex);
          double *z_E = &z[(static_cast<std::size_t>(E) * 3 + v) * n_z];
          for (unsigned int f = 0; f < n; ++f)
            for (unsigned int c = 0; c < 2; ++c)
              z_E[2 * f + c] = z_patch[2 * index[p][f] + c];
        }

      // R(phi_i e_c) for the components the Dirichlet part leaves free
      double galerkin_defect = 0.;
      for (const auto &[w, s] : vertex_functions)
        if (w == vertex)
          for (unsigned int c = 0; c < 2; ++c)
            if (!fixed[2 * s + c] && galerkin_scale[c] > 0.)
              galerkin_defect =
                std::max(galerkin_defect,
                         std::abs(galerkin[c]) / galerkin_scale[c]);
      std::lock_guard<std::mutex> lock(defect_mutex);
      this->max_equilibrium_defect =
        std::max(this->max_equilibrium_defect, defect);
      this->max_prolongation_defect =
        std::max(this->max_prolongation_defect, galerkin_defect);
    };
    parallel::apply_to_subranges(
      0u,
      static_cast<unsigned int>(cells_of_vertex.size()),
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int vertex = begin; vertex < end; ++vertex)
          process_patch(vertex);
      },
      64);

    // --- sigma^ -/+ K eps(U^) = K eps(U~_h -/+ U^ + sum_i z_i) per cell ------
    struct NoScratch
    {};
    for_each_cell(
      dof_handler,
      [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
          NoScratch &) {
        if (!cell->is_locally_owned())
          return;
        const unsigned int       E    = cell->active_cell_index();
        const CellData          &data = cells[E];
        const FullMatrix<double> K_E  = cell_stiffness(data);
        Vector<double>           correction(n_z);
        for (unsigned int v = 0; v < 3; ++v)
          for (unsigned int i = 0; i < n_z; ++i)
            correction[i] += z[(static_cast<std::size_t>(E) * 3 + v) * n_z + i];
        Vector<double> minus(correction), plus(correction);
        for (unsigned int v = 0; v < 3; ++v)
          for (unsigned int c = 0; c < 2; ++c)
            {
              // the vertex function of v is basis function v
              minus[2 * v + c] += data.difference[v][c];
              plus[2 * v + c] += data.sum[v][c];
            }
        error_squared[E] = K_E.matrix_norm_square(minus);
        sum_squared[E]   = K_E.matrix_norm_square(plus);
      },
      NoScratch());

    this->max_equilibrium_defect =
      Utilities::MPI::max(this->max_equilibrium_defect, communicator);
    this->max_prolongation_defect =
      Utilities::MPI::max(this->max_prolongation_defect, communicator);
  }

  template class StarPatchEquilibration<2>;
} // namespace Signorini
