#ifndef signorini_domain_summary_h
#define signorini_domain_summary_h

#include <deal.II/base/point.h>
#include <deal.II/base/types.h>

#include <deal.II/grid/tria_description.h>

#include <map>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * What two meshes of the same body share whatever their cells: the
   * bounding box and measure of the domain, the number of separate bodies
   * (cells connected through faces), and per boundary id the measure and
   * bounding box of the boundary faces that carry it (id 0: the boundary
   * faces without one). Used to check that a remeshing geometry describes
   * the body of the mesh it replaces (GmshRemesher::check_geometry()):
   * another size, other or swapped boundary ids show here.
   */
  template <int dim>
  class DomainSummary
  {
  public:
    /// The summary of the mesh of simplices @p cells on @p vertices, the
    /// boundary ids from @p boundary (lines in 2D, triangles in 3D).
    DomainSummary(const std::vector<Point<dim>>    &vertices,
                  const std::vector<CellData<dim>> &cells,
                  const SubCellData                &boundary);

    /// A part of the domain or of its boundary.
    struct Part
    {
      Part();

      /// Extend by @p point.
      void
      add(const Point<dim> &point);

      double     measure = 0;
      Point<dim> lower, upper; // the bounding box
    };

    Part                               domain;
    unsigned int                       n_bodies = 0;
    std::map<types::boundary_id, Part> boundary;

    /**
     * How this summary (of "the geometry") differs from @p mesh's, as a
     * phrase for a message, or "" if not at all: bounding boxes differ by
     * more than @p tolerance times the diameter of @p mesh, measures by more
     * than @p tolerance relatively, or the sets of boundary ids differ.
     */
    std::string
    difference_from(const DomainSummary &mesh, const double tolerance) const;
  };
} // namespace Signorini

#endif
