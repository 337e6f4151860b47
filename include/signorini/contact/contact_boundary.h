#ifndef signorini_contact_contact_boundary_h
#define signorini_contact_contact_boundary_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <signorini/linear_algebra.h>

#include <array>
#include <map>
#include <memory>
#include <set>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The candidate contact part GC and its discretisation (paper section
   * 4.3, doc/theory.md section 2):
   * the mesh vertices on GC ("nodes"), the contact direction nu_c, the nodal
   * gap G_k = g(x_k), the weighted gap ghat_k = int_GC g psi_k and the
   * contact-boundary mass matrix M_jk = int_GC psi_j psi_k over all nodes.
   *
   * A node whose normal displacement is prescribed by a Dirichlet condition
   * (the block's clamped corner) stays in M, since its basis function is part
   * of the trace space, but carries no multiplier.
   */
  template <int dim>
  class ContactBoundary
  {
  public:
    /// A mesh vertex on GC.
    struct Node
    {
      /// x_k
      Point<dim> position;
      /// The mesh vertex index.
      unsigned int vertex;
      /// Its displacement dofs, one per component.
      std::array<types::global_dof_index, dim> dofs;
      /// Whether it carries a multiplier (its normal displacement is free).
      bool has_multiplier;
    };

    /// Boundary ids, Direction and Gap in section Contact.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read them.
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Collect the nodes of GC on the current mesh and build M, G and ghat.
     * Throws if a node of GC is a hanging node (not supported on GC), and
     * checks the contact data on this mesh (check_data()).
     */
    void
    reinit(const Mapping<dim>              &mapping,
           const DoFHandler<dim>           &dof_handler,
           const AffineConstraints<double> &dirichlet_constraints,
           const AffineConstraints<double> &hanging_node_constraints);

    /// Number of nodes of GC.
    unsigned int
    n_nodes() const;

    /// Node @p k of GC.
    const Node &
    node(const unsigned int k) const;

    /// The node at the mesh vertex @p vertex (which must lie on GC).
    unsigned int
    node_index(const unsigned int vertex) const;

    /// Indices (into the node list) of the nodes that carry a multiplier.
    const std::vector<unsigned int> &
    multiplier_nodes() const;

    /// nu_c
    const Tensor<1, dim> &
    direction() const;

    /// The displacement component that carries the normal constraint of an
    /// active node: the one with the largest |nu_c| entry.
    unsigned int
    constrained_component() const;

    /// M over all nodes of GC.
    const SparseMatrix<double> &
    mass_matrix() const;

    /// int_GC psi_k (the row sums of M): the area a node's force acts on.
    Vector<double>
    nodal_areas() const;

    /// The nodal pressure -f_k / int_GC psi_k of the nodal forces @p forces
    /// (ContactCondition::nodal_forces(); >= 0 in compression, 0 where f_k
    /// is).
    Vector<double>
    nodal_pressures(const Vector<double> &forces) const;

    /// G_k = g(x_k)
    const Vector<double> &
    nodal_gap() const;

    /// ghat_k = int_GC g psi_k
    const Vector<double> &
    weighted_gap() const;

    /// The initial gap g at a point of GC.
    double
    gap(const Point<dim> &x) const;

    /// v(x_k) . nu_c for every node of a nodal vector v (with v = U_h: the
    /// normal displacements q_N), on every rank.
    Vector<double>
    normal_components(const LA::Vector &v) const;

    /// v += sum_k forces_k nu_c at the dofs of node k.
    void
    add_normal_forces(const Vector<double> &forces, LA::Vector &v) const;

    /// Boundary ids forming GC.
    const std::set<types::boundary_id> &
    boundary_ids() const;

    /// Whether reinit() was called.
    bool
    is_reinitialised() const
    {
      return reinitialised;
    }

    /// Number of active cells with a face on GC.
    unsigned int
    n_contact_cells() const;

    /// The diagonal of the bounding box of GC's nodes: the length scale of
    /// comparisons of gaps and displacements (0 without nodes).
    double
    size() const;

    /**
     * Refuse (InputError) a node of GC whose displacement along nu_c the
     * Dirichlet @p dirichlet_constraints prescribe beyond its gap G_k: the
     * body is held in penetration there, and no displacement meets the
     * contact condition (the discrete problem has no solution, and an
     * estimate of its error would not be a bound). A node whose normal
     * displacement is only partly prescribed is not checked. reinit() calls
     * it with the constraints it is given; a load step calls it again with
     * its own.
     */
    void
    check_prescribed_nodes(
      const AffineConstraints<double> &dirichlet_constraints) const;

  private:
    /**
     * Called by reinit() once G and ghat are built: refuse a gap that is
     * not finite at the nodes or at the face quadrature points where it is
     * evaluated, and warn on screen (rank 0, once per run) if nu_c is nearly
     * tangent to GC or points into the body at some face, or if the gap is
     * negative at some node (initial penetration). These are warnings, not
     * errors: a curved GC may well turn away from a fixed nu_c far from
     * where contact occurs.
     */
    void
    check_data(const Mapping<dim>    &mapping,
               const DoFHandler<dim> &dof_handler) const;

    /// Contact/Boundary ids
    std::set<types::boundary_id> ids;
    bool                         reinitialised = false;
    /// nu_c is the outward normal of a flat GC (found by reinit()) rather
    /// than a given vector.
    bool use_outward_normal = true;
    /// Contact/Gap
    std::unique_ptr<Functions::ParsedFunction<dim>> gap_function;

    /// nu_c
    Tensor<1, dim> contact_direction;
    /// The nodes of GC, in the order reinit() met them.
    std::vector<Node> nodes;
    /// The node of each mesh vertex on GC.
    std::map<unsigned int, unsigned int> node_of_vertex;
    /// The nodes that carry a multiplier.
    std::vector<unsigned int> multiplier_node_indices;
    /// Sparsity of M
    SparsityPattern mass_sparsity;
    /// M
    SparseMatrix<double> mass;
    /// G
    Vector<double> gap_at_nodes;
    /// ghat
    Vector<double> weighted_gap_at_nodes;
    /// See n_contact_cells().
    unsigned int contact_cell_count = 0;
  };
} // namespace Signorini

#endif
