#ifndef signorini_adaptation_adaptive_mesh_h
#define signorini_adaptation_adaptive_mesh_h

#include <deal.II/grid/tria.h>

#include <signorini/mesh_input.h>

#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The meshes of an adaptive computation (paper section 6). deal.II 9.4
   * cannot coarsen triangles, and hanging nodes would break the element
   * equilibration, so two triangulations are kept:
   *
   * - the hierarchy: the initial mesh refined by deal.II (red refinement,
   *   at most one hanging node per face). Each new hierarchy is rebuilt from
   *   the initial mesh, so that element sizes may grow as well as shrink;
   * - the computational mesh: the hierarchy made conforming by green closure
   *   (cells with two or three hanging nodes are refined in the hierarchy,
   *   cells with one are bisected from the hanging node to the opposite
   *   vertex), a flat triangulation on which everything else runs.
   *
   * A computational cell refers to the hierarchy cell it comes from; its
   * level is the level of that cell, so that halving a green cell means
   * refining its hierarchy cell once.
   *
   * The green closure is written for triangles: in 3D, building a
   * computational mesh (initialize(), remesh()) throws an InputError.
   */
  template <int dim>
  class AdaptiveMesh
  {
  public:
    /// The hierarchy becomes the initial mesh of @p input; its conforming
    /// version (the same mesh) is written into @p mesh.
    void
    initialize(const MeshInput<dim> &input, Triangulation<dim> &mesh);

    /**
     * Rebuild the hierarchy from the initial mesh so that the region of
     * every cell c of the current computational mesh is refined to the level
     * max(level(c) + level_change[c], initial level); where regions of
     * different requests meet, the finest wins. The new conforming mesh is
     * written into @p mesh.
     */
    void
    remesh(const MeshInput<dim>   &input,
           const std::vector<int> &level_change,
           Triangulation<dim>     &mesh);

    /**
     * Take @p mesh (made elsewhere, e.g. by remeshing) as the initial mesh
     * of a new hierarchy: every cell at level 0, no green cells. Further
     * meshes then come from initialize() or adopt(), not remesh(), which
     * rebuilds from the input.
     */
    void
    adopt(Triangulation<dim> &mesh);

    /// Per active cell of the computational mesh: its hierarchy level.
    const std::vector<unsigned int> &
    levels() const;

    /// Cells of the computational mesh that are halves of a hierarchy cell.
    unsigned int
    n_green_cells() const;

  private:
    /// Close the hierarchy (green closure) and write it into @p mesh.
    void
    build_conforming_mesh(Triangulation<dim> &mesh);

    Triangulation<dim>        hierarchy;
    std::vector<unsigned int> hierarchy_cell_of; // active cell index
    std::vector<unsigned int> level_of;
    unsigned int              green_cells = 0;
    /// Whether the hierarchy starts from the input's mesh (not adopt()ed),
    /// as remesh() needs
    bool from_input = true;
  };

  /// In 3D: throws an InputError (the green closure bisects triangles).
  template <>
  void
  AdaptiveMesh<3>::build_conforming_mesh(Triangulation<3> &mesh);
} // namespace Signorini

#endif
