#ifndef signorini_contact_rigid_motions_h
#define signorini_contact_rigid_motions_h

#include <deal.II/base/mpi.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <signorini/linear_algebra.h>

#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The orthonormal eigenvectors (columns) of the symmetric positive
   * semidefinite @p gram whose eigenvalues are at most @p tolerance.
   */
  FullMatrix<double>
  null_space_of_gram(const FullMatrix<double> &gram, const double tolerance);

  /**
   * The rigid motions the Dirichlet data leave free. A body may be held by
   * the contact alone in some direction (a roller instead of a clamp, or no
   * Dirichlet part at all): its stiffness matrix is then singular on these
   * motions, and the contact problem has a solution only if the foundation
   * stops every one of them and the load presses the body onto it (see
   * DiscreteContactProblem::check_rigid_motions()).
   *
   * The motions are found from the problem itself: a rigid motion z of
   * R^dim (dim translations and dim (dim - 1) / 2 rotations) is free when it
   * vanishes at every dof the Dirichlet data constrain. The free ones span
   * the null space of the Gram matrix of the rigid motions restricted to
   * those dofs.
   *
   * For solves that need an invertible operator whatever the active set
   * (Frank-Wolfe's dual operator, the preconditioner), the class also
   * chooses one "support" dof per free motion: fixing them removes the free
   * motions without changing a load that the rigid motions cannot see.
   */
  template <int dim>
  class RigidMotions
  {
  public:
    /// Rigid motions of R^dim: translations first, then rotations.
    static constexpr unsigned int n_rigid_motions = dim * (dim + 1) / 2;

    /**
     * Find the free rigid motions of the mesh of @p dof_handler (P1 vector
     * element, the mesh known on every rank) under the constraints
     * @p dirichlet_constraints; @p hanging_node_constraints exclude
     * hanging dofs from the supports.
     */
    void
    reinit(const DoFHandler<dim>           &dof_handler,
           const AffineConstraints<double> &dirichlet_constraints,
           const AffineConstraints<double> &hanging_node_constraints);

    /// Number of free rigid motions (0 when the Dirichlet data hold the body).
    unsigned int
    size() const;

    /// Free motion @p j as a nodal displacement vector (distributed).
    const LA::Vector &
    mode(const unsigned int j) const;

    /// All dim (dim + 1) / 2 rigid motions of R^dim (translations, then
    /// rotations), free or not, as nodal displacement vectors: the near
    /// null space of AMG.
    const std::vector<LA::Vector> &
    all_motions() const;

    /// One dof per free motion such that fixing them stops every free motion.
    const std::vector<types::global_dof_index> &
    support_dofs() const;

    /// Add u_s = 0 at the support dofs to @p constraints (not closed).
    void
    add_supports(AffineConstraints<double> &constraints) const;

    /**
     * A description of the motion sum_j coefficients_j mode(j) for a
     * message: "translation along (0, 1)", "rotation about (0.5, 0.2)".
     */
    std::string
    describe(const Vector<double> &coefficients) const;

  private:
    /// The rigid motion @p k of R^dim at @p x, normalised with the diameter.
    Tensor<1, dim>
    rigid_motion(const unsigned int k, const Point<dim> &x) const;

    /// Bounding box centre and diameter of the mesh (scales the rotations).
    Point<dim> centre;
    double     diameter = 1.;
    /// Columns: the free motions in the basis of the rigid motions of R^dim.
    FullMatrix<double>                   basis;
    std::vector<LA::Vector>              modes;
    std::vector<LA::Vector>              motions;
    std::vector<types::global_dof_index> supports;
  };
} // namespace Signorini

#endif
