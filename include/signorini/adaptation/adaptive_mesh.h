#ifndef signorini_adaptation_adaptive_mesh_h
#define signorini_adaptation_adaptive_mesh_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/grid/tria.h>

#include <signorini/adaptation/bisection_forest.h>
#include <signorini/mesh_input.h>

#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The meshes of an adaptive computation (paper section 6), refined from
   * the initial mesh in one of two ways (Mesh adaptation/Realisation):
   *
   * - refinement: deal.II's red refinement, sizes in steps of 2, made
   *   conforming by green closure (below);
   * - bisection: newest-vertex bisection (BisectionForest), sizes in steps
   *   of sqrt 2, conforming by construction, no angle decay.
   *
   * For red refinement, since deal.II 9.4 cannot coarsen triangles and
   * hanging nodes would break the element equilibration, two triangulations
   * are kept:
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
   * refining its hierarchy cell once. With bisection the level of a cell is
   * its generation in the bisection forest.
   *
   * The green closure is written for triangles: in 3D, building a
   * computational mesh (initialize(), remesh()) throws an InputError.
   */
  template <int dim>
  class AdaptiveMesh
  {
  public:
    /// How predicted sizes become the next mesh.
    enum class Realisation
    {
      refinement,
      bisection,
      remeshing
    };

    /// Mesh adaptation/Realisation
    static void
    declare_parameters(ParameterHandler &prm);

    void
    parse_parameters(ParameterHandler &prm);

    /// The realisation chosen (by default red refinement). With remeshing
    /// (GmshRemesher) the meshes come from adopt().
    Realisation
    realisation() const;

    /// h_child / h_parent of one level: 1/2 for red refinement, 2^(-1/d)
    /// for bisection (whose levels halve the area of a triangle).
    double
    level_size_ratio() const;

    /// The hierarchy becomes the initial mesh of @p input; its conforming
    /// version (the same mesh) is written into @p mesh.
    void
    initialize(const MeshInput<dim> &input, Triangulation<dim> &mesh);

    /**
     * Rebuild the hierarchy (or choose the leaves of the bisection forest)
     * from the initial mesh so that the region of every cell c of the
     * current computational mesh is refined to the level max(level(c) +
     * level_change[c], initial level); where regions of different requests
     * meet, the finest wins. The new conforming mesh is
     * written into @p mesh.
     */
    void
    remesh(const MeshInput<dim>   &input,
           const std::vector<int> &level_change,
           Triangulation<dim>     &mesh);

    /**
     * Bisection: what remesh() would make of @p level_change, the current
     * mesh left as it is: per cell, the smallest level change in its region,
     * and the number of cells. Other realisations: empty (not simulated).
     */
    std::pair<std::vector<int>, unsigned int>
    trial_remesh(const std::vector<int> &level_change);

    /**
     * Take @p mesh (made elsewhere, e.g. by remeshing) as the initial mesh
     * of a new hierarchy: every cell at level 0, no green cells. Further
     * meshes then come from initialize() or adopt(), not remesh(), which
     * rebuilds from the input.
     */
    void
    adopt(Triangulation<dim> &mesh);

    /**
     * The current mesh is the last one: free the hierarchy (and the
     * bisection forest), which can be as large as the mesh itself. levels(),
     * n_green_cells() and finest_halvings() still answer; remesh() and
     * trial_remesh() may no longer be called.
     */
    void
    release_hierarchy();

    /// Per active cell of the computational mesh: its hierarchy level.
    const std::vector<unsigned int> &
    levels() const;

    /// How many times the finest cell's size was halved from the coarse
    /// input mesh (before its initial refinements), to compare with a
    /// uniformly refined mesh.
    double
    finest_halvings() const;

    /// Cells of the computational mesh that are halves of a hierarchy cell.
    unsigned int
    n_green_cells() const;

  private:
    /// Bisection: the forest rooted in the hierarchy (the input mesh) with
    /// no @p level_change, or its leaves refined by @p level_change, written
    /// into @p mesh.
    void
    bisect(Triangulation<dim> &mesh, const std::vector<int> *level_change);

    /**
     * In 3D, where the hierarchy is the input's mesh: if @p mesh is flat
     * (one level, every vertex used) it is its own hierarchy, which is then
     * not stored: index its cells as such, at @p level, and return true.
     */
    bool
    index_as_flat_mesh(const Triangulation<dim> &mesh,
                       const unsigned int        level);

    /// Close the hierarchy (green closure) and write it into @p mesh.
    void
    build_conforming_mesh(Triangulation<dim> &mesh);

    Realisation               chosen_realisation = Realisation::refinement;
    BisectionForest           forest;
    Triangulation<dim>        hierarchy;
    std::vector<unsigned int> hierarchy_cell_of; // active cell index
    std::vector<unsigned int> level_of;
    unsigned int              green_cells = 0;
    /// Bisection: the level of the forest's roots in the red hierarchy
    unsigned int initial_level = 0;
    /// Whether the hierarchy starts from the input's mesh (not adopt()ed),
    /// as remesh() needs
    bool from_input = true;
    /// Whether release_hierarchy() was called since the last initialize()
    /// or adopt() (in 3D the hierarchy may be empty without that).
    bool hierarchy_released = false;
  };

  /// In 3D: throws an InputError (the green closure bisects triangles).
  template <>
  void
  AdaptiveMesh<3>::build_conforming_mesh(Triangulation<3> &mesh);
} // namespace Signorini

#endif
