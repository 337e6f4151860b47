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
   * meshed anew by Gmsh (its C++ API, Frontal-Delaunay), the element size
   * at a point given by the predicted sizes of the current mesh, so that
   * sizes are continuous, may grow beyond the initial mesh's and need no
   * closure. Chosen by Mesh adaptation/Realisation = remeshing; the others
   * refine the initial mesh (AdaptiveMesh).
   *
   * The size field: a cell E of area |E| asked to shrink by r_E should
   * become triangles of about r_E^-2 per area |E| (N* = sum_E r_E^-2), i.e.
   * equilateral triangles of edge h*_E = r_E (4 |E| / sqrt 3)^(1/2). Its
   * logarithm is averaged at the vertices and interpolated linearly inside
   * the cells (CellLocator), which Gmsh queries through its size callback.
   * Rank 0 meshes and broadcasts the mesh, so that every rank holds the
   * same one.
   *
   * The geometry: the generated block (Mesh/Source = block: the unit
   * square, its boundary ids on the same edges, split at x = 1/2 on the top
   * and y = 1/2 on the right), or for a Gmsh mesh file the .geo of its
   * domain (Mesh/Geometry file, physical curves as boundary ids and no mesh
   * size fields); without one, remeshing is refused at input.
   */
  template <int dim>
  class GmshRemesher
  {
  public:
    /// Throws InputError if @p input has no geometry to remesh, or if a
    /// .geo lacks a physical curve for one of the @p boundary_ids in use.
    void
    check_geometry(const MeshInput<dim>               &input,
                   const std::set<types::boundary_id> &boundary_ids) const;

    /// The geometry of @p input meshed with the sizes r_E h_E of the cells
    /// of @p mesh (@p size_ratio per active cell), written into @p mesh.
    void
    remesh(const MeshInput<dim> &input,
           const Vector<double> &size_ratio,
           Triangulation<dim>   &mesh) const;

  private:
    /// log of the size asked for at every vertex of @p mesh: the mean of
    /// log(r_E h*_E) over its cells, h*_E the size of Gmsh's cells of the
    /// measure of E.
    static std::vector<double>
    vertex_log_sizes(const Triangulation<dim> &mesh,
                     const Vector<double>     &size_ratio);
  };
} // namespace Signorini

#endif
