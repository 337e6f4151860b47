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
   * The mesh of a Gmsh file, ready for Triangulation::create_triangulation():
   * the data GridIn::read_msh() would pass (nodes in file order, material ids
   * from the physical tags of the cells, boundary ids from those of the
   * boundary elements), except that nodes no cell uses are left out (deal.II
   * 9.4 would keep them as vertices without cells), and so are boundary
   * elements without a physical tag and, in 3D, line elements.
   */
  template <int dim>
  struct GmshMesh
  {
    /// The nodes used by the cells, in the order of the file.
    std::vector<Point<dim>> vertices;

    /// The cells (triangles, tetrahedra) in the order of the file. Triangles
    /// are oriented as in the file (GridTools::invert_cells_with_negative_
    /// measure() fixes clockwise ones); tetrahedra are oriented positively.
    std::vector<CellData<dim>> cells;

    /// The boundary elements that carry a non-zero physical tag: lines
    /// (boundary_lines) in 2D, triangles (boundary_quads) in 3D.
    SubCellData boundary;
  };

  /**
   * Read the ASCII Gmsh file @p path (msh 2.x, 4.0 or 4.1) of a mesh of
   * triangles (@p dim = 2) or tetrahedra (@p dim = 3) with a strict parser
   * and check it before anything is built from it, because deal.II's
   * reader trusts the file: a wrong count in $Nodes overruns a heap buffer, a
   * wrong entity block count or an unterminated section makes it crash, hang
   * or allocate gigabytes. Checked are the structure (sections in the order
   * deal.II reads them, each closed, counts equal to the records present,
   * numbers that parse and are finite, tags in range, nodes referenced by
   * elements defined, element types: 3-node triangles, 4-node tetrahedra in
   * 3D, 2-node lines and points only) and the geometry of the cells (in 2D a
   * flat mesh in a plane z = const; no two nodes at the same point, no cell
   * of (nearly) zero area or volume, no face (edge in 2D) shared by more than
   * two cells or by two cells on the same side, no node on a boundary face
   * that is not one of its corners, boundary elements with a physical tag on
   * boundary faces, one body: cells connected through shared faces, a
   * diameter in [1e-100, 1e100] and coordinates of at most 1e150). Distances
   * are relative to the diameter of the mesh (1e-10), areas to its square
   * (1e-12), volumes to its cube (1e-18).
   *
   * Throws InputError whose one-line message names @p path and, where it
   * applies, the line of the file, the element and the nodes (by their Gmsh
   * tags and coordinates).
   */
  template <int dim>
  GmshMesh<dim>
  read_gmsh_file(const std::string &path);

  /// read_gmsh_file() on the contents @p text of a mesh file, named @p name
  /// in the messages.
  template <int dim>
  GmshMesh<dim>
  read_gmsh_text(const std::string &name, const std::string &text);
} // namespace Signorini

#endif
