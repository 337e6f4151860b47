#include <deal.II/base/mpi.h>
#include <deal.II/base/parallel.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/estimator/johnson_krizek_mercier_element.h>
#include <signorini/estimator/simplex_element_equilibration.h>
#include <signorini/estimator/small_matrices.h>
#include <signorini/progress.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>

namespace Signorini
{
  namespace
  {
    constexpr unsigned int invalid = numbers::invalid_unsigned_int;

    /// The number of rigid motions of R^dim.
    template <int dim>
    constexpr unsigned int n_rigid = (dim * (dim + 1)) / 2;

    /// Component @p c at @p x of rigid motion @p k (translations, then
    /// rotations), about @p centre in units of @p size.
    template <int dim>
    double
    rigid_motion(const unsigned int k,
                 const Point<dim>  &x,
                 const Point<dim>  &centre,
                 const double       size,
                 const unsigned int c)
    {
      if (k < dim)
        return (c == k) ? 1. : 0.;
      static constexpr unsigned int planes[3][2] = {{0, 1}, {1, 2}, {0, 2}};
      const unsigned int a = planes[k - dim][0], b = planes[k - dim][1];
      return (c == a) ? -(x[b] - centre[b]) / size :
             (c == b) ? (x[a] - centre[a]) / size :
                        0.;
    }

    /**
     * The conforming simplex mesh, held whole by every rank: the vertices and
     * faces of each cell and the cells of each face (faces are numbered
     * compactly here). A face's densities are the tractions on its first
     * cell (the one of lower active cell index), at its vertices in the
     * face's own order, so every cell and rank reads them the same way.
     */
    template <int dim>
    struct SimplexMesh
    {
      explicit SimplexMesh(const Triangulation<dim> &triangulation)
        : vertices(triangulation.get_vertices())
        , cell_vertices(triangulation.n_active_cells())
        , cell_faces(triangulation.n_active_cells())
        , subdomain(triangulation.n_active_cells())
        , owned(triangulation.n_active_cells())
        , cells_of_vertex(triangulation.n_vertices())
      {
        std::vector<unsigned int> compact(triangulation.n_raw_faces(), invalid);
        for (const auto &cell : triangulation.active_cell_iterators())
          {
            const unsigned int index = cell->active_cell_index();
            subdomain[index]         = cell->subdomain_id();
            owned[index]             = cell->is_locally_owned();
            for (const unsigned int v : cell->vertex_indices())
              {
                cell_vertices[index][v] = cell->vertex_index(v);
                cells_of_vertex[cell->vertex_index(v)].push_back(index);
              }
            for (const unsigned int f : cell->face_indices())
              {
                const auto face = cell->face(f);
                if (compact[face->index()] == invalid)
                  {
                    compact[face->index()] = face_cells.size();
                    face_cells.push_back({{index, invalid}});
                    std::array<unsigned int, dim> corners;
                    for (unsigned int k = 0; k < dim; ++k)
                      corners[k] = face->vertex_index(k);
                    face_vertices.push_back(corners);
                    face_boundary.push_back(
                      face->at_boundary() ? face->boundary_id() :
                                            numbers::internal_face_boundary_id);
                    face_measure.push_back(simplex_face_measure(corners));
                  }
                else
                  face_cells[compact[face->index()]][1] = index;
                cell_faces[index][f] = compact[face->index()];
              }
          }
      }

      /// The area (3D) or length (2D) of the face with these corners.
      double
      simplex_face_measure(const std::array<unsigned int, dim> &corners) const
      {
        if constexpr (dim == 2)
          return vertices[corners[0]].distance(vertices[corners[1]]);
        else
          return 0.5 *
                 cross_product_3d(vertices[corners[1]] - vertices[corners[0]],
                                  vertices[corners[2]] - vertices[corners[0]])
                   .norm();
      }

      /// +1 if the densities of @p face are the tractions on @p cell.
      double
      sign(const unsigned int face, const unsigned int cell) const
      {
        return (face_cells[face][0] == cell) ? 1. : -1.;
      }

      /// Whether vertex @p vertex is a corner of face @p face; its position.
      unsigned int
      corner(const unsigned int face, const unsigned int vertex) const
      {
        for (unsigned int k = 0; k < dim; ++k)
          if (face_vertices[face][k] == vertex)
            return k;
        return invalid;
      }

      /// The position in @p cell of the vertex opposite its face @p f.
      unsigned int
      opposite_vertex(const unsigned int cell, const unsigned int f) const
      {
        unsigned int v = 0;
        while (corner(cell_faces[cell][f], cell_vertices[cell][v]) != invalid)
          ++v;
        return v;
      }

      /// The triangulation's vertices.
      const std::vector<Point<dim>> &vertices;
      /// By active cell index: its vertices, in the cell's order.
      std::vector<std::array<unsigned int, dim + 1>> cell_vertices;
      /// By active cell index: its faces, in the cell's order.
      std::vector<std::array<unsigned int, dim + 1>> cell_faces;
      /// By active cell index: its subdomain (the rank that owns it).
      std::vector<types::subdomain_id> subdomain;
      /// By active cell index: whether this rank owns it.
      std::vector<bool> owned;
      /// By vertex: the cells around it, in increasing index.
      std::vector<std::vector<unsigned int>> cells_of_vertex;
      /// By face: its vertices.
      std::vector<std::array<unsigned int, dim>> face_vertices;
      /// By face: its first and second cell (invalid on the boundary).
      std::vector<std::array<unsigned int, 2>> face_cells;
      /// By face: its boundary id (internal_face_boundary_id inside).
      std::vector<types::boundary_id> face_boundary;
      /// By face: its area (3D) or length (2D).
      std::vector<double> face_measure;
    };

    /**
     * The hinges of the enhancement's patches: the vertices of a triangle
     * mesh, the edges of a tetrahedral one; for each, the cells around it and
     * whether this rank computes its patch (the lowest subdomain among
     * these cells is this rank's).
     */
    template <int dim>
    struct Hinges
    {
      Hinges(const SimplexMesh<dim> &mesh, const unsigned int rank)
        : mesh(mesh)
      {
        if constexpr (dim == 2)
          for (unsigned int v = 0; v < mesh.cells_of_vertex.size(); ++v)
            {
              if (mesh.cells_of_vertex[v].empty())
                continue;
              vertices.push_back({{v, v}});
              cells.push_back(mesh.cells_of_vertex[v]);
            }
        else
          {
            // the edges, numbered by their first vertex, then second
            for (unsigned int v = 0; v < mesh.cells_of_vertex.size(); ++v)
              {
                std::vector<unsigned int> neighbours;
                for (const unsigned int cell : mesh.cells_of_vertex[v])
                  for (const unsigned int w : mesh.cell_vertices[cell])
                    if (w > v)
                      neighbours.push_back(w);
                std::sort(neighbours.begin(), neighbours.end());
                neighbours.erase(std::unique(neighbours.begin(),
                                             neighbours.end()),
                                 neighbours.end());
                for (const unsigned int w : neighbours)
                  {
                    std::vector<unsigned int> around;
                    for (const unsigned int cell : mesh.cells_of_vertex[v])
                      {
                        const auto &corners = mesh.cell_vertices[cell];
                        if (std::find(corners.begin(), corners.end(), w) !=
                            corners.end())
                          around.push_back(cell);
                      }
                    vertices.push_back({{v, w}});
                    cells.push_back(around);
                  }
              }
          }
        computes.resize(vertices.size());
        for (unsigned int h = 0; h < vertices.size(); ++h)
          {
            types::subdomain_id lowest = numbers::invalid_subdomain_id;
            for (const unsigned int cell : cells[h])
              lowest = std::min(lowest, mesh.subdomain[cell]);
            computes[h] = (lowest == rank);
          }
      }

      /// The number of hinges.
      unsigned int
      size() const
      {
        return vertices.size();
      }

      /// The number of hinge @p hinge among the dim hinges of face @p face
      /// (2D: its corner; 3D: the corner opposite the edge).
      unsigned int
      position_in_face(const unsigned int hinge, const unsigned int face) const
      {
        if (vertices[hinge][0] == vertices[hinge][1])
          return mesh.corner(face, vertices[hinge][0]);
        else
          {
            const unsigned int a = mesh.corner(face, vertices[hinge][0]);
            const unsigned int b = mesh.corner(face, vertices[hinge][1]);
            return 3 - a - b;
          }
      }

      /// Whether face @p face contains hinge @p hinge.
      bool
      in_face(const unsigned int hinge, const unsigned int face) const
      {
        return mesh.corner(face, vertices[hinge][0]) != invalid &&
               mesh.corner(face, vertices[hinge][1]) != invalid;
      }

      const SimplexMesh<dim> &mesh;
      /// The vertices of each hinge (twice the vertex in 2D).
      std::vector<std::array<unsigned int, 2>> vertices;
      /// The cells around each hinge, in increasing index.
      std::vector<std::vector<unsigned int>> cells;
      /// Whether this rank computes the patch of each hinge.
      std::vector<bool> computes;
    };

    /// Slot of face @p face, corner @p k, component @p c in the vector of
    /// all densities (or of their projections).
    template <int dim>
    unsigned int
    slot(const unsigned int face, const unsigned int k, const unsigned int c)
    {
      return (face * dim + k) * dim + c;
    }

    /// The values per element: (dim + 1) faces, dim corners, dim components.
    template <int dim>
    constexpr unsigned int n_element_values = (dim + 1) * (dim * dim);

    /// The affine geometry of a simplex.
    template <int dim>
    struct CellGeometry
    {
      CellGeometry(const SimplexMesh<dim> &mesh, const unsigned int cell)
      {
        for (unsigned int v = 0; v <= dim; ++v)
          x[v] = mesh.vertices[mesh.cell_vertices[cell][v]];
        Tensor<2, dim> jacobian;
        for (unsigned int k = 1; k <= dim; ++k)
          for (unsigned int i = 0; i < dim; ++i)
            jacobian[i][k - 1] = x[k][i] - x[0][i];
        determinant                  = std::abs(dealii::determinant(jacobian));
        measure                      = determinant / (dim == 2 ? 2. : 6.);
        const Tensor<2, dim> inverse = invert(jacobian);
        grad_hat[0]                  = Tensor<1, dim>();
        for (unsigned int k = 1; k <= dim; ++k)
          {
            for (unsigned int i = 0; i < dim; ++i)
              grad_hat[k][i] = inverse[k - 1][i];
            grad_hat[0] -= grad_hat[k];
          }
        centre = Point<dim>();
        size   = 0.;
        for (unsigned int v = 0; v <= dim; ++v)
          {
            centre += x[v] / (dim + 1.);
            for (unsigned int w = 0; w < v; ++w)
              size = std::max(size, x[v].distance(x[w]));
          }
        for (unsigned int f = 0; f <= dim; ++f)
          {
            const unsigned int opposite = mesh.opposite_vertex(cell, f);
            // the hat of the opposite vertex grows inwards
            normal[f] = -grad_hat[opposite] / grad_hat[opposite].norm();
          }
      }

      /// The point of barycentric coordinates (1 - sum xi, xi).
      Point<dim>
      point(const Point<dim> &xi) const
      {
        Point<dim> p = x[0];
        for (unsigned int k = 1; k <= dim; ++k)
          p += xi[k - 1] * (x[k] - x[0]);
        return p;
      }

      /// The vertices, in the cell's order.
      std::array<Point<dim>, dim + 1> x;
      /// The gradients of their hat functions.
      std::array<Tensor<1, dim>, dim + 1> grad_hat;
      /// The outward unit normal of each face, in the cell's order.
      std::array<Tensor<1, dim>, dim + 1> normal;
      /// |det J| of the affine map from the reference simplex, the measure,
      /// the longest edge.
      double determinant, measure, size;
      /// The centroid.
      Point<dim> centre;
    };

    /// int_G phi_k l for the hat of corner @p k of a face of @p measure and
    /// the linear function l of values @p values at its corners.
    template <int dim>
    double
    hat_times_linear(const double                   measure,
                     const unsigned int             k,
                     const std::array<double, dim> &values)
    {
      double sum = values[k];
      for (unsigned int m = 0; m < dim; ++m)
        sum += values[m];
      return measure * sum / (dim * (dim + 1.));
    }

    /**
     * The displacements of the element problems: vector polynomials of
     * degree 1 to p in coordinates centred on the cell and scaled by its
     * size, without the rigid motions (the linear part is spanned by the
     * dim (dim + 1) / 2 pure strains), so that the stiffness is definite.
     */
    template <int dim>
    class ElementSpace
    {
    public:
      /// The largest degree written out.
      static constexpr unsigned int max_degree = 6;

      explicit ElementSpace(const unsigned int degree)
        : degree(degree)
      {
        AssertThrow(degree >= 1 && degree <= max_degree,
                    ExcMessage("element problems of degree 1 to 6"));
        // the linear pure strains: x_a e_a, and x_b e_a + x_a e_b
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = a; b < dim; ++b)
            {
              std::vector<Term>             terms;
              std::array<unsigned int, dim> exponent{};
              exponent[b] = 1;
              terms.push_back({a, exponent});
              if (a != b)
                {
                  exponent    = {};
                  exponent[a] = 1;
                  terms.push_back({b, exponent});
                }
              basis.push_back(terms);
            }
        for (unsigned int total = 2; total <= degree; ++total)
          for (const auto &exponent : exponents(total))
            for (unsigned int c = 0; c < dim; ++c)
              basis.push_back({{c, exponent}});
      }

      unsigned int
      size() const
      {
        return basis.size();
      }

      /// Values and strains of the basis at @p x of a cell of @p centre and
      /// @p size.
      void
      evaluate(const Point<dim>                     &x,
               const Point<dim>                     &centre,
               const double                          size,
               std::vector<Tensor<1, dim>>          &values,
               std::vector<SymmetricTensor<2, dim>> &strains) const
      {
        const Tensor<1, dim> y = (x - centre) / size;
        // powers[d][e] = y_d^e, and e y_d^(e - 1) / size
        std::array<std::array<double, max_degree + 1>, dim> powers, slopes;
        for (unsigned int d = 0; d < dim; ++d)
          {
            powers[d][0] = 1.;
            slopes[d][0] = 0.;
            for (unsigned int e = 1; e <= degree; ++e)
              {
                powers[d][e] = powers[d][e - 1] * y[d];
                slopes[d][e] = e * powers[d][e - 1] / size;
              }
          }
        values.resize(basis.size());
        strains.resize(basis.size());
        for (unsigned int j = 0; j < basis.size(); ++j)
          {
            values[j] = Tensor<1, dim>();
            Tensor<2, dim> gradient;
            for (const auto &term : basis[j])
              {
                double value = 1.;
                for (unsigned int d = 0; d < dim; ++d)
                  value *= powers[d][term.exponent[d]];
                values[j][term.component] += value;
                for (unsigned int e = 0; e < dim; ++e)
                  {
                    double slope = slopes[e][term.exponent[e]];
                    for (unsigned int d = 0; d < dim; ++d)
                      if (d != e)
                        slope *= powers[d][term.exponent[d]];
                    gradient[term.component][e] += slope;
                  }
              }
            strains[j] = symmetrize(gradient);
          }
      }

    private:
      /// u_c = prod_d y_d^exponent_d
      struct Term
      {
        unsigned int                  component;
        std::array<unsigned int, dim> exponent;
      };

      /// The exponents of the monomials of degree @p total.
      static std::vector<std::array<unsigned int, dim>>
      exponents(const unsigned int total)
      {
        std::vector<std::array<unsigned int, dim>> result;
        if constexpr (dim == 2)
          for (unsigned int i = 0; i <= total; ++i)
            result.push_back({{i, total - i}});
        else
          for (unsigned int i = 0; i <= total; ++i)
            for (unsigned int j = 0; i + j <= total; ++j)
              result.push_back({{i, j, total - i - j}});
        return result;
      }

      const unsigned int             degree;
      std::vector<std::vector<Term>> basis;
    };

    /// The data every rank shares: per cell sigma_h and eps(U^).
    template <int dim>
    struct CellStrains
    {
      /// By active cell index: sigma_h (constant on P1 cells).
      std::vector<SymmetricTensor<2, dim>> sigma_h;
      /// By active cell index: eps(U^).
      std::vector<SymmetricTensor<2, dim>> admissible_strain;
    };

    /// sigma_h and eps(U^) on every cell (each rank evaluates its own and
    /// the sum over ranks completes them: every entry has one contribution).
    template <int dim>
    CellStrains<dim>
    cell_strains(const EquilibrationInput<dim> &input,
                 const LA::Vector              &admissible_displacement)
    {
      const auto        &triangulation = input.dof_handler.get_triangulation();
      const unsigned int n_cells       = triangulation.n_active_cells();
      constexpr unsigned int n_entries =
        SymmetricTensor<2, dim>::n_independent_components;
      std::vector<double>              local(2 * n_entries * n_cells, 0.);
      const FEValuesExtractors::Vector displacement(0);
      FEValues<dim>                    values(input.mapping,
                           input.dof_handler.get_fe(),
                           QGaussSimplex<dim>(1),
                           update_gradients);
      std::vector<Tensor<2, dim>>      gradient(1);
      for (const auto &cell : input.dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            values.reinit(cell);
            const unsigned int index = cell->active_cell_index();
            values[displacement].get_function_gradients(
              input.equilibrated_displacement, gradient);
            const SymmetricTensor<2, dim> sigma_h =
              input.material.stress(symmetrize(gradient[0]));
            values[displacement].get_function_gradients(admissible_displacement,
                                                        gradient);
            const SymmetricTensor<2, dim> strain = symmetrize(gradient[0]);
            for (unsigned int e = 0; e < n_entries; ++e)
              {
                const auto entry =
                  SymmetricTensor<2, dim>::unrolled_to_component_indices(e);
                local[(2 * index) * n_entries + e]     = sigma_h[entry];
                local[(2 * index + 1) * n_entries + e] = strain[entry];
              }
          }
      const MPI_Comm      communicator = triangulation.get_communicator();
      std::vector<double> all(local.size());
      if (Utilities::MPI::n_mpi_processes(communicator) > 1)
        Utilities::MPI::sum(local, communicator, all);
      else
        all.swap(local);
      CellStrains<dim> result;
      result.sigma_h.resize(n_cells);
      result.admissible_strain.resize(n_cells);
      for (unsigned int index = 0; index < n_cells; ++index)
        for (unsigned int e = 0; e < n_entries; ++e)
          {
            const auto entry =
              SymmetricTensor<2, dim>::unrolled_to_component_indices(e);
            result.sigma_h[index][entry] = all[(2 * index) * n_entries + e];
            result.admissible_strain[index][entry] =
              all[(2 * index + 1) * n_entries + e];
          }
      return result;
    }

    /// Sum @p values over the ranks, in place (the callers give every entry
    /// at most two nonzero contributions, whose sum does not depend on
    /// their order: the result is the same on any number of ranks).
    void
    sum_over_ranks(std::vector<double> &values, const MPI_Comm communicator)
    {
      if (Utilities::MPI::n_mpi_processes(communicator) == 1)
        return;
      std::vector<double> sums(values.size());
      Utilities::MPI::sum(values, communicator, sums);
      values.swap(sums);
    }

    /**
     * The Neumann problem of one element: stiffness K (Cholesky factor),
     * the work L of the densities (n x n_element_values, signs included),
     * of the body force l_f and of K eps(U^), a_U.
     */
    template <int dim>
    struct ElementSystem
    {
      /// The Cholesky factor of K (SmallMatrices::cholesky()).
      FullMatrix<double> factor;
      /// L
      FullMatrix<double> load;
      /// l_f
      Vector<double> body;
      /// a_U: int K eps(U^) : eps(v_j)
      Vector<double> admissible;
    };

    /// The rules of the element problems (degree 3 or 4: exact for the
    /// stiffness and the work of the linear densities).
    template <int dim>
    struct Rules
    {
      explicit Rules(const unsigned int degree)
        : cell(degree)
        , face(face_rule(3))
      {
        reference_face = 0.;
        for (unsigned int q = 0; q < face.size(); ++q)
          reference_face += face.weight(q);
      }

      static Quadrature<dim - 1>
      face_rule(const unsigned int n_points)
      {
        if constexpr (dim == 2)
          return QGauss<dim - 1>(n_points);
        else
          return QGaussSimplex<dim - 1>(n_points);
      }

      /// The point on face @p corners of reference coordinates @p eta and
      /// the values of the corners' hats there.
      static Point<dim>
      face_point(const std::array<Point<dim>, dim> &corners,
                 const Point<dim - 1>              &eta,
                 std::array<double, dim>           &hats)
      {
        hats[0] = 1.;
        for (unsigned int k = 1; k < dim; ++k)
          {
            hats[k] = eta[k - 1];
            hats[0] -= eta[k - 1];
          }
        Point<dim> p;
        for (unsigned int k = 0; k < dim; ++k)
          p += hats[k] * corners[k];
        return p;
      }

      /// On the cell: exact to degree 2 degree - 1.
      QGaussSimplex<dim> cell;
      /// On a face: exact to degree 5.
      Quadrature<dim - 1> face;
      /// The sum of the face rule's weights (the reference face's measure).
      double reference_face;
    };

    /// The element problem of @p cell (K, L, l_f, a_U for the admissible
    /// stress K eps(U^) = @p admissible_stress).
    template <int dim>
    ElementSystem<dim>
    element_system(const SimplexMesh<dim>        &mesh,
                   const CellGeometry<dim>       &geometry,
                   const unsigned int             cell,
                   const ElementSpace<dim>       &space,
                   const Rules<dim>              &rules,
                   const EquilibrationInput<dim> &input,
                   const SymmetricTensor<2, dim> &admissible_stress)
    {
      const unsigned int n = space.size();
      ElementSystem<dim> system;
      FullMatrix<double> stiffness(n, n);
      system.load.reinit(n, n_element_values<dim>);
      system.body.reinit(n);
      system.admissible.reinit(n);

      std::vector<Tensor<1, dim>>          values;
      std::vector<SymmetricTensor<2, dim>> strains, stresses(n);
      std::vector<Point<dim>>              points(rules.cell.size());
      for (unsigned int q = 0; q < rules.cell.size(); ++q)
        points[q] = geometry.point(rules.cell.point(q));
      std::vector<Vector<double>> body_force(points.size(),
                                             Vector<double>(dim));
      if (input.boundary_conditions.body_force &&
          !input.boundary_conditions.body_force_zero)
        input.boundary_conditions.body_force->vector_value_list(points,
                                                                body_force);
      for (unsigned int q = 0; q < rules.cell.size(); ++q)
        {
          const double JxW = rules.cell.weight(q) * geometry.determinant;
          space.evaluate(
            points[q], geometry.centre, geometry.size, values, strains);
          for (unsigned int j = 0; j < n; ++j)
            stresses[j] = input.material.stress(strains[j]);
          for (unsigned int j = 0; j < n; ++j)
            {
              for (unsigned int k = 0; k <= j; ++k)
                stiffness(j, k) += stresses[j] * strains[k] * JxW;
              system.admissible[j] += admissible_stress * strains[j] * JxW;
              for (unsigned int c = 0; c < dim; ++c)
                system.body[j] += body_force[q][c] * values[j][c] * JxW;
            }
        }
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int k = 0; k < j; ++k)
          stiffness(k, j) = stiffness(j, k);

      for (unsigned int f = 0; f <= dim; ++f)
        {
          const unsigned int          face = mesh.cell_faces[cell][f];
          const double                sign = mesh.sign(face, cell);
          std::array<Point<dim>, dim> corners;
          for (unsigned int k = 0; k < dim; ++k)
            corners[k] = mesh.vertices[mesh.face_vertices[face][k]];
          const double scale = mesh.face_measure[face] / rules.reference_face;
          std::array<double, dim> hats;
          for (unsigned int q = 0; q < rules.face.size(); ++q)
            {
              const Point<dim> x =
                Rules<dim>::face_point(corners, rules.face.point(q), hats);
              space.evaluate(
                x, geometry.centre, geometry.size, values, strains);
              const double JxW = rules.face.weight(q) * scale * sign;
              for (unsigned int j = 0; j < n; ++j)
                for (unsigned int k = 0; k < dim; ++k)
                  for (unsigned int c = 0; c < dim; ++c)
                    system.load(j, (f * dim + k) * dim + c) +=
                      hats[k] * values[j][c] * JxW;
            }
        }
      system.factor = stiffness;
      AssertThrow(SmallMatrices::cholesky(system.factor, 1e-14),
                  ExcMessage("an element problem of the element "
                             "equilibration is singular (a degenerate cell?)"));
      return system;
    }

    /// The element's densities (slot values) from the vector of all, into
    /// @p values (of size n_element_values: no allocation in the loops).
    template <int dim>
    void
    element_densities(const SimplexMesh<dim>    &mesh,
                      const unsigned int         cell,
                      const std::vector<double> &densities,
                      Vector<double>            &values)
    {
      for (unsigned int f = 0; f <= dim; ++f)
        for (unsigned int k = 0; k < dim; ++k)
          for (unsigned int c = 0; c < dim; ++c)
            values[(f * dim + k) * dim + c] =
              densities[slot<dim>(mesh.cell_faces[cell][f], k, c)];
    }

    /**
     * int_dE (s F) . r_k for the rigid motions r_k of the cell (rows) and the
     * element's density values (columns): the equilibrium of the element
     * with its densities is rows . d + int_E f . r_k = 0. Into @p work
     * (resized if needed: the loops reuse one).
     */
    template <int dim>
    void
    rigid_work(const SimplexMesh<dim>  &mesh,
               const CellGeometry<dim> &geometry,
               const unsigned int       cell,
               FullMatrix<double>      &work)
    {
      if (work.m() != n_rigid<dim> || work.n() != n_element_values<dim>)
        work.reinit(n_rigid<dim>, n_element_values<dim>);
      for (unsigned int f = 0; f <= dim; ++f)
        {
          const unsigned int face = mesh.cell_faces[cell][f];
          const double       sign = mesh.sign(face, cell);
          for (unsigned int r = 0; r < n_rigid<dim>; ++r)
            for (unsigned int c = 0; c < dim; ++c)
              {
                std::array<double, dim> corner_values;
                for (unsigned int m = 0; m < dim; ++m)
                  corner_values[m] = rigid_motion<dim>(
                    r,
                    mesh.vertices[mesh.face_vertices[face][m]],
                    geometry.centre,
                    geometry.size,
                    c);
                for (unsigned int k = 0; k < dim; ++k)
                  work(r, (f * dim + k) * dim + c) =
                    sign * hat_times_linear<dim>(mesh.face_measure[face],
                                                 k,
                                                 corner_values);
              }
        }
    }
    /// What the steps read: the input, the mesh, sigma_h and eps(U^), the
    /// rules and space of the element problems, the free components.
    template <int dim>
    struct Context
    {
      Context(const EquilibrationInput<dim>      &input,
              const LA::Vector                   &admissible_displacement,
              const SimplexEquilibrationSettings &settings)
        : input(input)
        , settings(settings)
        , triangulation(input.dof_handler.get_triangulation())
        , communicator(triangulation.get_communicator())
        , rank(Utilities::MPI::this_mpi_process(communicator))
        , mesh(triangulation)
        , strains(cell_strains(input, admissible_displacement))
        , rules(settings.degree)
        , space(settings.degree)
        , n_cells(triangulation.n_active_cells())
        , n_faces(mesh.face_cells.size())
        , n_slots(n_faces * dim * dim)
        , free(n_faces)
      {}

      const EquilibrationInput<dim>      &input;
      const SimplexEquilibrationSettings &settings;
      const Triangulation<dim>           &triangulation;
      const MPI_Comm                      communicator;
      /// This rank.
      const unsigned int      rank;
      const SimplexMesh<dim>  mesh;
      const CellStrains<dim>  strains;
      const Rules<dim>        rules;
      const ElementSpace<dim> space;
      /// Active cells, faces, density values (slot()).
      const unsigned int n_cells, n_faces, n_slots;
      /// By face: the components its densities may change (interior faces:
      /// all; boundary faces: the Dirichlet ones), set by data_densities().
      std::vector<std::array<bool, dim>> free;
    };

    /**
     * The element problems of the needed cells as quadratic functions of
     * their densities d: ||sigma^_E(d) -/+ K eps(U^)||^2_E = d^T H d +
     * 2 g-/+^T d + c-/+. Stored contiguously for the needed cells only, H by
     * its lower triangle: the conjugate gradients stream the Hessians once
     * per iteration, so their memory is their time. Each cell is set once,
     * from any thread.
     */
    template <int dim>
    class ElementQuadratics
    {
    public:
      /// The values per element.
      static constexpr unsigned int n = n_element_values<dim>;

      /// Room for the cells flagged in @p needed (by active cell index).
      explicit ElementQuadratics(const std::vector<bool> &needed)
        : position(needed.size(), invalid)
      {
        unsigned int count = 0;
        for (unsigned int cell = 0; cell < needed.size(); ++cell)
          if (needed[cell])
            position[cell] = count++;
        hessians.resize(std::size_t(count) * packed);
        gradients.resize(std::size_t(count) * n);
        sum_gradients.resize(std::size_t(count) * n);
        constants.resize(count);
        sum_constants.resize(count);
      }

      /// The quadratic of @p cell: H = @p hessian (symmetrised), g-/+ and
      /// c-/+.
      /// (@p hessian row-major n x n, the gradients n entries each: no
      /// container per cell)
      void
      set(const unsigned int cell,
          const double      *hessian,
          const double      *gradient,
          const double      *sum_gradient,
          const double       constant,
          const double       sum_constant)
      {
        const std::size_t k      = position[cell];
        double *const     values = &hessians[k * packed];
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j <= i; ++j)
            values[i * (i + 1) / 2 + j] =
              0.5 * (hessian[i * n + j] + hessian[j * n + i]);
        std::copy(gradient, gradient + n, &gradients[k * n]);
        std::copy(sum_gradient, sum_gradient + n, &sum_gradients[k * n]);
        constants[k]     = constant;
        sum_constants[k] = sum_constant;
      }

      /// The lower triangle of H of @p cell, (i, j <= i) at i (i + 1) / 2 + j.
      const double *
      packed_hessian(const unsigned int cell) const
      {
        return &hessians[std::size_t(position[cell]) * packed];
      }

      /// @p y = g- + H @p x (with @p with_gradient), or H @p x, of @p cell
      /// (n entries each).
      void
      product(const unsigned int cell,
              const double      *x,
              const bool         with_gradient,
              double            *y) const
      {
        const std::size_t k = position[cell];
        if (with_gradient)
          std::copy(&gradients[k * n], &gradients[k * n] + n, y);
        else
          std::fill(y, y + n, 0.);
        const double *values = &hessians[k * packed];
        for (unsigned int i = 0; i < n; ++i)
          {
            const double *row = &values[i * (i + 1) / 2];
            double        sum = 0.;
            for (unsigned int j = 0; j < i; ++j)
              {
                sum += row[j] * x[j];
                y[j] += row[j] * x[i];
              }
            y[i] += sum + row[i] * x[i];
          }
      }

      /// d^T H d + 2 g-/+^T d + c-/+ of @p cell at @p d (g+ and c+ with
      /// @p sum), at least 0: round-off can make a vanishing error negative.
      double
      value(const unsigned int    cell,
            const Vector<double> &d,
            const bool            sum) const
      {
        const std::size_t     k = position[cell];
        std::array<double, n> hd;
        product(cell, d.data(), false, hd.data());
        const double *g = sum ? &sum_gradients[k * n] : &gradients[k * n];
        double        quadratic = 0., linear = 0.;
        for (unsigned int i = 0; i < n; ++i)
          {
            quadratic += hd[i] * d[i];
            linear += g[i] * d[i];
          }
        return std::max(quadratic + 2. * linear +
                          (sum ? sum_constants[k] : constants[k]),
                        0.);
      }

    private:
      /// The entries of a lower triangle.
      static constexpr unsigned int packed = n * (n + 1) / 2;
      /// Each cell's place in the arrays (invalid: not needed).
      std::vector<unsigned int> position;
      /// H, row i of a cell's triangle holding (i, 0..i) at i (i + 1) / 2.
      std::vector<double> hessians;
      /// g-, g+, c-, c+.
      std::vector<double> gradients, sum_gradients, constants, sum_constants;
    };



    /**
     * Which components of each face are free (interior faces; the Dirichlet
     * components of boundary faces), in context.free, and the densities of
     * the others, returned with zero at the free ones: F_d (its L2
     * projection on the linear functions) and R^.
     */
    template <int dim>
    std::vector<double>
    data_densities(Context<dim> &context)
    {
      const auto         &input   = context.input;
      const auto         &bc      = input.boundary_conditions;
      const auto         &contact = input.contact_boundary;
      const auto         &mesh    = context.mesh;
      const auto         &rules   = context.rules;
      const auto          n_faces = context.n_faces;
      const auto          n_slots = context.n_slots;
      auto               &free    = context.free;
      std::vector<double> densities(n_slots, 0.);
      for (unsigned int face = 0; face < n_faces; ++face)
        {
          const types::boundary_id id = mesh.face_boundary[face];
          if (id == numbers::internal_face_boundary_id)
            {
              free[face].fill(true);
              continue;
            }
          const ComponentMask mask = bc.dirichlet_mask(id);
          for (unsigned int c = 0; c < dim; ++c)
            free[face][c] = mask.n_selected_components(dim) > 0 && mask[c];
          std::array<Point<dim>, dim> corners;
          for (unsigned int k = 0; k < dim; ++k)
            corners[k] = mesh.vertices[mesh.face_vertices[face][k]];
          const double measure = mesh.face_measure[face];
          if (bc.has_traction(id))
            {
              std::vector<Point<dim>> points(rules.face.size());
              std::vector<double>     hats(rules.face.size() * dim);
              std::array<double, dim> corner_hats;
              for (unsigned int q = 0; q < rules.face.size(); ++q)
                {
                  points[q] = Rules<dim>::face_point(corners,
                                                     rules.face.point(q),
                                                     corner_hats);
                  for (unsigned int k = 0; k < dim; ++k)
                    hats[q * dim + k] = corner_hats[k];
                }
              std::vector<Vector<double>> traction;
              bc.traction_values(id, points, traction);
              // projections b_k = int F_d phi_k, then the linear density
              // of the same projections: M^-1 b with M = |G| (I + J) /
              // (dim (dim + 1)), M^-1 = dim (dim + 1) (I - J / (dim + 1)) /
              // |G|
              for (unsigned int c = 0; c < dim; ++c)
                {
                  std::array<double, dim> projection{};
                  for (unsigned int q = 0; q < rules.face.size(); ++q)
                    for (unsigned int k = 0; k < dim; ++k)
                      projection[k] += traction[q][c] * hats[q * dim + k] *
                                       rules.face.weight(q) * measure /
                                       rules.reference_face;
                  double sum = 0.;
                  for (unsigned int k = 0; k < dim; ++k)
                    sum += projection[k];
                  for (unsigned int k = 0; k < dim; ++k)
                    densities[slot<dim>(face, k, c)] +=
                      dim * (dim + 1.) * (projection[k] - sum / (dim + 1.)) /
                      measure;
                }
            }
          if (contact.boundary_ids().count(id) != 0)
            for (unsigned int k = 0; k < dim; ++k)
              {
                const Tensor<1, dim> reaction = input.contact_reaction(
                  contact.node_index(mesh.face_vertices[face][k]));
                for (unsigned int c = 0; c < dim; ++c)
                  densities[slot<dim>(face, k, c)] += reaction[c];
              }
          for (unsigned int c = 0; c < dim; ++c)
            if (free[face][c])
              for (unsigned int k = 0; k < dim; ++k)
                densities[slot<dim>(face, k, c)] = 0.;
        }

      return densities;
    }



    /**
     * The classical densities at the free components of @p densities: per
     * vertex i and component c, the projections b_G(i) = int_G F phi_i of
     * the faces through i satisfy the prolongation condition sum_G s(E, G)
     * b_G(i) = Q_E = int_E sigma_h : eps(phi_i e_c) - int_E f_c phi_i on
     * every cell E around i; the free ones are the least squares solution
     * towards the averaged FE tractions. Returns the largest defect of the
     * condition relative to its largest term.
     */
    template <int dim>
    double
    classical_densities(const Context<dim>  &context,
                        std::vector<double> &densities)
    {
      const auto &triangulation = context.triangulation;
      const auto &bc            = context.input.boundary_conditions;
      const auto &mesh          = context.mesh;
      const auto &strains       = context.strains;
      const auto &rules         = context.rules;
      const auto &free          = context.free;
      const auto  communicator  = context.communicator;
      const auto  n_faces       = context.n_faces;
      const auto  n_slots       = context.n_slots;
      double      prolongation  = 0.;

      // the patches this rank computes: those of the vertices whose lowest
      // subdomain among their cells is this rank's
      std::vector<bool> computes(triangulation.n_vertices(), false);
      for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
        if (!mesh.cells_of_vertex[v].empty())
          {
            types::subdomain_id lowest = numbers::invalid_subdomain_id;
            for (const unsigned int cell : mesh.cells_of_vertex[v])
              lowest = std::min(lowest, mesh.subdomain[cell]);
            computes[v] = (lowest == context.rank);
          }

      std::vector<double> projections(n_slots, 0.);
      {
        // (the rule of the element problems: the element data are then in
        // equilibrium to round-off whatever f_d)
        const QGaussSimplex<dim> &quadrature = rules.cell;
        std::mutex                mutex;
        // (relative to the largest term of all patches)
        double largest_defect = 0., largest_scale = 0.;
        // (the work space of one thread's patches: reused, not allocated
        // per patch and component)
        struct Scratch
        {
          std::vector<unsigned int>            faces;
          std::vector<std::array<double, dim>> q_values, scale;
          std::vector<Point<dim>>              points;
          std::vector<Vector<double>>          force;
          FullMatrix<double>                   incidence, normal, factor;
          std::vector<Tensor<1, dim>>          average_traction;
          Vector<double>                       rhs, average, residual, lambda;
          std::vector<bool>                    is_free;
        };
        const auto classical_patch = [&](const unsigned int vertex,
                                         Scratch           &scratch) {
          const auto        &cells = mesh.cells_of_vertex[vertex];
          const unsigned int n     = cells.size();
          // the faces through the vertex, and Q_E for every component
          auto &faces    = scratch.faces;
          auto &q_values = scratch.q_values;
          auto &scale    = scratch.scale;
          faces.clear();
          q_values.resize(n);
          scale.resize(n);
          for (unsigned int e = 0; e < n; ++e)
            {
              const unsigned int      cell = cells[e];
              const CellGeometry<dim> geometry(mesh, cell);
              unsigned int            a = 0;
              while (mesh.cell_vertices[cell][a] != vertex)
                ++a;
              const Tensor<1, dim> traction =
                strains.sigma_h[cell] * geometry.grad_hat[a];
              for (unsigned int c = 0; c < dim; ++c)
                {
                  q_values[e][c] = traction[c] * geometry.measure;
                  scale[e][c]    = std::abs(q_values[e][c]);
                }
              // (a parsed zero costs a parser call per point: skipped)
              if (bc.body_force && !bc.body_force_zero)
                {
                  auto &points = scratch.points;
                  auto &force  = scratch.force;
                  points.resize(quadrature.size());
                  for (unsigned int q = 0; q < quadrature.size(); ++q)
                    points[q] = geometry.point(quadrature.point(q));
                  force.resize(points.size(), Vector<double>(dim));
                  bc.body_force->vector_value_list(points, force);
                  for (unsigned int q = 0; q < quadrature.size(); ++q)
                    {
                      // the hat of local vertex a at reference point xi
                      const Point<dim> &xi  = quadrature.point(q);
                      double            hat = 1.;
                      for (unsigned int d = 0; d < dim; ++d)
                        hat -= xi[d];
                      if (a > 0)
                        hat = xi[a - 1];
                      for (unsigned int c = 0; c < dim; ++c)
                        {
                          const double term = force[q][c] * hat *
                                              quadrature.weight(q) *
                                              geometry.determinant;
                          q_values[e][c] -= term;
                          scale[e][c] += std::abs(term);
                        }
                    }
                }
              for (unsigned int f = 0; f <= dim; ++f)
                {
                  const unsigned int face = mesh.cell_faces[cell][f];
                  if (mesh.corner(face, vertex) != invalid &&
                      std::find(faces.begin(), faces.end(), face) ==
                        faces.end())
                    faces.push_back(face);
                }
            }
          const unsigned int n_faces_here = faces.size();
          // A: s(E, G) for the faces of E through the vertex
          FullMatrix<double> &incidence = scratch.incidence;
          incidence.reinit(n, n_faces_here);
          for (unsigned int e = 0; e < n; ++e)
            for (unsigned int g = 0; g < n_faces_here; ++g)
              {
                const auto &fc = mesh.face_cells[faces[g]];
                if (fc[0] == cells[e] || fc[1] == cells[e])
                  incidence(e, g) = mesh.sign(faces[g], cells[e]);
              }
          // the averaged FE traction on each face through the vertex (on
          // its first cell; sigma_h n on a boundary face), for the free
          // components
          auto &average_traction = scratch.average_traction;
          average_traction.resize(n_faces_here);
          for (unsigned int g = 0; g < n_faces_here; ++g)
            {
              const auto             &fc = mesh.face_cells[faces[g]];
              const CellGeometry<dim> first(mesh, fc[0]);
              unsigned int            f = 0;
              while (mesh.cell_faces[fc[0]][f] != faces[g])
                ++f;
              SymmetricTensor<2, dim> stress = strains.sigma_h[fc[0]];
              if (fc[1] != invalid)
                stress = 0.5 * (stress + strains.sigma_h[fc[1]]);
              average_traction[g] = stress * first.normal[f];
            }
          double defect = 0., defect_scale = 0.;
          for (unsigned int c = 0; c < dim; ++c)
            {
              // data faces to the right-hand side; the averaged FE tractions
              // of the free ones
              Vector<double> &rhs = scratch.rhs, &average = scratch.average;
              rhs.reinit(n);
              average.reinit(n_faces_here);
              auto &is_free = scratch.is_free;
              is_free.assign(n_faces_here, false);
              bool free_boundary = false;
              for (unsigned int g = 0; g < n_faces_here; ++g)
                {
                  const unsigned int face = faces[g];
                  const unsigned int k    = mesh.corner(face, vertex);
                  is_free[g]              = free[face][c];
                  if (is_free[g])
                    {
                      if (mesh.face_cells[face][1] == invalid)
                        free_boundary = true;
                      average[g] =
                        average_traction[g][c] * mesh.face_measure[face] / dim;
                    }
                  else
                    {
                      std::array<double, dim> corner_values;
                      for (unsigned int m = 0; m < dim; ++m)
                        corner_values[m] = densities[slot<dim>(face, m, c)];
                      const double data =
                        hat_times_linear<dim>(mesh.face_measure[face],
                                              k,
                                              corner_values);
                      projections[slot<dim>(face, k, c)] = data;
                      for (unsigned int e = 0; e < n; ++e)
                        if (incidence(e, g) != 0.)
                          {
                            rhs[e] -= incidence(e, g) * data;
                            scale[e][c] += std::abs(data);
                          }
                    }
                }
              for (unsigned int e = 0; e < n; ++e)
                rhs[e] += q_values[e][c];
              // b = average + A^T lambda, A A^T lambda = rhs - A average
              Vector<double> &residual   = scratch.residual;
              residual                   = rhs;
              FullMatrix<double> &normal = scratch.normal;
              normal.reinit(n, n);
              for (unsigned int e = 0; e < n; ++e)
                {
                  for (unsigned int g = 0; g < n_faces_here; ++g)
                    if (is_free[g])
                      residual[e] -= incidence(e, g) * average[g];
                  for (unsigned int l = 0; l < n; ++l)
                    for (unsigned int g = 0; g < n_faces_here; ++g)
                      if (is_free[g])
                        normal(e, l) += incidence(e, g) * incidence(l, g);
                }
              // without a free boundary face the sum of the rows vanishes
              // (and so does that of the right-hand side: R(phi_i e_c) = 0),
              // cells without a free face have empty rows: make it definite
              // without changing A^T lambda
              for (unsigned int e = 0; e < n; ++e)
                {
                  if (normal(e, e) == 0.)
                    normal(e, e) = 1.;
                  if (!free_boundary)
                    for (unsigned int l = 0; l < n; ++l)
                      normal(e, l) += 1.;
                }
              FullMatrix<double> &factor = scratch.factor;
              factor                     = normal;
              Vector<double> &lambda     = scratch.lambda;
              lambda                     = residual;
              if (SmallMatrices::cholesky(factor, 1e-13))
                SmallMatrices::cholesky_solve(factor, lambda);
              else
                {
                  // (a patch of unusual topology) least squares via the
                  // pseudo-inverse
                  LAPACKFullMatrix<double> pseudo(n, n);
                  pseudo = normal;
                  pseudo.compute_inverse_svd(1e-12);
                  pseudo.vmult(lambda, residual);
                }
              for (unsigned int g = 0; g < n_faces_here; ++g)
                if (is_free[g])
                  {
                    double value = average[g];
                    for (unsigned int e = 0; e < n; ++e)
                      value += incidence(e, g) * lambda[e];
                    projections[slot<dim>(
                      faces[g], mesh.corner(faces[g], vertex), c)] = value;
                  }
              // the prolongation condition's defect
              for (unsigned int e = 0; e < n; ++e)
                {
                  double value = rhs[e];
                  for (unsigned int g = 0; g < n_faces_here; ++g)
                    if (is_free[g])
                      value -= incidence(e, g) *
                               projections[slot<dim>(
                                 faces[g], mesh.corner(faces[g], vertex), c)];
                  defect       = std::max(defect, std::abs(value));
                  defect_scale = std::max(defect_scale, scale[e][c]);
                }
            }
          std::lock_guard<std::mutex> lock(mutex);
          largest_defect = std::max(largest_defect, defect);
          largest_scale  = std::max(largest_scale, defect_scale);
        };
        parallel::apply_to_subranges(
          0u,
          triangulation.n_vertices(),
          [&](const unsigned int begin, const unsigned int end) {
            Scratch scratch;
            for (unsigned int v = begin; v < end; ++v)
              if (computes[v])
                classical_patch(v, scratch);
          },
          32);
        sum_over_ranks(projections, communicator);
        largest_scale = Utilities::MPI::max(largest_scale, communicator);
        prolongation =
          Utilities::MPI::max(largest_defect, communicator) /
          std::max(largest_scale, std::numeric_limits<double>::min());
      }
      // the densities of the free components from their projections: M^-1 b
      for (unsigned int face = 0; face < n_faces; ++face)
        for (unsigned int c = 0; c < dim; ++c)
          if (free[face][c])
            {
              double sum = 0.;
              for (unsigned int k = 0; k < dim; ++k)
                sum += projections[slot<dim>(face, k, c)];
              for (unsigned int k = 0; k < dim; ++k)
                densities[slot<dim>(face, k, c)] =
                  dim * (dim + 1.) *
                  (projections[slot<dim>(face, k, c)] - sum / (dim + 1.)) /
                  mesh.face_measure[face];
            }
      projections.clear();
      projections.shrink_to_fit();

      return prolongation;
    }



    /**
     * The element problems of the @p needed cells as quadratic functions of
     * the densities d_E of each: with w = K^-1 (L d + l_f),
     * ||K eps(w) -/+ K eps(U^)||^2_E = d^T H d + 2 g-/+^T d + c-/+,
     * H = L^T K^-1 L, g-/+ = L^T K^-1 (l_f -/+ a_U).
     */
    template <int dim>
    ElementQuadratics<dim>
    element_quadratics(const Context<dim>      &context,
                       const std::vector<bool> &needed)
    {
      const auto            &input   = context.input;
      const auto            &mesh    = context.mesh;
      const auto            &strains = context.strains;
      const auto            &rules   = context.rules;
      const auto            &space   = context.space;
      const auto             n_cells = context.n_cells;
      ElementQuadratics<dim> quadratics(needed);
      parallel::apply_to_subranges(
        0u,
        n_cells,
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int cell = begin; cell < end; ++cell)
            if (needed[cell])
              {
                const CellGeometry<dim>  geometry(mesh, cell);
                const ElementSystem<dim> system =
                  element_system(mesh,
                                 geometry,
                                 cell,
                                 space,
                                 rules,
                                 input,
                                 input.material.stress(
                                   strains.admissible_strain[cell]));
                const unsigned int n = space.size();
                FullMatrix<double> solved(n, n_element_values<dim>);
                Vector<double>     column(n);
                for (unsigned int a = 0; a < n_element_values<dim>; ++a)
                  {
                    for (unsigned int j = 0; j < n; ++j)
                      column[j] = system.load(j, a);
                    SmallMatrices::cholesky_solve(system.factor, column);
                    for (unsigned int j = 0; j < n; ++j)
                      solved(j, a) = column[j];
                  }
                FullMatrix<double> full(n_element_values<dim>,
                                        n_element_values<dim>);
                system.load.Tmmult(full, solved);
                Vector<double> data(system.body);
                data -= system.admissible;
                Vector<double> gradient(n_element_values<dim>),
                  sum_gradient(n_element_values<dim>);
                solved.Tvmult(gradient, data);
                data.add(2., system.admissible);
                solved.Tvmult(sum_gradient, data);
                // l_f^T w_f -/+ 2 a_U^T w_f + |E| K eps(U^) : eps(U^)
                Vector<double> body_solution(system.body);
                SmallMatrices::cholesky_solve(system.factor, body_solution);
                const SymmetricTensor<2, dim> &strain =
                  strains.admissible_strain[cell];
                const double base =
                  (system.body * body_solution) +
                  geometry.measure * (input.material.stress(strain) * strain);
                quadratics.set(cell,
                               &full(0, 0),
                               gradient.begin(),
                               sum_gradient.begin(),
                               base - 2. * (system.admissible * body_solution),
                               base + 2. * (system.admissible * body_solution));
              }
        },
        16);


      return quadratics;
    }



    /**
     * One cell's Johnson-Krizek-Mercier field in the density slots of its
     * faces: where each slot's value goes among the element's tractions
     * (JohnsonKrizekMercierElement::traction_index()) and with which sign
     * (the densities are the tractions on the face's first cell), and the
     * body force f~ of the split, constant on each sub-simplex, with the
     * resultant and moment that f_d has in the rule of the element
     * problems (the rule of the equilibrium of the densities).
     */
    template <int dim>
    struct EquilibratedCell
    {
      using Element = JohnsonKrizekMercierElement<dim>;

      EquilibratedCell(const Context<dim> &context, const unsigned int cell)
      {
        const auto                     &mesh = context.mesh;
        std::array<Point<dim>, dim + 1> vertices;
        for (unsigned int v = 0; v <= dim; ++v)
          vertices[v] = mesh.vertices[mesh.cell_vertices[cell][v]];
        geometry = Element::geometry(vertices);
        for (unsigned int f = 0; f <= dim; ++f)
          {
            const unsigned int face     = mesh.cell_faces[cell][f];
            const unsigned int opposite = mesh.opposite_vertex(cell, f);
            for (unsigned int k = 0; k < dim; ++k)
              {
                unsigned int j = 0;
                while (mesh.cell_vertices[cell][j] !=
                       mesh.face_vertices[face][k])
                  ++j;
                for (unsigned int c = 0; c < dim; ++c)
                  {
                    const unsigned int a = slot<dim>(f, k, c);
                    traction_index[a] = Element::traction_index(opposite, j, c);
                    sign[a]           = mesh.sign(face, cell);
                  }
              }
          }

        const auto &force_function =
          context.input.boundary_conditions.body_force;
        if (!force_function ||
            context.input.boundary_conditions.body_force_zero)
          return;
        const auto             &rule = context.rules.cell;
        std::vector<Point<dim>> points(rule.size());
        for (unsigned int q = 0; q < rule.size(); ++q)
          points[q] = vertices[0] + geometry.jacobian * rule.point(q);
        std::vector<Vector<double>> force(points.size(), Vector<double>(dim));
        force_function->vector_value_list(points, force);
        Tensor<1, dim>                            resultant;
        std::array<double, (dim * (dim - 1)) / 2> moments{};
        for (unsigned int q = 0; q < rule.size(); ++q)
          {
            Tensor<1, dim> f;
            for (unsigned int c = 0; c < dim; ++c)
              f[c] = force[q][c];
            const double weight = rule.weight(q) * geometry.determinant;
            resultant += weight * f;
            for (unsigned int k = 0; k < moments.size(); ++k)
              moments[k] +=
                weight *
                (f * Element::rotation(k, points[q] - geometry.centroid));
          }
        body_force = Element::balanced_body_force(geometry, resultant, moments);
      }

      /// The element's tractions from its slot values @p densities.
      typename Element::Traction
      traction(const Vector<double> &densities) const
      {
        typename Element::Traction result;
        for (unsigned int a = 0; a < n_element_values<dim>; ++a)
          result[traction_index[a] / dim][traction_index[a] % dim] =
            sign[a] * densities[a];
        return result;
      }

      typename Element::Geometry geometry;
      /// By slot: the traction value and the sign.
      std::array<unsigned int, n_element_values<dim>> traction_index;
      std::array<double, n_element_values<dim>>       sign;
      /// f~ (zero without body force).
      typename Element::BodyForce body_force;
    };



    /**
     * The Johnson-Krizek-Mercier fields of the @p needed cells as quadratic
     * functions of their densities d: ||sigma^(d) -/+ K eps(U^)||^2_E =
     * d^T H d + 2 g-/+^T d + c-/+ (JohnsonKrizekMercierElement::hessian()
     * and linear_part() in the element's tractions, which are the slot
     * values up to order and sign).
     */
    template <int dim>
    ElementQuadratics<dim>
    equilibrated_quadratics(const Context<dim>                     &context,
                            const std::vector<bool>                &needed,
                            const JohnsonKrizekMercierElement<dim> &element)
    {
      constexpr unsigned int n = n_element_values<dim>;
      ElementQuadratics<dim> quadratics(needed);
      parallel::apply_to_subranges(
        0u,
        context.n_cells,
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int cell = begin; cell < end; ++cell)
            if (needed[cell])
              {
                const EquilibratedCell<dim> data(context, cell);
                const auto hessian = element.hessian(data.geometry);
                const SymmetricTensor<2, dim> admissible =
                  context.input.material.stress(
                    context.strains.admissible_strain[cell]);
                const auto difference = element.linear_part(data.geometry,
                                                            data.body_force,
                                                            admissible);
                const auto sum        = element.linear_part(data.geometry,
                                                     data.body_force,
                                                     -admissible);
                std::array<double, n * n> full;
                std::array<double, n>     gradient, sum_gradient;
                for (unsigned int a = 0; a < n; ++a)
                  {
                    const unsigned int t = data.traction_index[a];
                    for (unsigned int b = 0; b < n; ++b)
                      full[a * n + b] = data.sign[a] * data.sign[b] *
                                        hessian[t * n + data.traction_index[b]];
                    gradient[a]     = data.sign[a] * difference.first[t];
                    sum_gradient[a] = data.sign[a] * sum.first[t];
                  }
                quadratics.set(cell,
                               full.data(),
                               gradient.data(),
                               sum_gradient.data(),
                               difference.second,
                               sum.second);
              }
        },
        16);
      return quadratics;
    }



    /**
     * The enhancement of @p densities (Pled, Chamoin and Ladeveze 2012):
     * the conjugate gradient method in the density changes that keep every
     * element in equilibrium, preconditioned by the patches of the
     * @p hinges. Returns the decrease of J in each iteration.
     */
    template <int dim>
    std::vector<double>
    enhance_densities(const Context<dim>           &context,
                      const Hinges<dim>            &hinges,
                      const ElementQuadratics<dim> &quadratics,
                      std::vector<double>          &densities)
    {
      const auto         &settings     = context.settings;
      const auto         &mesh         = context.mesh;
      const auto         &free         = context.free;
      const auto          communicator = context.communicator;
      const auto          n_cells      = context.n_cells;
      const auto          n_faces      = context.n_faces;
      const auto          n_slots      = context.n_slots;
      std::vector<double> measure;
      // the patch preconditioner: for each computed hinge, the free slots
      // of the faces through it, its position among the hinges of each
      // (its contributions are summed in that order: the same on any
      // number of ranks and threads) and B with B B^T = Z (Z^T H Z)^-1
      // Z^T, Z a basis of the changes of these slots keeping every element
      // of the patch in equilibrium, H the Hessian of J on them
      struct Patch
      {
        /// The density slots it changes.
        std::vector<unsigned int> slots;
        /// For each, its entry in the contributions (slot, hinge in face).
        std::vector<unsigned int> entries;
        /// B, row-major (in double precision: the corrections must keep
        /// every element in equilibrium to round-off).
        std::vector<double> correction;
        /// The columns of B: the dimension of the patch's changes.
        unsigned int n_changes = 0;
      };
      // the patches in blocks of consecutive computed hinges, each block's
      // data contiguous: the preconditioner streams them every iteration
      // (patches without changes are left out: they contribute nothing)
      struct PatchBlock
      {
        /// Per patch: its first slot (one past the last: the next one's),
        /// its first entry of B, the columns of B.
        std::vector<unsigned int> slot_start{0}, correction_start{0}, n_changes;
        /// Patch::slots, Patch::entries, Patch::correction, concatenated.
        std::vector<unsigned int> slots, entries;
        std::vector<double>       correction;

        void
        append(const Patch &patch)
        {
          if (patch.n_changes == 0)
            return;
          slots.insert(slots.end(), patch.slots.begin(), patch.slots.end());
          entries.insert(entries.end(),
                         patch.entries.begin(),
                         patch.entries.end());
          correction.insert(correction.end(),
                            patch.correction.begin(),
                            patch.correction.end());
          slot_start.push_back(slots.size());
          correction_start.push_back(correction.size());
          n_changes.push_back(patch.n_changes);
        }
      };
      // (the work space of one thread's patches)
      struct Scratch
      {
        std::vector<std::array<int, n_element_values<dim>>> positions;
        FullMatrix<double> patch_hessian, constraints, work, hz, reduced;
      };
      const auto describe_patch =
        [&](const unsigned int hinge, Scratch &scratch, Patch &patch) {
          patch.slots.clear();
          patch.entries.clear();
          patch.n_changes       = 0;
          const auto &cells     = hinges.cells[hinge];
          auto       &positions = scratch.positions;
          positions.resize(cells.size());
          for (unsigned int e = 0; e < cells.size(); ++e)
            for (unsigned int f = 0; f <= dim; ++f)
              {
                const unsigned int face    = mesh.cell_faces[cells[e]][f];
                const bool         through = hinges.in_face(hinge, face);
                for (unsigned int k = 0; k < dim; ++k)
                  for (unsigned int c = 0; c < dim; ++c)
                    {
                      int &position = positions[e][(f * dim + k) * dim + c];
                      position      = -1;
                      if (!through || !free[face][c])
                        continue;
                      const unsigned int s = slot<dim>(face, k, c);
                      const auto         it =
                        std::find(patch.slots.begin(), patch.slots.end(), s);
                      position = it - patch.slots.begin();
                      if (it == patch.slots.end())
                        {
                          patch.slots.push_back(s);
                          patch.entries.push_back(
                            s * dim + hinges.position_in_face(hinge, face));
                        }
                    }
              }
          const unsigned int n_free = patch.slots.size();
          if (n_free == 0)
            return;
          FullMatrix<double> &patch_hessian = scratch.patch_hessian;
          FullMatrix<double> &constraints   = scratch.constraints;
          FullMatrix<double> &work          = scratch.work;
          patch_hessian.reinit(n_free, n_free);
          constraints.reinit(n_rigid<dim> * cells.size(), n_free);
          for (unsigned int e = 0; e < cells.size(); ++e)
            {
              const unsigned int      cell = cells[e];
              const CellGeometry<dim> geometry(mesh, cell);
              rigid_work(mesh, geometry, cell, work);
              // (each packed entry read once, for both of its places: the
              // slots of a cell are distinct, so every entry of the patch's
              // Hessian receives the same terms in the same order)
              const double *hessian = quadratics.packed_hessian(cell);
              for (unsigned int a = 0; a < n_element_values<dim>; ++a)
                {
                  const int i = positions[e][a];
                  if (i < 0)
                    continue;
                  const double *row = hessian + a * (a + 1) / 2;
                  for (unsigned int b = 0; b < a; ++b)
                    if (positions[e][b] >= 0)
                      {
                        patch_hessian(i, positions[e][b]) += row[b];
                        patch_hessian(positions[e][b], i) += row[b];
                      }
                  patch_hessian(i, i) += row[a];
                  for (unsigned int r = 0; r < n_rigid<dim>; ++r)
                    constraints(e * n_rigid<dim> + r, i) = work(r, a);
                }
            }
          const FullMatrix<double> kernel =
            SmallMatrices::kernel_basis(constraints);
          const unsigned int m = kernel.n();
          if (m == 0)
            return;
          FullMatrix<double> &hz = scratch.hz, &reduced = scratch.reduced;
          hz.reinit(n_free, m);
          reduced.reinit(m, m);
          patch_hessian.mmult(hz, kernel);
          kernel.Tmmult(reduced, hz);
          double largest = 0.;
          for (unsigned int i = 0; i < m; ++i)
            largest = std::max(largest, reduced(i, i));
          for (unsigned int i = 0; i < m; ++i)
            reduced(i, i) += 1e-12 * largest;
          if (!SmallMatrices::cholesky(reduced, 1e-14))
            return;
          // B = Z L^-T: B B^T = Z (L L^T)^-1 Z^T, row by row
          patch.n_changes = m;
          patch.correction.resize(n_free * m);
          for (unsigned int i = 0; i < n_free; ++i)
            {
              double *const row = &patch.correction[i * m];
              for (unsigned int j = 0; j < m; ++j)
                {
                  double value = kernel(i, j);
                  for (unsigned int k = 0; k < j; ++k)
                    value -= row[k] * reduced(j, k);
                  row[j] = value / reduced(j, j);
                }
            }
        };
      std::vector<unsigned int> computed;
      for (unsigned int h = 0; h < hinges.size(); ++h)
        if (hinges.computes[h])
          computed.push_back(h);
      constexpr unsigned int  patches_per_block = 256;
      std::vector<PatchBlock> blocks((computed.size() + patches_per_block - 1) /
                                     patches_per_block);
      parallel::apply_to_subranges(
        0u,
        static_cast<unsigned int>(blocks.size()),
        [&](const unsigned int begin, const unsigned int end) {
          Scratch scratch;
          Patch   patch;
          for (unsigned int b = begin; b < end; ++b)
            for (unsigned int p = b * patches_per_block;
                 p < std::min<std::size_t>((b + 1) * patches_per_block,
                                           computed.size());
                 ++p)
              {
                describe_patch(computed[p], scratch, patch);
                blocks[b].append(patch);
              }
        },
        1);

      // (in blocks of a fixed size summed in order: the same sum on any
      // number of threads; the passes that fuse a dot product use the same
      // blocks, so they give the same sum)
      // sum_s term(s) for s < n: term may also write its slot's entry of a
      // vector, so that a pass fuses a dot product with the vector it makes
      const auto blocked_sum = [](const std::size_t n, const auto &term) {
        constexpr std::size_t block    = 4096;
        const std::size_t     n_blocks = (n + block - 1) / block;
        std::vector<double>   partial(n_blocks);
        parallel::apply_to_subranges(
          std::size_t(0),
          n_blocks,
          [&](const std::size_t begin, const std::size_t end) {
            for (std::size_t k = begin; k < end; ++k)
              {
                double sum = 0.;
                for (std::size_t i = k * block;
                     i < std::min(n, (k + 1) * block);
                     ++i)
                  sum += term(i);
                partial[k] = sum;
              }
          },
          4);
        double sum = 0.;
        for (const double p : partial)
          sum += p;
        return sum;
      };
      const auto dot = [&](const std::vector<double> &a,
                           const std::vector<double> &b) {
        return blocked_sum(a.size(),
                           [&](const std::size_t i) { return a[i] * b[i]; });
      };

      // z = sum over the patches of B B^T r (each entry of the
      // contributions has one source: the sum is rank independent)
      std::vector<double> contributions(n_slots * dim);
      // (on one rank every call writes the same entries and the others stay
      // zero: no need to clear them)
      const bool several_ranks =
        Utilities::MPI::n_mpi_processes(communicator) > 1;
      const auto precondition = [&](const std::vector<double> &r,
                                    std::vector<double>       &z) {
        if (several_ranks)
          std::fill(contributions.begin(), contributions.end(), 0.);
        parallel::apply_to_subranges(
          0u,
          static_cast<unsigned int>(blocks.size()),
          [&](const unsigned int begin, const unsigned int end) {
            std::vector<double> reduced;
            for (unsigned int b = begin; b < end; ++b)
              {
                const PatchBlock &block = blocks[b];
                for (unsigned int p = 0; p < block.n_changes.size(); ++p)
                  {
                    const unsigned int m      = block.n_changes[p];
                    const unsigned int first  = block.slot_start[p];
                    const unsigned int n_free = block.slot_start[p + 1] - first;
                    const unsigned int *slots = &block.slots[first];
                    const unsigned int *entries = &block.entries[first];
                    const double       *correction =
                      &block.correction[block.correction_start[p]];
                    // B (B^T r)
                    reduced.assign(m, 0.);
                    for (unsigned int i = 0; i < n_free; ++i)
                      {
                        const double  value = r[slots[i]];
                        const double *row   = correction + i * m;
                        for (unsigned int j = 0; j < m; ++j)
                          reduced[j] += row[j] * value;
                      }
                    for (unsigned int i = 0; i < n_free; ++i)
                      {
                        const double *row   = correction + i * m;
                        double        value = 0.;
                        for (unsigned int j = 0; j < m; ++j)
                          value += row[j] * reduced[j];
                        contributions[entries[i]] = value;
                      }
                  }
              }
          },
          1);
        sum_over_ranks(contributions, communicator);
        // z, and r . z summed as dot() sums
        return blocked_sum(n_slots, [&](const std::size_t s) {
          double value = 0.;
          for (unsigned int k = 0; k < dim; ++k)
            value += contributions[s * dim + k];
          z[s] = value;
          return r[s] * value;
        });
      };

      // y = H x (+ g): the sum of the owned cells' contributions, at
      // most two per slot (so the sum is rank independent too)
      std::vector<std::array<unsigned int, 2>> local_face(n_faces);
      for (unsigned int face = 0; face < n_faces; ++face)
        for (unsigned int side = 0; side < 2; ++side)
          {
            const unsigned int cell = mesh.face_cells[face][side];
            local_face[face][side]  = invalid;
            if (cell != invalid)
              for (unsigned int f = 0; f <= dim; ++f)
                if (mesh.cell_faces[cell][f] == face)
                  local_face[face][side] = f;
          }
      // (one contiguous block for the owned cells: each iteration writes
      // and reads all of it)
      constexpr unsigned int    n = n_element_values<dim>;
      std::vector<unsigned int> owned_position(n_cells, invalid);
      unsigned int              n_owned = 0;
      for (unsigned int cell = 0; cell < n_cells; ++cell)
        if (mesh.owned[cell])
          owned_position[cell] = n_owned++;
      std::vector<double> cell_products(std::size_t(n_owned) * n);
      const auto          multiply = [&](const std::vector<double> &x,
                                const bool                 with_gradient,
                                std::vector<double>       &y) {
        parallel::apply_to_subranges(
          0u,
          n_cells,
          [&](const unsigned int begin, const unsigned int end) {
            Vector<double> d(n);
            for (unsigned int cell = begin; cell < end; ++cell)
              if (mesh.owned[cell])
                {
                  element_densities(mesh, cell, x, d);
                  quadratics.product(
                    cell,
                    d.data(),
                    with_gradient,
                    &cell_products[std::size_t(owned_position[cell]) * n]);
                }
          },
          64);
        // y by slot, and on one rank x . y summed as dot() sums
        const double xy = blocked_sum(n_slots, [&](const std::size_t s) {
          const unsigned int face  = s / (dim * dim);
          const unsigned int k     = (s / dim) % dim;
          const unsigned int c     = s % dim;
          double             value = 0.;
          for (unsigned int side = 0; side < 2; ++side)
            {
              const unsigned int cell = mesh.face_cells[face][side];
              if (cell != invalid && mesh.owned[cell])
                value +=
                  cell_products[std::size_t(owned_position[cell]) * n +
                                (local_face[face][side] * dim + k) * dim + c];
            }
          y[s] = free[face][c] ? value : 0.;
          return x[s] * y[s];
        });
        if (!several_ranks)
          return xy;
        sum_over_ranks(y, communicator);
        return dot(x, y);
      };
      // preconditioned conjugate gradients in the changes that keep every
      // element in equilibrium (each preconditioned residual is a sum of
      // such changes, so is every direction): every iterate is admissible
      std::vector<double> residual(n_slots), z(n_slots), direction(n_slots),
        product(n_slots);
      multiply(densities, true, residual);
      for (double &r : residual)
        r = -r;
      double rz         = precondition(residual, z);
      direction         = z;
      double   decrease = 0.;
      Progress progress("estimate, enhanced densities", context.communicator);
      for (unsigned int iteration = 0;
           iteration < settings.max_iterations && rz > 0.;
           ++iteration)
        {
          progress.report([&]() {
            return "iteration " + std::to_string(iteration) + " of at most " +
                   std::to_string(settings.max_iterations);
          });
          const double curvature = multiply(direction, false, product);
          if (!(curvature > 0.))
            break;
          const double alpha = rz / curvature;
          // (densities and residual in one pass)
          parallel::apply_to_subranges(
            0u,
            n_slots,
            [&](const unsigned int begin, const unsigned int end) {
              for (unsigned int s = begin; s < end; ++s)
                {
                  densities[s] += alpha * direction[s];
                  residual[s] += -alpha * product[s];
                }
            },
            4096);
          const double step_decrease = 0.5 * alpha * rz;
          decrease += step_decrease;
          measure.push_back(step_decrease);
          // (a decrease at the level of round-off ends it whatever the
          // tolerance: beyond, the directions are noise)
          if (step_decrease <= std::max(settings.tolerance, 1e-13) * decrease)
            break;
          const double rz_new = precondition(residual, z);
          const double beta   = rz_new / rz;
          rz                  = rz_new;
          parallel::apply_to_subranges(
            0u,
            n_slots,
            [&](const unsigned int begin, const unsigned int end) {
              for (unsigned int s = begin; s < end; ++s)
                direction[s] = z[s] + beta * direction[s];
            },
            4096);
        }

      return measure;
    }



    /**
     * The terms of e [14] of the cells this rank owns at @p densities: from
     * the Johnson-Krizek-Mercier fields of @p element if given (computed
     * here, their constraints checked), otherwise from the @p quadratics.
     * Returns the largest relative defect of the equilibrium [2]
     * (resultant and moment) of an element's data and of the constraints
     * of its field.
     */
    template <int dim>
    double
    element_errors(const Context<dim>                     &context,
                   const ElementQuadratics<dim>           &quadratics,
                   const JohnsonKrizekMercierElement<dim> *element,
                   const std::vector<double>              &densities,
                   Vector<double>                         &error_squared,
                   Vector<double>                         &sum_squared)
    {
      const auto &bc           = context.input.boundary_conditions;
      const auto &mesh         = context.mesh;
      const auto &rules        = context.rules;
      const auto  communicator = context.communicator;
      const auto  n_cells      = context.n_cells;
      std::mutex  mutex;
      double      largest_equilibrium_defect = 0.;
      // (a parsed zero costs a parser call per point: skipped)
      const bool with_force = bc.body_force && !bc.body_force_zero;
      parallel::apply_to_subranges(
        0u,
        n_cells,
        [&](const unsigned int begin, const unsigned int end) {
          double                      range_defect = 0.;
          Vector<double>              d(n_element_values<dim>);
          FullMatrix<double>          work;
          std::vector<Point<dim>>     points(rules.cell.size());
          std::vector<Vector<double>> force(points.size(), Vector<double>(dim));
          for (unsigned int cell = begin; cell < end; ++cell)
            if (mesh.owned[cell])
              {
                const CellGeometry<dim> geometry(mesh, cell);
                element_densities(mesh, cell, densities, d);
                if (element != nullptr)
                  {
                    const EquilibratedCell<dim> data(context, cell);
                    const auto                  traction = data.traction(d);
                    const auto                  field =
                      element->field(data.geometry, traction, data.body_force);
                    const SymmetricTensor<2, dim> admissible =
                      context.input.material.stress(
                        context.strains.admissible_strain[cell]);
                    error_squared[cell] =
                      element->energy(data.geometry, field, admissible);
                    sum_squared[cell] =
                      element->energy(data.geometry, field, -admissible);
                    range_defect = std::max(
                      range_defect,
                      JohnsonKrizekMercierElement<dim>::constraint_defect(
                        data.geometry, field, traction, data.body_force));
                  }
                else
                  {
                    error_squared[cell] = quadratics.value(cell, d, false);
                    sum_squared[cell]   = quadratics.value(cell, d, true);
                  }

                // the resultant and moment of the element's data
                rigid_work(mesh, geometry, cell, work);
                if (with_force)
                  {
                    for (unsigned int q = 0; q < rules.cell.size(); ++q)
                      points[q] = geometry.point(rules.cell.point(q));
                    bc.body_force->vector_value_list(points, force);
                  }
                for (unsigned int r = 0; r < n_rigid<dim>; ++r)
                  {
                    double value = 0., scale = 0.;
                    for (unsigned int a = 0; a < n_element_values<dim>; ++a)
                      {
                        value += work(r, a) * d[a];
                        scale += std::abs(work(r, a) * d[a]);
                      }
                    for (unsigned int q = 0; with_force && q < points.size();
                         ++q)
                      for (unsigned int c = 0; c < dim; ++c)
                        {
                          const double term =
                            force[q][c] *
                            rigid_motion<dim>(
                              r, points[q], geometry.centre, geometry.size, c) *
                            rules.cell.weight(q) * geometry.determinant;
                          value += term;
                          scale += std::abs(term);
                        }
                    if (scale > 0.)
                      range_defect =
                        std::max(range_defect, std::abs(value) / scale);
                  }
              }
          std::lock_guard<std::mutex> lock(mutex);
          largest_equilibrium_defect =
            std::max(largest_equilibrium_defect, range_defect);
        },
        64);
      return Utilities::MPI::max(largest_equilibrium_defect, communicator);
    }
  } // namespace



  template <int dim>
  SimplexEquilibrationChecks
  compute_simplex_element_equilibration(
    const EquilibrationInput<dim>      &input,
    const LA::Vector                   &admissible_displacement,
    const SimplexEquilibrationSettings &settings,
    Vector<double>                     &error_squared,
    Vector<double>                     &sum_squared)
  {
    AssertThrow(!input.dof_handler.get_triangulation().has_hanging_nodes(),
                ExcMessage(
                  "the element equilibration needs a conforming mesh"));
    Progress                   progress("estimate",
                      input.dof_handler.get_triangulation().get_communicator());
    SimplexEquilibrationChecks checks;
    Timer                      timer;
    // the wall seconds since the last step, under @p step
    const auto lap = [&](const std::string &step) {
      checks.seconds.emplace_back(step, timer.wall_time());
      timer.restart();
    };
    Context<dim> context(input, admissible_displacement, settings);
    error_squared.reinit(context.n_cells);
    sum_squared.reinit(context.n_cells);
    lap("mesh and strains");

    // 1. the classical densities
    std::vector<double> densities = data_densities(context);
    checks.prolongation           = classical_densities(context, densities);
    progress.report([]() { return std::string("classical densities done"); });
    lap("classical densities");

    // 2. the element problems on the cells this rank owns and those of the
    //    patches of the enhancement: around each hinge, a vertex in 2D, an
    //    edge in 3D (the entities of dimension dim - 2, around which the
    //    changes of densities that keep every element in equilibrium are
    //    generated; Pled et al. 2012 use vertices in 2D)
    // (the hinges only when there is an enhancement)
    std::unique_ptr<const Hinges<dim>> hinges;
    // (the equilibrated fields compute the errors from the fields: their
    // quadratics serve the enhancement only, which multiplies by those of
    // the owned cells and factors those of the patches)
    std::vector<bool> needed =
      (settings.equilibrated_fields && settings.max_iterations == 0) ?
        std::vector<bool>(context.n_cells, false) :
        context.mesh.owned;
    if (settings.max_iterations > 0)
      {
        hinges =
          std::make_unique<const Hinges<dim>>(context.mesh, context.rank);
        for (unsigned int h = 0; h < hinges->size(); ++h)
          if (hinges->computes[h])
            for (const unsigned int cell : hinges->cells[h])
              needed[cell] = true;
      }
    std::unique_ptr<const JohnsonKrizekMercierElement<dim>> element;
    if (settings.equilibrated_fields)
      element = std::make_unique<const JohnsonKrizekMercierElement<dim>>(
        input.material);
    const ElementQuadratics<dim> quadratics =
      element ? equilibrated_quadratics(context, needed, *element) :
                element_quadratics(context, needed);
    progress.report([]() { return std::string("element problems done"); });
    lap(settings.equilibrated_fields ? "element fields" : "element problems");

    // 3. the enhancement
    if (hinges)
      {
        checks.measure =
          enhance_densities(context, *hinges, quadratics, densities);
        lap("enhancement (" + std::to_string(checks.measure.size()) +
            " iterations)");
      }

    // 4. the terms of e [14] per element, and the check of equilibrium [2]
    checks.equilibrium = element_errors(context,
                                        quadratics,
                                        element.get(),
                                        densities,
                                        error_squared,
                                        sum_squared);
    lap("element errors");
    return checks;
  }



  template SimplexEquilibrationChecks
  compute_simplex_element_equilibration<2>(const EquilibrationInput<2> &,
                                           const LA::Vector &,
                                           const SimplexEquilibrationSettings &,
                                           Vector<double> &,
                                           Vector<double> &);
  template SimplexEquilibrationChecks
  compute_simplex_element_equilibration<3>(const EquilibrationInput<3> &,
                                           const LA::Vector &,
                                           const SimplexEquilibrationSettings &,
                                           Vector<double> &,
                                           Vector<double> &);
} // namespace Signorini
