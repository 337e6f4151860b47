#ifndef signorini_cell_locator_h
#define signorini_cell_locator_h

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/point.h>

#include <deal.II/grid/tria.h>

#include <deal.II/numerics/rtree.h>

#include <deal.II/boost_adaptors/bounding_box.h>
#include <deal.II/boost_adaptors/point.h>

#include <array>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The cell of a triangle or tetrahedron mesh that contains a point, and
   * the point's barycentric coordinates in it. deal.II 9.4's point location
   * is not reliable on simplices (dealii-9.4-triangles.md), so the cell is
   * found with an rtree of the cells' bounding boxes and a barycentric test:
   * of the candidates, the one the point is deepest inside (round-off on
   * edges). A point outside every box (beyond a curved boundary the mesh
   * approximates) gets the cell of the nearest box, whose weights then
   * extrapolate.
   */
  template <int dim>
  class CellLocator
  {
  public:
    /// What locate() found.
    struct Location
    {
      /// Whether a cell was found (not for an empty mesh).
      bool found = false;
      /// That cell's active cell index in the mesh.
      unsigned int cell = 0;
      /// The barycentric coordinates of the point in that cell.
      std::array<double, dim + 1> weights{};
    };

    /// For the active cells of @p mesh (which must outlive the locator).
    explicit CellLocator(const Triangulation<dim> &mesh);

    Location
    locate(const Point<dim> &p) const;

    /// The active cell of index @p cell.
    const typename Triangulation<dim>::active_cell_iterator &
    cell(const unsigned int cell) const;

  private:
    std::vector<typename Triangulation<dim>::active_cell_iterator> cells;
    RTree<std::pair<BoundingBox<dim>, unsigned int>>               tree;
  };
} // namespace Signorini

#endif
