#include <signorini/contact/integral_condition.h>

namespace Signorini
{
  template <int dim>
  std::string
  IntegralCondition<dim>::name() const
  {
    return "integral";
  }



  template <int dim>
  void
  IntegralCondition<dim>::reinit(const ContactBoundary<dim> &boundary)
  {
    // rows of M for the multiplier nodes: (M q_N)_i <= ghat_i
    this->n_all_nodes     = boundary.n_nodes();
    this->multiplier_node = boundary.multiplier_nodes();
    const unsigned int m  = this->multiplier_node.size();
    this->weight_rows.assign(m, {});
    this->bound_values.reinit(m);
    const auto &mass = boundary.mass_matrix();
    for (unsigned int i = 0; i < m; ++i)
      {
        const unsigned int k = this->multiplier_node[i];
        for (auto entry = mass.begin(k); entry != mass.end(k); ++entry)
          this->weight_rows[i].emplace_back(entry->column(), entry->value());
        this->bound_values[i] = boundary.weighted_gap()[k];
      }
  }



  template <int dim>
  Vector<double>
  IntegralCondition<dim>::multiplier(const Vector<double> &y) const
  {
    Vector<double> lambda(y.size());
    for (unsigned int i = 0; i < y.size(); ++i)
      lambda[i] = -y[i];
    return lambda;
  }

  template class IntegralCondition<2>;
} // namespace Signorini
