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
    std::string
    name() const override;

    void
    reinit(const ContactBoundary<dim> &boundary) override;

    Vector<double>
    multiplier(const Vector<double> &y) const override;

  private:
    SparsityPattern      multiplier_mass_sparsity;
    SparseMatrix<double> multiplier_mass;
    SparseDirectUMFPACK  multiplier_mass_inverse;
  };
} // namespace Signorini

#endif
