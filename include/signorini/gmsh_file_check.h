#ifndef signorini_gmsh_file_check_h
#define signorini_gmsh_file_check_h

#include <deal.II/base/point.h>

#include <deal.II/grid/tria_description.h>

#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The triangle mesh of a Gmsh file, ready for
   * Triangulation::create_triangulation(): the same data GridIn::read_msh()
   * would pass (nodes in file order, material ids from the physical surface
   * tags, boundary ids from the physical curve tags), except that nodes no
   * triangle uses are left out (deal.II 9.4 would keep them as vertices
   * without cells) and so are line elements without a physical tag.
   */
  struct GmshTriangleMesh
  {
    /// The nodes used by the triangles, in the order of the file.
    std::vector<Point<2>> vertices;

    /// The triangles, in the order of the file, oriented as in the file
    /// (GridTools::invert_cells_with_negative_measure() fixes clockwise ones).
    std::vector<CellData<2>> cells;

    /// The boundary edges that carry a non-zero physical tag (boundary_lines).
    SubCellData boundary;
  };

  /**
   * Read the ASCII Gmsh file @p path (msh 2.x, 4.0 or 4.1) with a strict
   * parser and check it before anything is built from it, because deal.II's
   * reader trusts the file: a wrong count in $Nodes overruns a heap buffer, a
   * wrong entity block count or an unterminated section makes it crash, hang
   * or allocate gigabytes. Checked are the structure (sections in the order
   * deal.II reads them, each closed, counts equal to the records present,
   * numbers that parse and are finite, tags in range, nodes referenced by
   * elements defined, element types: 3-node triangles, 2-node lines and
   * points only) and the geometry of the triangles (a flat mesh in a plane
   * z = const, no two nodes at the same point, no triangle of (nearly) zero
   * area, no edge shared by more than two triangles or by two triangles on
   * the same side, no node inside a boundary edge, line elements with a
   * physical tag on boundary edges, one body: triangles connected through
   * shared edges, a diameter in [1e-100, 1e100] and coordinates of at most
   * 1e150). Distances are relative to the diameter of the mesh (1e-10),
   * areas to its square (1e-12).
   *
   * Throws InputError whose one-line message names @p path and, where it
   * applies, the line of the file, the element and the nodes (by their Gmsh
   * tags and coordinates).
   */
  GmshTriangleMesh
  read_gmsh_file(const std::string &path);
} // namespace Signorini

#endif
