#ifndef signorini_adaptation_bisection_forest_h
#define signorini_adaptation_bisection_forest_h

#include <deal.II/base/point.h>
#include <deal.II/base/types.h>

#include <deal.II/grid/tria.h>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * Newest-vertex bisection of a triangle mesh (Mitchell 1991; Binev,
   * Dahmen and DeVore 2004), which deal.II does not provide: every triangle
   * is halved through the midpoint of its refinement edge, the edge opposite
   * its newest vertex, so that each bisection halves the area (sizes change
   * by sqrt 2, against 2 for red refinement) and all triangles fall into a
   * few similarity classes of every initial triangle (no angle decay: the
   * right isosceles triangles of the generated block stay right isosceles).
   *
   * The roots are the initial mesh, each with its longest edge as
   * refinement edge (Mitchell's condition under which the closure ends). A
   * leaf with a hanging node is bisected until none is left; the closure
   * keeps every triangle a node of the bisection trees, so the mesh stays
   * conforming without special closure cells.
   *
   * Every triangle ever made is kept: a new mesh is chosen from the roots
   * anew (refine()), so that leaves may become coarser as well as finer.
   * 2D only.
   */
  class BisectionForest
  {
  public:
    /// The roots: the triangles of @p coarse (a flat triangulation).
    void
    initialize(const Triangulation<2> &coarse);

    /**
     * The leaves become the coarsest conforming mesh of the forest in which
     * the region of every current leaf c is bisected to generation at least
     * max(generation(c) + generation_change[c], 0); where the regions of
     * different requests meet, the finest wins.
     */
    void
    refine(const std::vector<int> &generation_change);

    /**
     * What refine(@p generation_change) would make, the leaves left as they
     * are: per current leaf, the smallest generation change of the new
     * leaves in its region (negative if one new leaf covers it), and the
     * number of new leaves.
     */
    std::pair<std::vector<int>, unsigned int>
    trial_refine(const std::vector<int> &generation_change);

    /// The leaves as a flat triangulation @p mesh, cell i being leaf i, with
    /// the boundary ids of the edges they halve and the material ids of
    /// their roots.
    void
    write(Triangulation<2> &mesh) const;

    /// Number of leaves.
    unsigned int
    n_leaves() const;

    /// The generation (bisections since its root) of leaf @p i.
    unsigned int
    generation(const unsigned int i) const;

  private:
    struct Triangle
    {
      /// vertex[0] is the newest vertex; the refinement edge joins vertex[1]
      /// and vertex[2]. The orientation is that of the root.
      std::array<unsigned int, 3> vertex;
      unsigned int                generation  = 0;
      int                         parent      = -1;
      std::array<int, 2>          child       = {{-1, -1}};
      types::material_id          material_id = 0;
    };

    /// The key of the edge between vertices @p a and @p b.
    static std::uint64_t
    edge(const unsigned int a, const unsigned int b);

    /// The children of triangle @p t, made on first use.
    std::array<int, 2>
    children(const unsigned int t);

    /// Bisect leaves until no leaf has a hanging node.
    void
    close();

    std::vector<Point<2>>     vertices;
    std::vector<Triangle>     triangles; // the roots first
    unsigned int              n_roots = 0;
    std::vector<unsigned int> leaves;
    /// midpoint vertex of every edge ever bisected
    std::unordered_map<std::uint64_t, unsigned int> midpoint;
    /// boundary id of every boundary edge ever made
    std::unordered_map<std::uint64_t, types::boundary_id> boundary_id;
  };
} // namespace Signorini

#endif
