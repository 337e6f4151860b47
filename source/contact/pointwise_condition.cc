#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <signorini/contact/discrete_problem.h>
#include <signorini/contact/pointwise_condition.h>

#include <algorithm>

namespace Signorini
{
  namespace
  {
    /**
     * A body held only by the contact: the clipped reaction
     * R^ = min(Lambda, 0) no longer balances the load on the free rigid
     * motions N_j, and no stress is in equilibrium with it. Rescale it node
     * by node by 1 + sum_j beta_j (nu_c . N_j)(x_k), beta such that
     * N_j^T (F + forces) = 0; it stays compressive while the factors stay
     * positive (the clipped part is small next to the compressive one).
     * Updates @p normal_reaction and its nodal @p forces = M R^.
     */
    template <int dim>
    void
    balance_on_rigid_motions(const DiscreteContactProblem<dim> &problem,
                             Vector<double>                    &normal_reaction,
                             Vector<double>                    &forces)
    {
      const FullMatrix<double> normals = problem.rigid_normal_components();
      const unsigned int       r = normals.n(), n = normals.m();
      const auto              &mass = problem.boundary().mass_matrix();
      // work of the forces on the free motions, and its change per beta_l
      Vector<double> imbalance(problem.rigid_load());
      normals.Tvmult_add(imbalance, forces);
      FullMatrix<double> change(r, r);
      Vector<double>     scaled(n), scaled_forces(n);
      for (unsigned int l = 0; l < r; ++l)
        {
          for (unsigned int k = 0; k < n; ++k)
            scaled[k] = normal_reaction[k] * normals(k, l);
          mass.vmult(scaled_forces, scaled);
          for (unsigned int j = 0; j < r; ++j)
            for (unsigned int k = 0; k < n; ++k)
              change(j, l) += normals(k, j) * scaled_forces[k];
        }
      change.gauss_jordan();
      Vector<double> beta(r);
      change.vmult(beta, imbalance);
      beta *= -1.;
      for (unsigned int k = 0; k < n; ++k)
        {
          double factor = 1.;
          for (unsigned int j = 0; j < r; ++j)
            factor += beta[j] * normals(k, j);
          AssertThrow(factor >= 0.,
                      ExcMessage("the contact reaction of a body held only "
                                 "by the contact cannot be made admissible "
                                 "(Contact/Condition = pointwise: try "
                                 "integral)"));
          normal_reaction[k] *= factor;
        }
      mass.vmult(forces, normal_reaction);
    }
  } // namespace



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



  template <int dim>
  AdmissibleContactFields<dim>
  PointwiseCondition<dim>::admissible_fields(
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
      {
        fields.normal_reaction[this->multiplier_node[i]] =
          std::min(lambda[i], 0.);
        fields.positive_multipliers += (lambda[i] > 0.) ? 1 : 0;
      }
    fields.displacement              = u_h;
    fields.equilibrated_displacement = u_h;
    if (friction != nullptr)
      {
        // R^_t = M^{-1} f_t in the cone; where it was moved, or R^_n
        // clipped, U~_h answers the loads and all of R^ (nodal forces M R^;
        // friction needs the body held by its Dirichlet data)
        const bool changed =
          this->set_tangential_reaction(boundary, *friction, fields);
        // (without friction forces, mu = 0, the frictionless fields below)
        const bool frictionless =
          std::all_of(fields.tangential_reaction.begin(),
                      fields.tangential_reaction.end(),
                      [](const Tensor<1, dim> &r) { return r.norm() == 0.; });
        if (!frictionless && (changed || fields.positive_multipliers > 0))
          {
            const auto    &mass = boundary.mass_matrix();
            Vector<double> component(boundary.n_nodes()),
              forces(boundary.n_nodes());
            std::vector<std::pair<types::global_dof_index, double>> loads;
            for (unsigned int c = 0; c < dim; ++c)
              {
                for (unsigned int k = 0; k < boundary.n_nodes(); ++k)
                  component[k] =
                    fields.normal_reaction[k] * boundary.direction()[c] +
                    fields.tangential_reaction[k][c];
                mass.vmult(forces, component);
                for (unsigned int k = 0; k < boundary.n_nodes(); ++k)
                  if (forces[k] != 0.)
                    loads.emplace_back(boundary.node(k).dofs[c], forces[k]);
              }
            problem.update_preconditioner(
              std::vector<bool>(problem.n_constraints(), false));
            problem.solve_with_nodal_forces(loads,
                                            fields.equilibrated_displacement);
          }
        if (!frictionless)
          return fields;
      }
    if (fields.positive_multipliers > 0)
      {
        // nodal forces of R^: (M R^_n)_k nu_c
        Vector<double> forces(boundary.n_nodes());
        boundary.mass_matrix().vmult(forces, fields.normal_reaction);
        if (problem.n_rigid_motions() > 0)
          balance_on_rigid_motions(problem, fields.normal_reaction, forces);
        // the preconditioner is that of the last active set: rebuild it for
        // the operator without contact constraints (it saves CG iterations
        // on large meshes)
        problem.update_preconditioner(
          std::vector<bool>(problem.n_constraints(), false));
        problem.solve_with_normal_forces(forces,
                                         fields.equilibrated_displacement);
      }
    return fields;
  }

  template class PointwiseCondition<2>;
  template class PointwiseCondition<3>;

  SIGNORINI_REGISTER_TEMPLATE(ContactCondition,
                              PointwiseCondition,
                              1,
                              "pointwise",
                              "q_N <= G, [17]");
} // namespace Signorini
