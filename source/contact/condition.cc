#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>

#include <signorini/contact/condition.h>

namespace Signorini
{
  template <int dim>
  Registry<ContactCondition<dim>> &
  ContactCondition<dim>::registry()
  {
    // the conditions register themselves in their own files
    static Registry<ContactCondition<dim>> conditions(
      "Contact", "Condition", "Discrete non-penetration condition");
    return conditions;
  }



  template <int dim>
  const std::string &
  ContactCondition<dim>::name() const
  {
    return registry().name_of(*this);
  }



  template <int dim>
  unsigned int
  ContactCondition<dim>::n_constraints() const
  {
    return weight_rows.size();
  }



  template <int dim>
  Vector<double>
  ContactCondition<dim>::constraint_values(const Vector<double> &q_n) const
  {
    AssertDimension(q_n.size(), n_all_nodes);
    Vector<double> values(weight_rows.size());
    for (unsigned int i = 0; i < weight_rows.size(); ++i)
      for (const auto &[k, w] : weight_rows[i])
        values[i] += w * q_n[k];
    return values;
  }



  template <int dim>
  const Vector<double> &
  ContactCondition<dim>::bounds() const
  {
    return bound_values;
  }



  template <int dim>
  Vector<double>
  ContactCondition<dim>::nodal_forces(const Vector<double> &y) const
  {
    AssertDimension(y.size(), weight_rows.size());
    Vector<double> forces(n_all_nodes);
    for (unsigned int i = 0; i < weight_rows.size(); ++i)
      for (const auto &[k, w] : weight_rows[i])
        forces[k] -= w * y[i];
    return forces;
  }



  template <int dim>
  double
  ContactCondition<dim>::row_weight(const unsigned int i) const
  {
    for (const auto &[k, w] : weight_rows[i])
      if (k == multiplier_node[i])
        return w;
    Assert(false, ExcInternalError());
    return 0.;
  }



  template <int dim>
  double
  ContactCondition<dim>::row_sum(const unsigned int i) const
  {
    AssertIndexRange(i, weight_rows.size());
    double sum = 0.;
    for (const auto &entry : weight_rows[i])
      sum += entry.second;
    return sum;
  }



  template <int dim>
  void
  ContactCondition<dim>::solve_active_block(
    const std::vector<unsigned int> &active_rows,
    std::vector<Vector<double>>     &right_hand_sides) const
  {
    const unsigned int        n = active_rows.size();
    std::vector<unsigned int> position_of_node(n_all_nodes,
                                               numbers::invalid_unsigned_int);
    for (unsigned int a = 0; a < n; ++a)
      position_of_node[multiplier_node[active_rows[a]]] = a;

    DynamicSparsityPattern dsp(n, n);
    for (unsigned int a = 0; a < n; ++a)
      for (const auto &[k, w] : weight_rows[active_rows[a]])
        if (position_of_node[k] != numbers::invalid_unsigned_int)
          dsp.add(a, position_of_node[k]);
    SparsityPattern sparsity;
    sparsity.copy_from(dsp);
    SparseMatrix<double> block(sparsity);
    for (unsigned int a = 0; a < n; ++a)
      for (const auto &[k, w] : weight_rows[active_rows[a]])
        if (position_of_node[k] != numbers::invalid_unsigned_int)
          block.set(a, position_of_node[k], w);

    SparseDirectUMFPACK inverse;
    inverse.initialize(block);
    for (auto &rhs : right_hand_sides)
      inverse.solve(rhs);
  }



  template <int dim>
  const std::vector<std::pair<unsigned int, double>> &
  ContactCondition<dim>::weight_row(const unsigned int i) const
  {
    AssertIndexRange(i, weight_rows.size());
    return weight_rows[i];
  }



  template <int dim>
  void
  ContactCondition<dim>::add_active_constraints(
    const std::vector<bool>    &active,
    const ContactBoundary<dim> &boundary,
    AffineConstraints<double>  &constraints) const
  {
    add_constraints_along(active,
                          boundary.direction(),
                          boundary.constrained_component(),
                          bound_values,
                          boundary,
                          constraints);
  }



  template <int dim>
  void
  ContactCondition<dim>::add_component_constraints(
    const std::vector<bool>    &rows,
    const unsigned int          component,
    const Vector<double>       &right_hand_side,
    const ContactBoundary<dim> &boundary,
    AffineConstraints<double>  &constraints) const
  {
    Tensor<1, dim> unit;
    unit[component] = 1.;
    add_constraints_along(
      rows, unit, component, right_hand_side, boundary, constraints);
  }



  template <int dim>
  void
  ContactCondition<dim>::add_constraints_along(
    const std::vector<bool>    &active,
    const Tensor<1, dim>       &nu,
    const unsigned int          c_star,
    const Vector<double>       &right_hand_side,
    const ContactBoundary<dim> &boundary,
    AffineConstraints<double>  &constraints) const
  {
    AssertDimension(active.size(), weight_rows.size());
    std::vector<unsigned int> active_rows;
    std::vector<bool>         node_is_active(n_all_nodes, false);
    for (unsigned int i = 0; i < active.size(); ++i)
      if (active[i])
        {
          active_rows.push_back(i);
          node_is_active[multiplier_node[i]] = true;
        }
    if (active_rows.empty())
      return;

    // The other nodes coupled to the active rows (R), one right-hand side
    // each, plus b_A.
    std::vector<unsigned int> coupled_nodes;
    {
      std::vector<bool> seen(n_all_nodes, false);
      for (const unsigned int i : active_rows)
        for (const auto &[k, w] : weight_rows[i])
          if (!node_is_active[k] && !seen[k])
            {
              seen[k] = true;
              coupled_nodes.push_back(k);
            }
    }
    const unsigned int          n_active = active_rows.size();
    std::vector<Vector<double>> columns(1 + coupled_nodes.size(),
                                        Vector<double>(n_active));
    for (unsigned int a = 0; a < n_active; ++a)
      {
        columns[0][a] = right_hand_side[active_rows[a]];
        for (const auto &[k, w] : weight_rows[active_rows[a]])
          for (unsigned int r = 0; r < coupled_nodes.size(); ++r)
            if (coupled_nodes[r] == k)
              columns[1 + r][a] = -w;
      }
    solve_active_block(active_rows, columns);

    for (unsigned int a = 0; a < n_active; ++a)
      {
        const auto &node = boundary.node(multiplier_node[active_rows[a]]);
        const types::global_dof_index dof = node.dofs[c_star];
        constraints.add_line(dof);
        // nu_c* u_c* = q_N(a) - sum_{c != c*} nu_c u_c, with
        // q_N(a) = d_a + sum_r coef_ar q_N(r).
        for (unsigned int r = 0; r < coupled_nodes.size(); ++r)
          {
            const double coefficient = columns[1 + r][a];
            if (std::abs(coefficient) < 1e-15)
              continue; // entries of W_AA^{-1} decay geometrically
            for (unsigned int c = 0; c < dim; ++c)
              if (nu[c] != 0.)
                constraints.add_entry(dof,
                                      boundary.node(coupled_nodes[r]).dofs[c],
                                      coefficient * nu[c] / nu[c_star]);
          }
        for (unsigned int c = 0; c < dim; ++c)
          if (c != c_star && nu[c] != 0.)
            constraints.add_entry(dof, node.dofs[c], -nu[c] / nu[c_star]);
        constraints.set_inhomogeneity(dof, columns[0][a] / nu[c_star]);
      }
  }



  template <int dim>
  Vector<double>
  ContactCondition<dim>::dual_from_residual(
    const std::vector<bool> &active,
    const Vector<double>    &normal_residual) const
  {
    std::vector<unsigned int> active_rows;
    for (unsigned int i = 0; i < active.size(); ++i)
      if (active[i])
        active_rows.push_back(i);
    Vector<double> y(weight_rows.size());
    if (active_rows.empty())
      return y;
    std::vector<Vector<double>> rhs(1, Vector<double>(active_rows.size()));
    for (unsigned int a = 0; a < active_rows.size(); ++a)
      rhs[0][a] = normal_residual[multiplier_node[active_rows[a]]];
    solve_active_block(active_rows, rhs); // W_AA is symmetric
    for (unsigned int a = 0; a < active_rows.size(); ++a)
      y[active_rows[a]] = rhs[0][a];
    return y;
  }



  template <int dim>
  bool
  ContactCondition<dim>::set_tangential_reaction(
    const ContactBoundary<dim>   &boundary,
    const FrictionData<dim>      &friction,
    AdmissibleContactFields<dim> &fields) const
  {
    const unsigned int m = multiplier_node.size();
    AssertDimension(friction.multiplier.size(), m);
    auto &reaction = fields.tangential_reaction;
    reaction.assign(boundary.n_nodes(), Tensor<1, dim>());
    for (unsigned int c = 0; c < dim; ++c)
      {
        // (multiplier() maps y to Lambda, with -y the rows' forces)
        Vector<double> force(m);
        for (unsigned int i = 0; i < m; ++i)
          force[i] = -friction.multiplier[i][c];
        const Vector<double> lambda = multiplier(force);
        for (unsigned int i = 0; i < m; ++i)
          reaction[multiplier_node[i]][c] = lambda[i];
      }
    std::vector<bool> has_row(boundary.n_nodes(), false);
    for (unsigned int i = 0; i < m; ++i)
      has_row[multiplier_node[i]] = true;
    const bool coulomb = friction.law.type() == FrictionLaw<dim>::Type::coulomb;
    fields.friction_bound.assign(boundary.n_nodes(), 0.);
    double largest = 0., largest_change = 0.;
    for (unsigned int k = 0; k < reaction.size(); ++k)
      {
        const double bound =
          coulomb ? friction.law.coefficient() *
                      std::max(-fields.normal_reaction[k], 0.) :
          has_row[k] ? friction.law.threshold_at(boundary.node(k).position) :
                       0.;
        fields.friction_bound[k] = bound;
        const double norm        = reaction[k].norm();
        largest                  = std::max(largest, norm);
        if (norm > bound)
          {
            largest_change = std::max(largest_change, norm - bound);
            reaction[k] *= bound / norm;
          }
      }
    return largest_change > 1e-8 * largest;
  }



  template class ContactCondition<2>;
  template class ContactCondition<3>;
} // namespace Signorini
