#include <deal.II/lac/householder.h>

#include <signorini/contact/discrete_problem.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace Signorini
{
  namespace
  {
    /**
     * Non-negative least squares (Lawson-Hanson): min |sum_i x_i a_i - t|
     * over x >= 0, for few-dimensional columns a_i (here the rows of C, of
     * size n_rigid_motions). Returns the residual t - sum_i x_i a_i: zero
     * when t lies in the cone of the a_i; otherwise a direction z with
     * a_i . z <= 0 for all i and t . z = |z|^2 > 0.
     */
    Vector<double>
    cone_residual(const std::vector<Vector<double>> &columns,
                  const Vector<double>              &target)
    {
      const unsigned int        n = target.size();
      std::vector<double>       x(columns.size(), 0.);
      std::vector<unsigned int> passive;
      Vector<double>            residual(target);
      double                    scale = target.l2_norm();
      for (const auto &a : columns)
        scale = std::max(scale, a.l2_norm());
      const double tolerance       = 1e-13 * scale * scale;
      const auto   update_residual = [&]() {
        residual = target;
        for (const unsigned int i : passive)
          residual.add(-x[i], columns[i]);
      };
      for (unsigned int step = 0; step < 10 * columns.size() + 10; ++step)
        {
          unsigned int entering = numbers::invalid_unsigned_int;
          double       best     = tolerance;
          for (unsigned int i = 0; i < columns.size(); ++i)
            if (std::find(passive.begin(), passive.end(), i) == passive.end() &&
                columns[i] * residual > best)
              {
                best     = columns[i] * residual;
                entering = i;
              }
          if (entering == numbers::invalid_unsigned_int || passive.size() >= n)
            break;
          passive.push_back(entering);
          while (true)
            {
              // unconstrained least squares on the passive columns
              FullMatrix<double> matrix(n, passive.size());
              for (unsigned int k = 0; k < passive.size(); ++k)
                for (unsigned int d = 0; d < n; ++d)
                  matrix(d, k) = columns[passive[k]][d];
              Vector<double> z(passive.size());
              Householder<double>(matrix).least_squares(z, target);
              bool   positive = true;
              double alpha    = 1.;
              for (unsigned int k = 0; k < passive.size(); ++k)
                if (z[k] <= 0.)
                  {
                    positive = false;
                    alpha =
                      std::min(alpha, x[passive[k]] / (x[passive[k]] - z[k]));
                  }
              if (positive)
                {
                  for (unsigned int k = 0; k < passive.size(); ++k)
                    x[passive[k]] = z[k];
                  break;
                }
              for (unsigned int k = 0; k < passive.size(); ++k)
                x[passive[k]] += alpha * (z[k] - x[passive[k]]);
              passive.erase(std::remove_if(passive.begin(),
                                           passive.end(),
                                           [&](const unsigned int i) {
                                             if (x[i] > 1e-14 * scale)
                                               return false;
                                             x[i] = 0.;
                                             return true;
                                           }),
                            passive.end());
            }
          update_residual();
        }
      update_residual();
      return residual;
    }
  } // namespace



  template <int dim>
  DiscreteContactProblem<dim>::DiscreteContactProblem(
    const LA::SparseMatrix          &stiffness,
    const LA::Vector                &load,
    const AffineConstraints<double> &constraints,
    const AffineConstraints<double> &homogeneous_constraints,
    const AffineConstraints<double> &hanging_node_constraints,
    const ContactBoundary<dim>      &boundary,
    const ContactCondition<dim>     &condition,
    const RigidMotions<dim>         &rigid_motions,
    ElasticitySolver                &linear_solver)
    : stiffness_matrix(stiffness)
    , load_vector(load)
    , base_constraints(constraints)
    , homogeneous_base_constraints(homogeneous_constraints)
    , hanging_node_constraints(hanging_node_constraints)
    , contact_boundary(boundary)
    , contact_condition(condition)
    , rigid_motions(rigid_motions)
    , linear_solver(linear_solver)
  {
    for (const auto i : load.locally_owned_elements())
      largest_diagonal =
        std::max(largest_diagonal, std::abs(stiffness.diag_element(i)));
    largest_diagonal =
      std::max(Utilities::MPI::max(largest_diagonal,
                                   load.get_mpi_communicator()),
               std::numeric_limits<double>::min());
    // (the order of doc/library.md: a problem of objects not set up gave no
    // contact at all, or a crash later)
    if (!boundary.is_reinitialised())
      throw std::invalid_argument(
        "DiscreteContactProblem: call ContactBoundary::reinit() first");
    if (condition.n_boundary_nodes() != boundary.n_nodes() ||
        condition.n_constraints() != boundary.multiplier_nodes().size())
      throw std::invalid_argument(
        "DiscreteContactProblem: the contact condition was not built for "
        "this contact boundary (" +
        std::to_string(condition.n_constraints()) + " rows for " +
        std::to_string(boundary.multiplier_nodes().size()) +
        " multiplier nodes): call ContactCondition::reinit() after "
        "ContactBoundary::reinit()");
    check_constraints_and_matrix();
    const unsigned int r = rigid_motions.size();
    if (r == 0)
      return;
    for (auto [supported, base] :
         {std::make_pair(&supported_constraints, &base_constraints),
          std::make_pair(&homogeneous_supported_constraints,
                         &homogeneous_base_constraints)})
      {
        supported->clear();
        supported->merge(*base);
        rigid_motions.add_supports(*supported);
        supported->close();
      }
    rigid_rows.reinit(n_constraints(), r);
    rigid_load_vector.reinit(r);
    for (unsigned int j = 0; j < r; ++j)
      {
        const Vector<double> column = constraint_values(rigid_motions.mode(j));
        for (unsigned int i = 0; i < n_constraints(); ++i)
          rigid_rows(i, j) = column[i];
        rigid_load_vector[j] = load_vector * rigid_motions.mode(j);
      }
  }



  template <int dim>
  void
  DiscreteContactProblem<dim>::check_constraints_and_matrix() const
  {
    // the homogeneous constraints: the same dofs, no values (their values
    // passed for them gave a wrong energy; none, CG without end)
    std::string mismatch;
    for (const auto &line : base_constraints.get_lines())
      if (!homogeneous_base_constraints.is_constrained(line.index))
        mismatch = "dof " + std::to_string(line.index) +
                   " is constrained but not in the homogeneous constraints";
      else if (homogeneous_base_constraints.is_inhomogeneously_constrained(
                 line.index))
        mismatch = "dof " + std::to_string(line.index) +
                   " has a value in the homogeneous constraints";
    for (const auto &line : homogeneous_base_constraints.get_lines())
      if (!base_constraints.is_constrained(line.index))
        mismatch = "dof " + std::to_string(line.index) +
                   " is in the homogeneous constraints only";
    // K must be the raw stiffness matrix: constraints condensed into it
    // leave the rows of the Dirichlet dofs without entries off the
    // diagonal, and the residuals and checks would be those of another
    // problem
    // (Epetra's row views: deal.II's row iterators copy each row)
    unsigned int            n_fixed = 0, n_bare = 0;
    const Epetra_CrsMatrix &matrix = stiffness_matrix.trilinos_matrix();
    for (const auto &line : base_constraints.get_lines())
      {
        const int local_row = matrix.LRID(
          static_cast<TrilinosWrappers::types::int_type>(line.index));
        if (!line.entries.empty() || local_row < 0)
          continue;
        ++n_fixed;
        int     n_entries;
        double *values;
        int    *local_columns;
        matrix.ExtractMyRowView(local_row, n_entries, values, local_columns);
        bool bare = true;
        for (int k = 0; k < n_entries; ++k)
          if (values[k] != 0. &&
              matrix.ColMap().GID(local_columns[k]) !=
                static_cast<TrilinosWrappers::types::int_type>(line.index))
            bare = false;
        n_bare += bare ? 1 : 0;
      }
    const MPI_Comm communicator = load_vector.get_mpi_communicator();
    n_fixed                     = Utilities::MPI::sum(n_fixed, communicator);
    n_bare                      = Utilities::MPI::sum(n_bare, communicator);
    const bool mismatch_anywhere =
      Utilities::MPI::max(mismatch.empty() ? 0 : 1, communicator) != 0;
    if (mismatch_anywhere)
      throw std::invalid_argument(
        "DiscreteContactProblem: the homogeneous constraints are not the "
        "constraints without their values" +
        (mismatch.empty() ? std::string(" (on another rank)") :
                            ": " + mismatch));
    if (n_fixed > 0 && n_bare == n_fixed)
      throw std::invalid_argument(
        "DiscreteContactProblem: the stiffness matrix looks condensed (no "
        "row of the " +
        std::to_string(n_fixed) +
        " dofs with Dirichlet data has an entry off the diagonal): pass the "
        "raw matrix and load, without the constraints applied");
  }



  template <int dim>
  unsigned int
  DiscreteContactProblem<dim>::n_rigid_motions() const
  {
    return rigid_motions.size();
  }



  template <int dim>
  void
  DiscreteContactProblem<dim>::check_rigid_motions() const
  {
    const unsigned int r = n_rigid_motions();
    if (r == 0)
      return;
    const unsigned int m = n_constraints();
    // the rows of C per unit of row weight: the normal motion of each
    // contact row under each free motion, of size one
    std::vector<Vector<double>> rows(m, Vector<double>(r));
    FullMatrix<double>          gram(r, r);
    for (unsigned int i = 0; i < m; ++i)
      {
        for (unsigned int j = 0; j < r; ++j)
          rows[i][j] = rigid_rows(i, j) / contact_condition.row_weight(i);
        for (unsigned int j = 0; j < r; ++j)
          for (unsigned int k = 0; k < r; ++k)
            gram(j, k) += rows[i][j] * rows[i][k];
      }
    const FullMatrix<double> unstopped =
      null_space_of_gram(gram, 1e-10 * std::max(1., 1. * m));
    if (unstopped.n() > 0)
      {
        Vector<double> motion(r);
        for (unsigned int j = 0; j < r; ++j)
          motion[j] = unstopped(j, 0);
        throw InputError(
          "the body is free to move: the " + rigid_motions.describe(motion) +
          " is prevented neither by the Dirichlet data (Boundary "
          "conditions/Dirichlet) nor by the contact (Contact/Boundary ids, "
          "Direction); prescribe that motion with a Dirichlet condition");
      }

    // C^T y = h with y >= 0 must hold for h and every nearby load: h in the
    // interior of the cone of the rows, or some free motion z with C z <= 0
    // (lifting off, or sliding) has h . z >= 0
    const double   h_norm = rigid_load_vector.l2_norm();
    Vector<double> target(rigid_load_vector);
    if (h_norm > 0.)
      target /= h_norm;
    for (unsigned int k = 0; k <= 2 * r; ++k)
      {
        Vector<double> perturbed(target);
        if (k > 0)
          perturbed[(k - 1) / 2] += ((k % 2 == 0) ? 1e-6 : -1e-6);
        const Vector<double> motion = cone_residual(rows, perturbed);
        if (motion.l2_norm() > 1e-9)
          throw InputError(
            "no equilibrium: the body is held only by the contact, and the "
            "load does not press it onto the foundation (Contact/Boundary "
            "ids, Direction): the free " +
            rigid_motions.describe(motion) +
            " moves it away from the foundation or along it without the load "
            "resisting; check the direction of the load or prescribe that "
            "motion with a Dirichlet condition");
      }
  }



  template <int dim>
  bool
  DiscreteContactProblem<dim>::blocks_rigid_motions(
    const std::vector<bool> &active) const
  {
    const unsigned int r = n_rigid_motions();
    if (r == 0)
      return true;
    FullMatrix<double> gram(r, r);
    unsigned int       n_active = 0;
    for (unsigned int i = 0; i < active.size(); ++i)
      if (active[i])
        {
          ++n_active;
          const double weight = contact_condition.row_weight(i);
          for (unsigned int j = 0; j < r; ++j)
            for (unsigned int k = 0; k < r; ++k)
              gram(j, k) +=
                rigid_rows(i, j) * rigid_rows(i, k) / (weight * weight);
        }
    return n_active > 0 &&
           null_space_of_gram(gram, 1e-10 * std::max(1., 1. * n_active)).n() ==
             0;
  }



  template <int dim>
  const FullMatrix<double> &
  DiscreteContactProblem<dim>::rigid_constraint_rows() const
  {
    return rigid_rows;
  }



  template <int dim>
  const Vector<double> &
  DiscreteContactProblem<dim>::rigid_load() const
  {
    return rigid_load_vector;
  }



  template <int dim>
  FullMatrix<double>
  DiscreteContactProblem<dim>::rigid_normal_components() const
  {
    FullMatrix<double> normals(contact_boundary.n_nodes(), n_rigid_motions());
    for (unsigned int j = 0; j < n_rigid_motions(); ++j)
      {
        const Vector<double> column =
          contact_boundary.normal_components(rigid_motions.mode(j));
        for (unsigned int k = 0; k < column.size(); ++k)
          normals(k, j) = column[k];
      }
    return normals;
  }



  template <int dim>
  void
  DiscreteContactProblem<dim>::add_rigid_motion(const Vector<double> &c,
                                                LA::Vector           &u) const
  {
    for (unsigned int j = 0; j < c.size(); ++j)
      u.add(c[j], rigid_motions.mode(j));
  }



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
  unsigned int
  DiscreteContactProblem<dim>::solve_with_friction(
    const std::vector<bool>         &active,
    const AffineConstraints<double> &stick_constraints,
    const std::vector<std::pair<types::global_dof_index, double>> &forces,
    const ElasticitySolver::Springs                               &springs,
    LA::Vector                                                    &u,
    const double relative_tolerance) const
  {
    AffineConstraints<double> constraints;
    contact_condition.add_active_constraints(active,
                                             contact_boundary,
                                             constraints);
    constraints.merge(stick_constraints,
                      AffineConstraints<double>::no_conflicts_allowed);
    constraints.merge(base_constraints,
                      AffineConstraints<double>::no_conflicts_allowed);
    constraints.close();
    return linear_solver.solve(
      constraints, load_with(forces), u, relative_tolerance, springs);
  }



  template <int dim>
  LA::Vector
  DiscreteContactProblem<dim>::load_with(
    const std::vector<std::pair<types::global_dof_index, double>> &forces) const
  {
    LA::Vector     load(load_vector);
    const IndexSet owned = load.locally_owned_elements();
    for (const auto &[dof, value] : forces)
      if (owned.is_element(dof))
        load[dof] += value;
    load.compress(VectorOperation::add);
    return load;
  }



  template <int dim>
  const AffineConstraints<double> &
  DiscreteContactProblem<dim>::free_body_constraints() const
  {
    return n_rigid_motions() > 0 ? supported_constraints : base_constraints;
  }



  template <int dim>
  void
  DiscreteContactProblem<dim>::update_preconditioner(
    const std::vector<bool>                    &active,
    const std::vector<types::global_dof_index> &fixed_dofs,
    const ElasticitySolver::Springs            &springs) const
  {
    const auto        &multiplier_nodes = contact_boundary.multiplier_nodes();
    const unsigned int c_star = contact_boundary.constrained_component();
    std::vector<types::global_dof_index> dofs(fixed_dofs);
    for (unsigned int i = 0; i < active.size(); ++i)
      if (active[i])
        dofs.push_back(contact_boundary.node(multiplier_nodes[i]).dofs[c_star]);
    linear_solver.update_preconditioner(dofs, springs);
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
    return linear_solver.solve(free_body_constraints(),
                               load,
                               u,
                               relative_tolerance);
  }



  template <int dim>
  unsigned int
  DiscreteContactProblem<dim>::solve_with_nodal_forces(
    const std::vector<std::pair<types::global_dof_index, double>> &forces,
    LA::Vector                                                    &u,
    const double relative_tolerance) const
  {
    return linear_solver.solve(free_body_constraints(),
                               load_with(forces),
                               u,
                               relative_tolerance);
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
      linear_solver.solve(n_rigid_motions() > 0 ?
                            homogeneous_supported_constraints :
                            homogeneous_base_constraints,
                          load,
                          z);
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
  const LA::SparseMatrix &
  DiscreteContactProblem<dim>::stiffness() const
  {
    return stiffness_matrix;
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
    return weight * std::max({u.linfty_norm(),
                              max_norm(contact_boundary.nodal_gap()),
                              force_scale() / largest_diagonal});
  }

  template <int dim>
  double
  DiscreteContactProblem<dim>::force_scale() const
  {
    double scale = load_vector.linfty_norm();
    for (const auto i : load_vector.locally_owned_elements())
      if (base_constraints.is_inhomogeneously_constrained(i))
        scale = std::max(scale,
                         std::abs(stiffness_matrix.diag_element(i) *
                                  base_constraints.get_inhomogeneity(i)));
    return Utilities::MPI::max(scale, load_vector.get_mpi_communicator());
  }

  template class DiscreteContactProblem<2>;
  template class DiscreteContactProblem<3>;
} // namespace Signorini
