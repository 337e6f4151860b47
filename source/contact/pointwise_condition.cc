#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <signorini/contact/pointwise_condition.h>

namespace Signorini
{
  template <int dim>
  std::string
  PointwiseCondition<dim>::name() const
  {
    return "pointwise";
  }



  template <int dim>
  void
  PointwiseCondition<dim>::reinit(const ContactBoundary<dim> &boundary)
  {
    // identity rows: q_N(i) <= G_i
    this->n_all_nodes     = boundary.n_nodes();
    this->multiplier_node = boundary.multiplier_nodes();
    const unsigned int m  = this->multiplier_node.size();
    this->weight_rows.assign(m, {});
    this->bound_values.reinit(m);
    std::vector<unsigned int> row_of_node(boundary.n_nodes(),
                                          numbers::invalid_unsigned_int);
    for (unsigned int i = 0; i < m; ++i)
      {
        this->weight_rows[i].emplace_back(this->multiplier_node[i], 1.);
        this->bound_values[i] = boundary.nodal_gap()[this->multiplier_node[i]];
        row_of_node[this->multiplier_node[i]] = i;
      }
    if (m == 0)
      return;

    // M restricted to the multiplier nodes, to turn Gamma into Lambda.
    const auto            &mass = boundary.mass_matrix();
    DynamicSparsityPattern dsp(m, m);
    for (unsigned int i = 0; i < m; ++i)
      for (auto entry = mass.begin(this->multiplier_node[i]);
           entry != mass.end(this->multiplier_node[i]);
           ++entry)
        if (row_of_node[entry->column()] != numbers::invalid_unsigned_int)
          dsp.add(i, row_of_node[entry->column()]);
    multiplier_mass.clear();
    multiplier_mass_sparsity.copy_from(dsp);
    multiplier_mass.reinit(multiplier_mass_sparsity);
    for (unsigned int i = 0; i < m; ++i)
      for (auto entry = mass.begin(this->multiplier_node[i]);
           entry != mass.end(this->multiplier_node[i]);
           ++entry)
        if (row_of_node[entry->column()] != numbers::invalid_unsigned_int)
          multiplier_mass.set(i, row_of_node[entry->column()], entry->value());
    multiplier_mass_inverse.initialize(multiplier_mass);
  }



  template <int dim>
  Vector<double>
  PointwiseCondition<dim>::multiplier(const Vector<double> &y) const
  {
    // Gamma = -y = M Lambda
    Vector<double> lambda(y.size());
    for (unsigned int i = 0; i < y.size(); ++i)
      lambda[i] = -y[i];
    if (lambda.size() > 0)
      multiplier_mass_inverse.solve(lambda);
    return lambda;
  }

  template class PointwiseCondition<2>;
} // namespace Signorini
