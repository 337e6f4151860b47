#ifndef signorini_contact_condition_h
#define signorini_contact_condition_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <signorini/contact/contact_boundary.h>

#include <memory>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * A discrete non-penetration condition (spec section 2), written as
   *
   *   B q <= b,  B = W N,
   *
   * with N q = q_N the nodal normal displacements of all nodes of GC and W a
   * weight matrix with one row per multiplier node: W = M (rows of the
   * multiplier nodes) and b = ghat for the integral condition [16], W = I and
   * b = G for the pointwise one [17]. The dual variable y >= 0 of this form
   * gives the problem K q + B^T y = F; each condition says how y maps to the
   * multiplier Lambda and to the nodal forces Gamma.
   *
   * This is the whole interface a contact solver needs: everything else (the
   * equality constrained problem for an active set, the recovery of y from
   * the residual) follows from W and b and is implemented here once.
   */
  template <int dim>
  class ContactCondition
  {
  public:
    virtual ~ContactCondition() = default;

    /// "integral" or "pointwise"
    virtual std::string
    name() const = 0;

    /// Build W and b for the current contact boundary.
    virtual void
    reinit(const ContactBoundary<dim> &boundary) = 0;

    /// Lambda, the nodal values of the multiplier lambda_h on the multiplier
    /// nodes (<= 0 in compression), from y.
    virtual Vector<double>
    multiplier(const Vector<double> &y) const = 0;

    /// Number of constraint rows (= multiplier nodes).
    unsigned int
    n_constraints() const;

    /// B q = W q_N for the given normal displacements of all nodes.
    Vector<double>
    constraint_values(const Vector<double> &normal_displacements) const;

    const Vector<double> &
    bounds() const;

    /// Normal nodal contact forces on every node of GC, -W^T y (<= 0).
    Vector<double>
    nodal_forces(const Vector<double> &y) const;

    /// The diagonal of W (scale of a row).
    double
    row_weight(const unsigned int i) const;

    /**
     * Add to @p constraints the equality constraints (B q)_i = b_i, i in the
     * active set, solved for the constrained component of the active nodes:
     * q_N(A) = W_AA^{-1} (b_A - W_{A,R} q_N(R)), R the other nodes of GC.
     */
    void
    add_active_constraints(const std::vector<bool>    &active,
                           const ContactBoundary<dim> &boundary,
                           AffineConstraints<double>  &constraints) const;

    /**
     * The dual variable from the normal residual forces rho_k = nu_c . (F -
     * K q)_k on the nodes of GC: y_A = W_AA^{-T} rho_A, y = 0 elsewhere.
     */
    Vector<double>
    dual_from_residual(const std::vector<bool> &active,
                       const Vector<double>    &normal_residual) const;

  protected:
    /// W as sparse rows: (node index, weight); row i belongs to node
    /// multiplier_node[i].
    std::vector<std::vector<std::pair<unsigned int, double>>> weight_rows;
    std::vector<unsigned int>                                 multiplier_node;
    Vector<double>                                            bound_values;
    unsigned int                                              n_all_nodes = 0;

  private:
    /// Solve W_AA X = R for several right-hand sides (columns of R, each of
    /// length |A|); W_AA is symmetric positive definite.
    void
    solve_active_block(const std::vector<unsigned int> &active_rows,
                       std::vector<Vector<double>>     &right_hand_sides) const;
  };

  template <int dim>
  void
  declare_contact_condition_parameters(ParameterHandler &prm);

  /// Create the condition named by Contact/Condition.
  template <int dim>
  std::unique_ptr<ContactCondition<dim>>
  create_contact_condition(ParameterHandler &prm);

  template <int dim>
  std::unique_ptr<ContactCondition<dim>>
  create_contact_condition(const std::string &name);
} // namespace Signorini

#endif
