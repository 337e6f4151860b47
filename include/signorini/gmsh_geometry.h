#ifndef signorini_gmsh_geometry_h
#define signorini_gmsh_geometry_h

#include <signorini/gmsh_mesh.h>

#include <string>

namespace Signorini
{
  /**
   * Mesh the Gmsh geometry file @p path (.geo) in dimension @p dim with the
   * Gmsh C++ API, as `gmsh -dim path` would (the file's own size fields and
   * options), on one thread so that every run gets the same mesh, and
   * return the model's mesh (unchecked: checked_mesh() comes next).
   *
   * Gmsh runs in a child process (run_in_gmsh_child()): a crash of Gmsh on
   * the file is an error of the file, not of the program. Before the mesh
   * is made, the file's sizes are checked against @p max_cells (Maximum
   * cells, which otherwise applies only after meshing, possibly hours
   * later): a lower estimate of the number of cells, the measure of the
   * domain over that of a cell of the largest size Gmsh uses on its curves,
   * beyond @p max_cells is refused.
   *
   * Runs on the calling rank only. Throws InputError naming @p path if Gmsh
   * cannot read or mesh the file, or if its sizes would make too many cells.
   */
  GmshModelMesh
  mesh_geometry(const std::string &path,
                const unsigned int dim,
                const double       max_cells);
} // namespace Signorini

#endif
