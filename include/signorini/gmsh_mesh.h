#ifndef signorini_gmsh_mesh_h
#define signorini_gmsh_mesh_h

#include <deal.II/base/point.h>

#include <deal.II/grid/tria_description.h>

#include <cstddef>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The mesh Gmsh holds after gmsh::open() of a mesh file or the meshing of
   * a geometry, as the model gives it: its nodes, and its elements by entity
   * with the physical groups of the entity. It is taken in the child
   * process that runs Gmsh (run_in_gmsh_child()) and sent to the parent as
   * bytes; nothing in it is checked yet (checked_mesh() does that).
   */
  struct GmshModelMesh
  {
    /// Gmsh's node tags, and their coordinates (three per node).
    std::vector<std::size_t> node_tags;
    std::vector<double>      coordinates;

    /// The elements of one type on one entity of the model.
    struct Block
    {
      /// Gmsh's element type (1 line, 2 triangle, 4 tetrahedron, ...).
      int type;
      /// The entity: its dimension and tag.
      int entity_dimension;
      int entity_tag;
      /// The tags of the physical groups the entity belongs to.
      std::vector<int> physical_tags;
      /// The element tags, and their nodes (by tag, one run per element).
      std::vector<std::size_t> element_tags;
      std::vector<std::size_t> element_nodes;
    };
    std::vector<Block> blocks;

    /// The number of elements the file's $Elements section announces (0:
    /// unknown). Gmsh stops at the announced number of element blocks, so
    /// that a wrong one would silently drop elements.
    std::size_t n_announced_elements = 0;

    /// The mesh of the current Gmsh model (in the process running Gmsh).
    static GmshModelMesh
    of_current_model();

    /// The mesh as bytes, to pass it from the child to the parent.
    std::string
    to_bytes() const;

    /// The inverse of to_bytes(); throws std::runtime_error on bytes it did
    /// not write.
    static GmshModelMesh
    from_bytes(const std::string &bytes);
  };



  /**
   * A mesh ready for Triangulation::create_triangulation(): the nodes the
   * cells use (in Gmsh's order), the cells (triangles, tetrahedra) oriented
   * positively with the physical tag of their entity as material id, and
   * the boundary elements (lines in 2D, triangles in 3D) that carry a
   * physical tag, as boundary ids.
   */
  template <int dim>
  struct GmshMesh
  {
    std::vector<Point<dim>>    vertices;
    std::vector<CellData<dim>> cells;
    SubCellData                boundary;
  };



  /**
   * The mesh of @p model in dimension @p dim after the checks that the
   * solver would otherwise fail on later, or silently compute another body
   * with, written once for triangles and tetrahedra:
   * - element types: 3-node triangles (2D) or 4-node tetrahedra (3D), their
   *   boundary elements, and points and lines, nothing else; an entity in at
   *   most one physical group;
   * - scales: finite coordinates of at most 1e150, a diameter in
   *   [1e-100, 1e100], in 2D a flat mesh in a plane z = const;
   * - no two nodes at the same point, no cell of (nearly) zero measure, no
   *   face shared by more than two cells or by two cells on the same side
   *   (a folded or repeated cell), no node on a boundary face that is not
   *   one of its corners (a hanging node), one body (cells connected through
   *   their faces), boundary elements with a physical tag on boundary faces
   *   only, one boundary id per face.
   * Distances are relative to the diameter of the mesh (1e-10), areas to its
   * square (1e-12), volumes to its cube (1e-18). Throws InputError whose
   * one-line message starts with <@p name> and names the elements and nodes
   * by their Gmsh tags and coordinates.
   */
  template <int dim>
  GmshMesh<dim>
  checked_mesh(const GmshModelMesh &model, const std::string &name);

  /**
   * The checked mesh (checked_mesh()) of the Gmsh file @p path: a mesh file
   * (.msh, any version and encoding Gmsh reads), or a geometry (.geo) that
   * Gmsh meshes with its own sizes, at most about @p max_cells cells
   * (mesh_geometry()). Gmsh runs in a child process on rank 0: a file that
   * crashes it is bad input, not a crash of the program. Collective on
   * MPI_COMM_WORLD; throws InputError naming @p path on every rank.
   */
  template <int dim>
  GmshMesh<dim>
  read_gmsh_mesh(const std::string &path, const double max_cells);
} // namespace Signorini

#endif
