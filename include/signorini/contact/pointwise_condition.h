#ifndef signorini_contact_pointwise_condition_h
#define signorini_contact_pointwise_condition_h

#include <deal.II/lac/sparse_direct.h>

#include <signorini/contact/condition.h>

namespace Signorini
{
  /**
   * The pointwise (nodal) condition [17], [22], [24]: q_N <= G at every
   * multiplier node. The nodal forces are Gamma = -y <= 0 and the multiplier
   * Lambda = M^{-1} Gamma (M restricted to the multiplier nodes) may have
   * positive entries; the method is conforming.
   */
  template <int dim>
  class PointwiseCondition : public ContactCondition<dim>
  {
  public:
    /// W = I on the multiplier nodes, b = G; factorises M restricted to
    /// them for multiplier().
    void
    reinit(const ContactBoundary<dim> &boundary) override;

    /// Lambda = M^{-1} Gamma, Gamma = -y.
    Vector<double>
    multiplier(const Vector<double> &y) const override;

    /**
     * Paper section 5.2: U^ = U_h (conforming) and R^_n = min(Lambda, 0).
     * When some Lambda_i > 0, sigma_h is no longer in finite element
     * equilibrium with R^: one more elasticity problem with the loads and
     * R^ gives U~_h, whose stress sigma~_h is. For a body held only by the
     * contact R^ is first rescaled to balance the load on the free rigid
     * motions (without that no stress is in equilibrium with it). With
     * friction R^_t = M^{-1} f_t, projected onto the cone: when that moved
     * it, U~_h answers the loads and the whole of R^.
     */
    AdmissibleContactFields<dim>
    admissible_fields(
      const DiscreteContactProblem<dim> &problem,
      const LA::Vector                  &u_h,
      const Vector<double>              &y,
      const FrictionData<dim>           *friction = nullptr) const override;

  private:
    /// Sparsity of multiplier_mass.
    SparsityPattern multiplier_mass_sparsity;
    /// M restricted to the multiplier nodes: Gamma = M Lambda there.
    SparseMatrix<double> multiplier_mass;
    /// Its factorisation.
    SparseDirectUMFPACK multiplier_mass_inverse;
  };
} // namespace Signorini

#endif
