#ifndef signorini_adaptation_gmsh_remesher_h
#define signorini_adaptation_gmsh_remesher_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/vector.h>

#include <signorini/mesh_input.h>

#include <set>

namespace Signorini
{
  using namespace dealii;

  /**
   * The paper's realisation of a size prediction (section 6): the geometry
   * meshed anew by Gmsh (its C++ API: Frontal-Delaunay triangles in 2D,
   * Delaunay tetrahedra in 3D), the element size at a point given by the
   * predicted sizes of the current mesh, so that sizes are continuous, may
   * grow beyond the initial mesh's and need no closure. Chosen by Mesh
   * adaptation/Realisation = remeshing; the others refine the initial mesh
   * (AdaptiveMesh, 2D).
   *
   * The size field: a cell E asked to shrink by r_E should become about
   * r_E^-d cells (N* = sum_E r_E^-d), i.e. cells of size h*_E = r_E h_E,
   * h_E the size of Gmsh's cells of the measure of E: the edge of the
   * equilateral triangle of area |E| in 2D; in 3D the size whose Delaunay
   * tetrahedra have volume |E| on average (0.55 times the count of regular
   * tetrahedra of that edge, measured). Its logarithm is averaged at the
   * vertices and interpolated linearly inside the cells (CellLocator),
   * which Gmsh queries through its size callback. Rank 0 meshes and
   * broadcasts the mesh, so that every rank holds the same one.
   *
   * The geometry: the generated block (Mesh/Source = block: the unit
   * square, or in 3D the unit cube extruded from it, its boundary ids on
   * the same edges and faces, split at x = 1/2 on the top and y = 1/2 on
   * the right, id 7 on z = 0 and z = 1), or for a Gmsh mesh file the .geo
   * of its domain (Mesh/Geometry file, physical curves (2D) or surfaces
   * (3D) as boundary ids and no mesh size fields); without one, remeshing
   * is refused at input.
   */
  template <int dim>
  class GmshRemesher
  {
  public:
    /// Throws InputError if @p input has no geometry to remesh, if
    /// Mesh/Geometry file is not a .geo, lacks a surface (2D) or volume
    /// (3D) or a physical curve or surface for one of the @p boundary_ids
    /// in use, makes Gmsh fail, or is not the domain of the mesh: meshed
    /// with about the mesh's number of cells, it must be one body with the
    /// mesh's bounding box, measure and boundary ids, each with the mesh's
    /// measure and bounding box (to 2 %; DomainSummary), or the remeshing
    /// would compute another body. Collective: rank 0 checks.
    void
    check_geometry(const MeshInput<dim>               &input,
                   const std::set<types::boundary_id> &boundary_ids) const;

    /// The geometry of @p input meshed with the sizes r_E h_E of the cells
    /// of @p mesh (@p size_ratio per active cell), written into @p mesh.
    void
    remesh(const MeshInput<dim> &input,
           const Vector<double> &size_ratio,
           Triangulation<dim>   &mesh) const;
  };
} // namespace Signorini

#endif
