#ifndef signorini_contact_condition_h
#define signorini_contact_condition_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <signorini/contact/contact_boundary.h>
#include <signorini/contact/friction_law.h>
#include <signorini/linear_algebra.h>
#include <signorini/registry.h>

#include <memory>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  template <int dim>
  class DiscreteContactProblem;

  /**
   * The admissible contact fields built from a finite element solution
   * (U_h, y) (paper section 5, doc/theory.md section 7): the reaction R^ =
   * R^_n nu_c, the displacement U^ (= W^ on GC) and a displacement whose
   * stress is in finite element equilibrium with the loads and R^, from
   * which sigma^ is built.
   */
  template <int dim>
  struct AdmissibleContactFields
  {
    /// R^_n (<= 0) at every node of GC, zero at the nodes without a
    /// multiplier: the nodal values of a continuous piecewise linear R^_n.
    Vector<double> normal_reaction;
    /// U^, with W^_n <= g at the nodes of GC.
    LA::Vector displacement;
    /// U_h, or U~_h when sigma_h is not in equilibrium with R^.
    LA::Vector equilibrated_displacement;
    /// Multiplier nodes where Lambda_i > 0 (the pointwise condition).
    unsigned int positive_multipliers = 0;
    /// With friction: R^_t at the nodes of GC, a continuous piecewise
    /// linear field with |R^_t| <= s, s the P1 field of friction_bound;
    /// empty without.
    std::vector<Tensor<1, dim>> tangential_reaction;
    /// With friction: the bound of |R^_t| at the nodes of GC, mu |R^_n|
    /// (Coulomb) or the threshold at the nodes of the rows, in contact or
    /// not, and zero at a node without one (Tresca, whose discrete law
    /// acts on every row).
    std::vector<double> friction_bound;
  };

  /// Friction's part of a solution, for its admissible fields: the law and
  /// the tangential multiplier of each row (FrictionState::force).
  template <int dim>
  struct FrictionData
  {
    const FrictionLaw<dim>            &law;
    const std::vector<Tensor<1, dim>> &multiplier;
  };

  /**
   * A discrete non-penetration condition (paper section 4, [16]-[24];
   * doc/theory.md section 2), written as
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
   * the residual) follows from W and b and is implemented here once. The
   * error estimator asks the condition for its admissible fields.
   *
   * The conditions form a family chosen by Contact/Condition (registry()).
   */
  template <int dim>
  class ContactCondition
  {
  public:
    virtual ~ContactCondition() = default;

    /// The conditions, chosen by Contact/Condition; each registers itself
    /// (SIGNORINI_REGISTER_TEMPLATE()).
    static Registry<ContactCondition<dim>> &
    registry();

    /// The name the condition is chosen by.
    const std::string &
    name() const;

    /// Build W and b for the current contact boundary.
    virtual void
    reinit(const ContactBoundary<dim> &boundary) = 0;

    /// Lambda, the nodal values of the multiplier lambda_h on the multiplier
    /// nodes (<= 0 in compression), from y.
    virtual Vector<double>
    multiplier(const Vector<double> &y) const = 0;

    /**
     * The admissible fields (paper sections 5.1 and 5.2) from the solution
     * @p u_h, y of @p problem (whose condition this is), with @p friction
     * if not null. @p u_h carries no ghost entries; the displacements
     * returned have its layout.
     */
    virtual AdmissibleContactFields<dim>
    admissible_fields(const DiscreteContactProblem<dim> &problem,
                      const LA::Vector                  &u_h,
                      const Vector<double>              &y,
                      const FrictionData<dim> *friction = nullptr) const = 0;

    /// Number of constraint rows (= multiplier nodes).
    unsigned int
    n_constraints() const;

    /// The number of nodes of GC at the last reinit() (checked against the
    /// boundary by DiscreteContactProblem: a condition not built for it).
    unsigned int
    n_boundary_nodes() const
    {
      return n_all_nodes;
    }

    /// B q = W q_N for the given normal displacements of all nodes.
    Vector<double>
    constraint_values(const Vector<double> &normal_displacements) const;

    /// b: ghat (integral) or G (pointwise) on the multiplier nodes.
    const Vector<double> &
    bounds() const;

    /// Normal nodal contact forces on every node of GC, -W^T y (<= 0).
    Vector<double>
    nodal_forces(const Vector<double> &y) const;

    /// The diagonal of W (scale of a row).
    double
    row_weight(const unsigned int i) const;

    /// The sum of row i of W: the total nodal force of a unit multiplier
    /// on the row (a traction's multiplier is the traction times the
    /// node's area over it).
    double
    row_sum(const unsigned int i) const;

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
     * The same for the displacement component @p component of the nodes
     * (friction: a tangential one): (W t)_i = @p right_hand_side[i] for the
     * rows in @p rows, t the component at the nodes of GC, solved for the
     * component of the rows' nodes, t(S) = W_SS^{-1} (b_S - W_{S,R} t(R)).
     */
    void
    add_component_constraints(const std::vector<bool>    &rows,
                              const unsigned int          component,
                              const Vector<double>       &right_hand_side,
                              const ContactBoundary<dim> &boundary,
                              AffineConstraints<double>  &constraints) const;

    /// Row i of W: (node of GC, weight).
    const std::vector<std::pair<unsigned int, double>> &
    weight_row(const unsigned int i) const;

    /**
     * The dual variable from the normal residual forces rho_k = nu_c . (F -
     * K q)_k on the nodes of GC: y_A = W_AA^{-T} rho_A, y = 0 elsewhere.
     */
    Vector<double>
    dual_from_residual(const std::vector<bool> &active,
                       const Vector<double>    &normal_residual) const;

  protected:
    /**
     * R^_t at the nodes of GC (in @p fields, whose normal_reaction is set):
     * the nodal values of the tangential multiplier (multiplier() of the
     * rows' tangential forces, component by component), projected at each
     * node onto the disc of AdmissibleContactFields::friction_bound, which
     * it sets too; the P1 field |R^_t| is then below the P1 field of the
     * bounds everywhere. Returns whether the projection moved a value by
     * more than 1e-8 of the largest.
     */
    bool
    set_tangential_reaction(const ContactBoundary<dim>   &boundary,
                            const FrictionData<dim>      &friction,
                            AdmissibleContactFields<dim> &fields) const;

    /// W as sparse rows: (node index, weight); row i belongs to node
    /// multiplier_node[i].
    std::vector<std::vector<std::pair<unsigned int, double>>> weight_rows;
    /// The node of GC of each constraint row.
    std::vector<unsigned int> multiplier_node;
    /// b
    Vector<double> bound_values;
    /// Number of nodes of GC (columns of W).
    unsigned int n_all_nodes = 0;

  private:
    /// Solve W_AA X = R for several right-hand sides (columns of R, each of
    /// length |A|); W_AA is symmetric positive definite.
    void
    solve_active_block(const std::vector<unsigned int> &active_rows,
                       std::vector<Vector<double>>     &right_hand_sides) const;

    /// add_active_constraints() along any direction: (W (d . u))_i = b_i
    /// for the rows in @p rows, solved for the component @p c_star of the
    /// rows' nodes (d_{c_star} != 0).
    void
    add_constraints_along(const std::vector<bool>    &rows,
                          const Tensor<1, dim>       &direction,
                          const unsigned int          c_star,
                          const Vector<double>       &right_hand_side,
                          const ContactBoundary<dim> &boundary,
                          AffineConstraints<double>  &constraints) const;
  };
} // namespace Signorini

#endif
