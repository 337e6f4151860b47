#ifndef signorini_estimator_density_enhancement_h
#define signorini_estimator_density_enhancement_h

#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <signorini/estimator/vertex_patches.h>

#include <array>
#include <functional>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * Enhanced traction densities: the weak prolongation condition
   * (Ladeveze and Rougeot 1997; Pled, Chamoin and Ladeveze, Comput. Mech.
   * 2012; doc/estimator.md).
   *
   * The classical densities satisfy the (strong) prolongation condition
   * int_E (sigma^ - sigma_h) : eps(phi_i) = 0 on every element and vertex,
   * which leaves them a few free parameters per vertex and keeps the
   * estimate loose however the element problems are solved. Here the
   * densities F (linear on every edge) are changed keeping only what makes
   * sigma^ admissible, the equilibrium of every element with its data, so
   * as to minimise
   *   J(F) = 1/2 sum_E ||sigma^_E(F) - K eps(U^)||^2_E,
   * sigma^_E(F) the stress of the element problem of E (affine in the
   * densities of its three edges, ElementQuadratic).
   *
   * The minimisation is a conjugate gradient method in the space of changes
   * that keep every element in equilibrium, preconditioned by the vertex
   * patches (additive Schwarz): the patch of vertex i may change both nodal
   * values of the densities of the edges through i (interior edges: both
   * components; boundary edges: their Dirichlet components; loaded and
   * contact components keep their data) under the equilibrium of each
   * element of the patch, and minimises its restriction of J exactly: over
   * the changes written out from an Airy function (AiryColumns) when every edge
   * through the vertex may change both components, otherwise over a kernel
   * computed by elimination. Each patch correction keeps every element in
   * equilibrium, so does every iterate: sigma^ stays statically admissible
   * after any number of iterations.
   *
   * Densities are exchanged as vectors over all edges of the mesh, slot
   * 4 G + 2 k + c for edge G (face index), its end k (in the face's vertex
   * order) and component c. The value of a slot is the traction on the cell
   * out of which the edge's reference normal (the tangent from end 0 to end
   * 1 turned clockwise) points, whichever rank looks at it. Each patch is
   * computed by exactly one rank (VertexPatches::computes_patch()), every
   * vector entry is the sum of at most two contributions and every scalar
   * product is taken over the full vectors in slot order: the result is the
   * same on any number of ranks and threads.
   */
  class DensityEnhancement
  {
  public:
    /// The slot of end @p end, component @p component of edge @p edge.
    static unsigned int
    slot(const unsigned int edge,
         const unsigned int end,
         const unsigned int component)
    {
      return 4 * edge + 2 * end + component;
    }

    /**
     * J_E(F + dF) = J_E(F) + gradient . dF + 1/2 dF . hessian dF for the 12
     * values dF of the densities of the cell's edges, at position
     * 4 e + 2 k + c for its edge e (VertexPatches::edges()), end k,
     * component c, taken as the values of the slots (not the traction on
     * this cell: sign() converts).
     */
    struct ElementQuadratic
    {
      /// 12 x 12, row by row, symmetric positive semi-definite.
      std::array<double, 144> hessian;
      /// 12 entries, at the current densities.
      std::array<double, 12> gradient;
    };

    /**
     * The problem on the patches of @p patches, with the coordinates
     * @p vertices of the mesh's vertices, the global vertex numbers
     * @p edge_vertices of every edge (by face index; only those of the
     * needed cells are read) and the components of every edge the densities
     * may change (@p free_components: both on interior edges, the Dirichlet
     * ones on the boundary).
     */
    DensityEnhancement(
      const VertexPatches                        &patches,
      const std::vector<Point<2>>                &vertices,
      const std::vector<std::array<unsigned, 2>> &edge_vertices,
      const std::vector<std::array<bool, 2>>     &free_components,
      const MPI_Comm                              communicator);

    /// +1 if the slot values of @p edge are the tractions on @p cell (the
    /// reference normal points out of it), -1 otherwise.
    double
    sign(const unsigned int edge, const unsigned int cell) const;

    /**
     * The regions solved at once in the preconditioner (RegionCorrection):
     * up to @p count of them, each the vertices within @p rings rings of
     * cells of a seed vertex.
     */
    struct RegionSettings
    {
      /// How many regions (0: the vertex patches alone).
      unsigned int count = 0;
      /// Their radius, in rings of cells around the seed.
      unsigned int rings = 0;
    };

    /// What run() did.
    struct Result
    {
      /// The iterations taken.
      unsigned int iterations = 0;
      /// The decrease of J (> 0: every iteration decreases J).
      double decrease = 0.;
    };

    /**
     * The preconditioned conjugate gradient method from the @p densities
     * given in all slots (identical on every rank; the result too), until
     * an iteration decreases J by at most @p tolerance times the decrease
     * so far, or @p max_iterations. @p element_quadratic(cell) is called
     * once per needed cell, on worker threads, at the given densities.
     */
    Result
    run(const std::function<ElementQuadratic(unsigned int)> &element_quadratic,
        const unsigned int                                   max_iterations,
        const double                                         tolerance,
        const RegionSettings                                &regions,
        Vector<double>                                      &densities) const;

  private:
    /**
     * The rows of Z of an edge of an Airy patch (describe_patch()): a change
     * of the Airy function phi of the stress at the patch's vertex (phi,
     * grad phi; zero at the edge's other end) and of the normal derivative
     * of phi at the edge's midpoint changes the traction on the edge by
     * d/ds (d phi/dy, -d phi/dx) (s from end 0 to end 1), linear since grad
     * phi is quadratic along the edge (phi cubic). Any such change leaves
     * every element in equilibrium: the resultant and moment on its
     * boundary are the jumps of single-valued quantities around it. The
     * columns are (phi / h, d phi/dx, d phi/dy, the normal derivative), h a
     * length of the patch. The rows at the other end are minus those at
     * the vertex's end, plus t = 2 s w in (component 1, column 1) and -t in
     * (component 0, column 2), w = 1 / the edge's length and s = +1 if the
     * vertex is end 0, -1 otherwise.
     *
     * Only the edge's geometry is kept, from which the rows are recomputed
     * where they are needed: 32 bytes per edge instead of 80 for the rows,
     * which the preconditioner streams through at every iteration.
     */
    struct AiryColumns
    {
      /// The unit tangent from end 0 to end 1.
      std::array<double, 2> tangent;
      /// w.
      double inverse_length;
      /// The edge's first slot.
      unsigned int first_slot;
      /// The end at the vertex.
      unsigned int vertex_end;

      /// The rows at the vertex's end (component c, column j at 4 c + j),
      /// for 1 / h = @p patch_scale.
      std::array<double, 8>
      at_vertex(const double patch_scale) const;

      /// t.
      double
      shift() const
      {
        return (vertex_end == 0 ? 2. : -2.) * inverse_length;
      }
    };

    /// What the preconditioner keeps of the patch of one vertex.
    struct Patch
    {
      /// The slots it may change.
      std::vector<unsigned int> slots;
      /// For each cell around the vertex (VertexPatches::cells_of_vertex()),
      /// the position in slots of each of its 12 values (-1: not changed).
      std::vector<std::array<int, 12>> positions;
      /// When every edge through the vertex may change both components (an
      /// Airy patch), the rows of Z of its edges in the order of the slots;
      /// empty otherwise.
      std::vector<AiryColumns> airy_columns;
      /// A basis Z of the changes of these slots keeping every element of
      /// the patch in equilibrium (columns): written out for an Airy patch
      /// (the first three columns from the vertex, then one per edge),
      /// otherwise SmallMatrices::kernel_basis() of the constraints.
      FullMatrix<double> basis;
    };

    /**
     * The preconditioner's data of consecutive patches, stored
     * contiguously. The correction of a patch is Z (Z^T H Z)^+ Z^T r for the
     * residual r, H the Hessian of the restriction of J to the patch.
     */
    struct PatchBlock
    {
      /// Per patch: the number n of its slots, k of the columns of Z and of
      /// its Airy edges (0 if it is not an Airy patch).
      std::vector<std::array<unsigned int, 3>> sizes;
      /// The slots of the patches other than Airy ones, one after the other
      /// (those of an Airy patch follow from its edges: for_each_slot()).
      std::vector<unsigned int> slots;
      /// The patches other than Airy ones: factors B = Z L^-T with
      /// B B^T = Z (Z^T H Z)^+ Z^T (n x k, row by row), one after the other.
      std::vector<double> factors;
      /// The Airy patches: their edges, one after the other (1 / h of a
      /// patch is w of its first edge).
      std::vector<AiryColumns> airy_columns;
      /// The Airy patches: the upper triangle of (Z^T H Z)^+ (k x k, row
      /// by row), in single precision: the correction stays a combination
      /// of the columns of Z, exactly equilibrated, whatever its
      /// coefficients.
      std::vector<float> airy_inverses;
      /// The Airy patches: the scale of each one's airy_inverses (their
      /// values are these times the stored ones).
      std::vector<double> airy_scales;

      /// @p function(q, j, slot) for each slot of each patch q of the
      /// block, j its position among the slots of the block, in the order
      /// of the patches and of their slots.
      template <typename Function>
      void
      for_each_slot(const Function &function) const
      {
        std::size_t         j          = 0;
        const unsigned int *other_slot = slots.data();
        const AiryColumns  *edge       = airy_columns.data();
        for (unsigned int q = 0; q < sizes.size(); ++q)
          if (sizes[q][2] > 0)
            for (unsigned int e = 0; e < sizes[q][2]; ++e, ++edge)
              for (unsigned int r = 0; r < 4; ++r)
                function(q, j++, edge->first_slot + r);
          else
            for (unsigned int i = 0; i < sizes[q][0]; ++i)
              function(q, j++, *other_slot++);
      }

      /// The number of slots of the patches of the block.
      std::size_t
      n_slots() const
      {
        std::size_t n = 0;
        for (const auto &size : sizes)
          n += size[0];
        return n;
      }
    };

    /**
     * A coarse correction of the preconditioner, where the vertex patches
     * alone converge slowly. At a singular point (the clamped loaded corner
     * of the block) the change of the densities that J needs spans several
     * rings of patches, which additive patch corrections only build up over
     * many iterations (27 on the block against 10 on a smooth solution, at
     * the same tolerance). A region, the vertices within a few rings of a
     * seed vertex, is minimised over at once: over the span W of the columns
     * of its vertices' patches, the correction W (W^T H W)^+ W^T r. It is a
     * combination of patch changes, so it keeps every element in
     * equilibrium.
     */
    struct RegionCorrection
    {
      /// The slots its columns change.
      std::vector<unsigned int> slots;
      /// W, column by column: (position in slots, value).
      std::vector<std::vector<std::pair<unsigned int, double>>> columns;
      /// The Cholesky factor of W^T H W (SmallMatrices::
      /// semidefinite_cholesky(): the columns of W that depend on earlier
      /// ones, as the normal derivative of an edge shared by the patches of
      /// its two ends, are dropped).
      FullMatrix<double> factor;

      /// @p z += W (W^T H W)^+ W^T @p r.
      void
      add_correction(const Vector<double> &r, Vector<double> &z) const;
    };

    /// The vertices within @p rings rings of cells around @p seed, in
    /// increasing order, the same on every rank.
    std::vector<unsigned int>
    region_vertices(const unsigned int seed, const unsigned int rings) const;

    /**
     * The correction of the region of the vertices @p region
     * (region_vertices()) with the element Hessians @p hessians (their
     * upper triangles, as run() stores them, by active cell index, each
     * divided by its entry of @p hessian_scales; those of the owned cells
     * are read), the
     * same on every rank: each patch is described by the rank that computes
     * it and each cell's Hessian comes from its owner.
     */
    RegionCorrection
    describe_region(const std::vector<unsigned int> &region,
                    const ArrayView<const float>    &hessians,
                    const ArrayView<const double>   &hessian_scales) const;

    /// The patch of @p vertex into @p patch: its slots, their positions in
    /// its cells and the basis of its equilibrated changes.
    void
    describe_patch(const unsigned int vertex, Patch &patch) const;

    /// The equilibrium of each cell of the patch of @p vertex (resultant,
    /// moment about its centroid / its diameter; rows) for a unit value of
    /// each of the slots of @p patch (columns).
    FullMatrix<double>
    equilibrium_constraints(const unsigned int vertex,
                            const Patch       &patch) const;

    /// The cells and edges.
    const VertexPatches &patches;
    /// Vertex coordinates.
    const std::vector<Point<2>> &vertices;
    /// The vertices of every edge.
    const std::vector<std::array<unsigned, 2>> &edge_vertices;
    /// The components the densities may change, by edge.
    const std::vector<std::array<bool, 2>> &free_components;
    /// The ranks.
    const MPI_Comm communicator;
  };
} // namespace Signorini

#endif
