#ifndef signorini_estimator_vertex_patches_h
#define signorini_estimator_vertex_patches_h

#include <deal.II/base/array_view.h>
#include <deal.II/base/parallel.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <deal.II/grid/tria.h>

#include <array>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The vertex patches (stars) omega_i of a conforming triangle mesh, on
   * which both stress reconstructions solve their local problems: the cells
   * around each vertex, the vertices and edges of each cell, and the two
   * cells of each edge.
   *
   * Under MPI every rank holds the whole mesh (parallel::shared) and computes
   * the error of the cells it owns. Their local problems involve the patches
   * of their vertices (the patches this rank "treats"), which cover the cells
   * around them (the "needed" cells): only those are described, the other
   * cells have no vertices, edges or patches here.
   */
  class VertexPatches
  {
  public:
    /// Describe the patches of @p triangulation that this rank treats.
    explicit VertexPatches(const Triangulation<2> &triangulation);

    /// The number of vertices of the triangulation (treated or not).
    unsigned int
    n_vertices() const
    {
      return first_cell_of_vertex.size() - 1;
    }

    /// Whether this rank solves the problem of the patch of @p vertex (a
    /// vertex of a cell it owns).
    bool
    treats_patch(const unsigned int vertex) const
    {
      return vertex_of_owned_cell[vertex] &&
             first_cell_of_vertex[vertex + 1] > first_cell_of_vertex[vertex];
    }

    /**
     * Whether this rank is the one that computes the patch of @p vertex
     * where every patch must be computed once over all ranks: among the
     * ranks that treat it, the one of lowest subdomain id owning a cell
     * around it.
     */
    bool
    computes_patch(const unsigned int vertex) const
    {
      return computing_vertex[vertex];
    }

    /// The number of active cells of the triangulation (needed or not).
    unsigned int
    n_cells() const
    {
      return needed_cell.size();
    }

    /// Whether this rank owns the cell of active cell index @p cell.
    bool
    owned(const unsigned int cell) const
    {
      return owned_cell[cell];
    }

    /// Whether the cell of active cell index @p cell lies in a treated patch.
    bool
    needed(const unsigned int cell) const
    {
      return needed_cell[cell];
    }

    /// The needed cells around @p vertex, in increasing active cell index
    /// (the order fixes the numbering of the patch unknowns).
    ArrayView<const unsigned int>
    cells_of_vertex(const unsigned int vertex) const
    {
      return make_array_view(cells_around_vertices.begin() +
                               first_cell_of_vertex[vertex],
                             cells_around_vertices.begin() +
                               first_cell_of_vertex[vertex + 1]);
    }

    /// Global vertex numbers of a needed cell, in the cell's order.
    const std::array<unsigned int, 3> &
    vertices(const unsigned int cell) const
    {
      return cell_vertices[cell];
    }

    /// Face indices of the edges of a needed cell: edge e joins the cell's
    /// vertices e and e + 1 (mod 3).
    const std::array<unsigned int, 3> &
    edges(const unsigned int cell) const
    {
      return cell_edges[cell];
    }

    /// 0, 1 or 2: the number of global vertex @p vertex in a needed cell.
    unsigned int
    local_vertex(const unsigned int cell, const unsigned int vertex) const;

    /**
     * The needed cells sharing the edge of face index @p edge, in active cell
     * order: the first one defines the orientation of the edge's normal and
     * densities (a fixed choice, independent of the thread schedule); the
     * second is numbers::invalid_unsigned_int on the boundary.
     */
    const std::array<unsigned int, 2> &
    cells_of_edge(const unsigned int edge) const
    {
      return edge_cells[edge];
    }

    /// Call @p worker(vertex) for every treated patch, in parallel on
    /// deal.II's worker threads (@p grain_size vertices per task).
    template <typename Worker>
    void
    for_each_patch(const Worker &worker, const unsigned int grain_size) const
    {
      parallel::apply_to_subranges(
        0u,
        n_vertices(),
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int vertex = begin; vertex < end; ++vertex)
            if (treats_patch(vertex))
              worker(vertex);
        },
        grain_size);
    }

    /// Call @p worker(vertex) for every treated patch, in increasing vertex
    /// order on the calling thread (when the results must come in order).
    template <typename Worker>
    void
    for_each_patch_in_order(const Worker &worker) const
    {
      for (unsigned int vertex = 0; vertex < n_vertices(); ++vertex)
        if (treats_patch(vertex))
          worker(vertex);
    }

  private:
    /// By vertex: is it a vertex of a locally owned cell?
    std::vector<bool> vertex_of_owned_cell;
    /// By vertex: does this rank compute its patch (computes_patch())?
    std::vector<bool> computing_vertex;
    /// By active cell index: does this rank own it?
    std::vector<bool> owned_cell;
    /// By active cell index: does the cell lie in a treated patch?
    std::vector<bool> needed_cell;
    /// The needed cells around each vertex, one vertex after the other
    /// (one array: a vector per vertex meant 0.8M allocations and frees at
    /// 1.6M DoFs).
    std::vector<unsigned int> cells_around_vertices;
    /// By vertex: where its cells start in cells_around_vertices (and, at
    /// vertex + 1, end).
    std::vector<unsigned int> first_cell_of_vertex;
    /// By active cell index: global vertex numbers.
    std::vector<std::array<unsigned int, 3>> cell_vertices;
    /// By active cell index: face indices of the edges.
    std::vector<std::array<unsigned int, 3>> cell_edges;
    /// By face index: the (at most two) needed cells of the edge.
    std::vector<std::array<unsigned int, 2>> edge_cells;
  };



  /**
   * The affine map x = origin + jacobian xi of a triangle from the reference
   * triangle (its vertices 0, 1, 2 to (0, 0), (1, 0), (0, 1)). Both
   * reconstructions integrate on the reference triangle with it instead of
   * deal.II's mapping, which is the same map for straight P1 triangles.
   */
  struct AffineTriangle
  {
    /// The map of @p cell (any active cell iterator of a triangle).
    template <typename CellIterator>
    explicit AffineTriangle(const CellIterator &cell)
      : origin(cell->vertex(0))
    {
      for (unsigned int d = 0; d < 2; ++d)
        {
          jacobian[d][0] = cell->vertex(1)[d] - origin[d];
          jacobian[d][1] = cell->vertex(2)[d] - origin[d];
        }
      inverse_jacobian = invert(jacobian);
      determinant      = std::abs(dealii::determinant(jacobian));
    }

    /// The image of vertex 0.
    Point<2> origin;
    /// The (constant) Jacobian matrix.
    Tensor<2, 2> jacobian;
    /// Its inverse: row a is the gradient of the barycentric coordinate
    /// lambda_{a+1}.
    Tensor<2, 2> inverse_jacobian;
    /// |det J|, twice the area.
    double determinant = 0.;
  };
} // namespace Signorini

#endif
