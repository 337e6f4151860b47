#ifndef signorini_contact_integral_condition_h
#define signorini_contact_integral_condition_h

#include <signorini/contact/condition.h>

namespace Signorini
{
  /**
   * The integral (global) condition [16], [19]-[21], [23]:
   * int_GC mu_h (u_hn - g) dS >= 0 for all P1 mu_h <= 0, i.e. M q_N <= ghat on
   * the rows of the multiplier nodes. The multiplier is Lambda = -y <= 0, so
   * the sign condition holds exactly while small nodal penetrations remain
   * possible (the method is non-conforming).
   */
  template <int dim>
  class IntegralCondition : public ContactCondition<dim>
  {
  public:
    /// W = the rows of M of the multiplier nodes, b = ghat.
    void
    reinit(const ContactBoundary<dim> &boundary) override;

    /// Lambda = -y.
    Vector<double>
    multiplier(const Vector<double> &y) const override;

    /**
     * Paper section 5.1: R^_n = Lambda (<= 0), with which sigma_h is in
     * finite element equilibrium by [19]; U^ = U_h except the normal
     * component at the multiplier nodes, min(U_hn, G) (the tangential part
     * unchanged), so that W^_n <= g at the nodes.
     */
    AdmissibleContactFields<dim>
    admissible_fields(
      const DiscreteContactProblem<dim> &problem,
      const LA::Vector                  &u_h,
      const Vector<double>              &y,
      const FrictionData<dim>           *friction = nullptr) const override;
  };
} // namespace Signorini

#endif
