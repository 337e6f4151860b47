#ifndef signorini_coarse_domain_mesher_h
#define signorini_coarse_domain_mesher_h

#include <deal.II/base/point.h>

#include <deal.II/grid/tria.h>

#include <array>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The domain of a mesh meshed again by Gmsh at a coarser, uniform size:
   * the coarser meshes of the nested start of the contact solve on a mesh
   * that has none (a user's mesh file, a .geo, a mesh without initial
   * refinements), so that the active set method starts near the answer on
   * any mesh (doc/benchmarks.md, "Cold start on any mesh").
   *
   * Only the boundary of the fine mesh is used, and only its shape:
   * - in 2D its edges are joined into curves between corners (where the
   *   boundary id changes or the boundary turns by more than 30 degrees;
   *   at least three per closed boundary curve), each a line if straight,
   *   else a spline through its vertices;
   * - in 3D Gmsh groups its triangles into smooth patches
   *   (classifySurfaces at 40 degrees) and parametrises them
   *   (createGeometry), as for an STL surface.
   * A boundary face of the coarse mesh takes the boundary id of the fine
   * boundary face whose centre is nearest to its own. The coarse mesh
   * approximates the domain (a curved boundary by its splines or patches):
   * it is meant for a first guess, never for an answer. Where Gmsh cannot
   * mesh the domain this way, create() throws and the caller starts cold.
   */
  template <int dim>
  class CoarseDomainMesher
  {
  public:
    /// Takes the boundary of @p fine (every rank must hold all its cells),
    /// for meshes of the cell sizes @p relative_sizes (coarsest first)
    /// times the fine mesh's mean edge length (Gmsh's sense of a size).
    CoarseDomainMesher(const Triangulation<dim>  &fine,
                       const std::vector<double> &relative_sizes);

    /// Build the coarser mesh @p i (0: the coarsest) in the empty
    /// @p coarse. Collective on MPI_COMM_WORLD: the first call meshes them
    /// all, rank 0 running Gmsh once in a child process, and every rank
    /// builds the same meshes. Throws std::runtime_error if Gmsh fails or
    /// a mesh does not pass checked_mesh().
    void
    create(const unsigned int i, Triangulation<dim> &coarse) const;

  private:
    /// The boundary faces of the fine mesh: vertices (indices into
    /// boundary_vertices), centre and boundary id.
    struct BoundaryFace
    {
      std::array<unsigned int, dim> vertices;
      Point<dim>                    centre;
      types::boundary_id            id;
    };

    /// The meshes of the domain at every size, each as its length in 20
    /// digits and GmshModelMesh::to_bytes() (run in the Gmsh child).
    std::string
    meshes_in_gmsh() const;

    /// 2D: the geometry from the boundary curves (see the class).
    /// (Defined for dim = 2 only, as add_surfaces_geometry() for dim = 3.)
    void
    add_curves_geometry() const;

    /// 3D: the geometry from the boundary triangles (see the class).
    void
    add_surfaces_geometry() const;

    std::vector<Point<dim>>   boundary_vertices;
    std::vector<BoundaryFace> boundary_faces;
    std::vector<double>       sizes;
    /// The meshes, once made.
    mutable std::vector<std::string> mesh_bytes;
  };
} // namespace Signorini

#endif
