#include <signorini/contact/discrete_problem.h>

namespace Signorini
{
  template <int dim>
  DiscreteContactProblem<dim>::DiscreteContactProblem(
    const LA::SparseMatrix          &stiffness,
    const LA::Vector                &load,
    const AffineConstraints<double> &constraints,
    const AffineConstraints<double> &homogeneous_constraints,
    const AffineConstraints<double> &hanging_node_constraints,
    const ContactBoundary<dim>      &boundary,
    const ContactCondition<dim>     &condition,
    ElasticitySolver                &linear_solver)
    : stiffness_matrix(stiffness)
    , load_vector(load)
    , base_constraints(constraints)
    , homogeneous_base_constraints(homogeneous_constraints)
    , hanging_node_constraints(hanging_node_constraints)
    , contact_boundary(boundary)
    , contact_condition(condition)
    , linear_solver(linear_solver)
  {}



  template <int dim>
  unsigned int
  DiscreteContactProblem<dim>::n_constraints() const
  {
    return contact_condition.n_constraints();
  }



  template <int dim>
  Vector<double>
  DiscreteContactProblem<dim>::constraint_values(const LA::Vector &u) const
  {
    return contact_condition.constraint_values(
      contact_boundary.normal_components(u));
  }



  template <int dim>
  Vector<double>
  DiscreteContactProblem<dim>::slack(const LA::Vector &u) const
  {
    Vector<double> s = contact_condition.bounds();
    if (s.size() > 0)
      s -= constraint_values(u);
    return s;
  }



  template <int dim>
  const Vector<double> &
  DiscreteContactProblem<dim>::bounds() const
  {
    return contact_condition.bounds();
  }



  template <int dim>
  unsigned int
  DiscreteContactProblem<dim>::solve_with_active_set(
    const std::vector<bool> &active,
    LA::Vector              &u,
    const double             relative_tolerance) const
  {
    AffineConstraints<double> constraints;
    contact_condition.add_active_constraints(active,
                                             contact_boundary,
                                             constraints);
    constraints.merge(base_constraints,
                      AffineConstraints<double>::no_conflicts_allowed);
    constraints.close();
    return linear_solver.solve(constraints, load_vector, u, relative_tolerance);
  }



  template <int dim>
  void
  DiscreteContactProblem<dim>::update_preconditioner(
    const std::vector<bool> &active) const
  {
    const auto        &multiplier_nodes = contact_boundary.multiplier_nodes();
    const unsigned int c_star = contact_boundary.constrained_component();
    std::vector<types::global_dof_index> dofs;
    for (unsigned int i = 0; i < active.size(); ++i)
      if (active[i])
        dofs.push_back(contact_boundary.node(multiplier_nodes[i]).dofs[c_star]);
    linear_solver.update_preconditioner(dofs);
  }



  template <int dim>
  unsigned int
  DiscreteContactProblem<dim>::solve_with_dual(
    const Vector<double> &y,
    LA::Vector           &u,
    const double          relative_tolerance) const
  {
    return solve_with_normal_forces(contact_condition.nodal_forces(y),
                                    u,
                                    relative_tolerance);
  }



  template <int dim>
  unsigned int
  DiscreteContactProblem<dim>::solve_with_normal_forces(
    const Vector<double> &forces,
    LA::Vector           &u,
    const double          relative_tolerance) const
  {
    LA::Vector load(load_vector);
    if (forces.size() > 0)
      contact_boundary.add_normal_forces(forces, load);
    load.compress(VectorOperation::add);
    return linear_solver.solve(base_constraints, load, u, relative_tolerance);
  }



  template <int dim>
  unsigned int
  DiscreteContactProblem<dim>::dual_operator_column(
    const unsigned int i,
    Vector<double>    &column) const
  {
    // z = K^{-1} B^T e_i, then column = B z
    Vector<double> unit(n_constraints());
    unit[i] = -1.; // nodal_forces() returns -W^T y
    LA::Vector load(load_vector);
    load = 0.;
    contact_boundary.add_normal_forces(contact_condition.nodal_forces(unit),
                                       load);
    load.compress(VectorOperation::add);
    LA::Vector z(load_vector);
    z = 0.;
    const unsigned int iterations =
      linear_solver.solve(homogeneous_base_constraints, load, z);
    column = constraint_values(z);
    return iterations;
  }



  template <int dim>
  LA::Vector
  DiscreteContactProblem<dim>::residual(const LA::Vector &u) const
  {
    LA::Vector r(load_vector);
    stiffness_matrix.vmult(r, u);
    r.sadd(-1., 1., load_vector);
    if (hanging_node_constraints.n_constraints() > 0)
      hanging_node_constraints.condense(r);
    return r;
  }



  template <int dim>
  Vector<double>
  DiscreteContactProblem<dim>::dual_from_residual(
    const std::vector<bool> &active,
    const LA::Vector        &u) const
  {
    // rho = nu . (F - K u) at the nodes; K u + B^T y = F gives W^T y = rho
    const Vector<double> rho = contact_boundary.normal_components(residual(u));
    // F - K u = B^T y = N^T W^T y, so rho = W^T y
    return contact_condition.dual_from_residual(active, rho);
  }



  template <int dim>
  double
  DiscreteContactProblem<dim>::energy(const LA::Vector &u) const
  {
    return 0.5 * stiffness_matrix.matrix_norm_square(u) - (load_vector * u);
  }



  template <int dim>
  const ContactBoundary<dim> &
  DiscreteContactProblem<dim>::boundary() const
  {
    return contact_boundary;
  }



  template <int dim>
  const ContactCondition<dim> &
  DiscreteContactProblem<dim>::condition() const
  {
    return contact_condition;
  }



  template <int dim>
  const LA::Vector &
  DiscreteContactProblem<dim>::load() const
  {
    return load_vector;
  }



  template <int dim>
  const AffineConstraints<double> &
  DiscreteContactProblem<dim>::constraints() const
  {
    return base_constraints;
  }



  template <int dim>
  double
  DiscreteContactProblem<dim>::constraint_scale(const LA::Vector &u) const
  {
    if (n_constraints() == 0)
      return u.linfty_norm();
    double weight = 0.;
    for (unsigned int i = 0; i < n_constraints(); ++i)
      weight = std::max(weight, contact_condition.row_weight(i));
    return weight *
           std::max(u.linfty_norm(), max_norm(contact_boundary.nodal_gap()));
  }

  template class DiscreteContactProblem<2>;
} // namespace Signorini
