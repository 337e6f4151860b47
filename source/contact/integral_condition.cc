#include <signorini/contact/discrete_problem.h>
#include <signorini/contact/integral_condition.h>

namespace Signorini
{
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



  template <int dim>
  AdmissibleContactFields<dim>
  IntegralCondition<dim>::admissible_fields(
    const DiscreteContactProblem<dim> &problem,
    const LA::Vector                  &u_h,
    const Vector<double>              &y,
    const FrictionData<dim>           *friction) const
  {
    const auto                  &boundary = problem.boundary();
    AdmissibleContactFields<dim> fields;
    const Vector<double>         lambda = multiplier(y);
    fields.normal_reaction.reinit(boundary.n_nodes());
    for (unsigned int i = 0; i < lambda.size(); ++i)
      fields.normal_reaction[this->multiplier_node[i]] = lambda[i];

    // U^: the nodal penetrations the integral condition allows removed
    fields.displacement        = u_h;
    const Vector<double> q_n   = boundary.normal_components(u_h);
    const IndexSet       owned = u_h.locally_owned_elements();
    for (const unsigned int k : this->multiplier_node)
      {
        const double excess = q_n[k] - boundary.nodal_gap()[k];
        if (excess > 0.)
          for (unsigned int c = 0; c < dim; ++c)
            if (owned.is_element(boundary.node(k).dofs[c]))
              fields.displacement[boundary.node(k).dofs[c]] -=
                excess * boundary.direction()[c];
      }
    fields.displacement.compress(VectorOperation::add);
    fields.equilibrated_displacement = u_h;
    // R^_t: the multiplier itself, whose nodal forces are those of u_h
    // (the projection moves it at the solver's tolerance only)
    if (friction != nullptr)
      this->set_tangential_reaction(boundary, *friction, fields);
    return fields;
  }

  template class IntegralCondition<2>;
  template class IntegralCondition<3>;

  SIGNORINI_REGISTER_TEMPLATE(ContactCondition,
                              IntegralCondition,
                              0,
                              "integral",
                              "M q_N <= ghat, [16]");
} // namespace Signorini
