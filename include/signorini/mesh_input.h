#ifndef signorini_mesh_input_h
#define signorini_mesh_input_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/grid/tria.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  template <int dim>
  struct GmshMesh;

  /**
   * Where the initial mesh comes from: the block of the paper's
   * section 7 generated in place, or a Gmsh file (.msh, .geo) whose
   * physical curve tags become boundary ids (a relative file name is taken
   * from the directory of the parameter file).
   *
   * A file is read (a .geo meshed by Gmsh first) and checked once; the
   * copies of a MeshInput made afterwards share what was read.
   *
   * Boundary ids of the generated block (0,1)^2:
   *   1 left edge x = 0, 2 bottom edge y = 0,
   *   3 top edge for x < 1/2, 5 top edge for x > 1/2,
   *   4 right edge for y > 1/2, 6 right edge for y < 1/2.
   * In 3D the block is extruded to (0,1)^3 in tetrahedra: the same ids on
   * the faces x, y = const, and 7 on z = 0 and z = 1. A Gmsh file holds
   * triangles in 2D and tetrahedra in 3D (read_gmsh_mesh()).
   */
  template <int dim>
  class MeshInput
  {
  public:
    /// Where the mesh comes from (Mesh/Source).
    enum class Source
    {
      block,
      file
    };

    static void
    declare_parameters(ParameterHandler &prm);

    /// Read section Mesh.
    void
    parse_parameters(ParameterHandler &prm);

    /// Relative mesh file names are taken from this directory (the
    /// parameter file's).
    void
    set_input_directory(const std::string &directory);

    /// The largest number of cells a .geo as File name may be meshed into
    /// (Maximum cells): checked from its sizes before Gmsh meshes it.
    void
    set_maximum_cells(const double max_cells);

    /// @p name, relative to the input directory unless absolute.
    std::string
    path_of(const std::string &name) const;

    /// Fill the (empty) @p triangulation with the initial mesh, refined
    /// "Initial refinements" times. Throws InputError for files Gmsh
    /// cannot read and for degenerate meshes (see read_gmsh_mesh()).
    void
    create(Triangulation<dim> &triangulation) const;

    /// The number of cells of the generated block before its
    /// refinements (8 triangles per rectangle, 24 tetrahedra per rectangle
    /// and layer), known without building it; computed
    /// in double, so that huge subdivisions do not overflow.
    double
    n_block_cells() const;

    /// The number of cells of the initial mesh before its refinements: the
    /// block's counted, a file's read (which create() then reuses).
    double
    n_coarse_cells() const;

    /// "4 x 3 rectangles" (2D), "4 x 3 x 1 rectangles x layers" (3D): for
    /// messages.
    std::string
    block_subdivisions_text() const;

    Source      source = Source::block;
    std::string file_name;
    /// Gmsh .geo of the domain of file_name (for remeshing), or empty.
    std::string               geometry_file_name;
    std::string               input_directory = ".";
    double                    max_cells = std::numeric_limits<double>::max();
    std::vector<unsigned int> block_subdivisions  = {4, 3};
    unsigned int              initial_refinements = 0;

    /// The mesh of file_name, read and checked at the first call
    /// (collective under MPI for a .geo, which rank 0 meshes).
    const GmshMesh<dim> &
    file_mesh() const;

  private:
    /// What file_mesh() read (shared by copies; reset by parse_parameters()).
    mutable std::shared_ptr<const GmshMesh<dim>> file_mesh_read;
  };
} // namespace Signorini

#endif
