#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/contact/rigid_motions.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace Signorini
{
  FullMatrix<double>
  null_space_of_gram(const FullMatrix<double> &gram, const double tolerance)
  {
    const unsigned int n = gram.m();
    if (n == 0)
      return FullMatrix<double>();
    LAPACKFullMatrix<double> matrix(n);
    matrix = gram;
    Vector<double>     eigenvalues;
    FullMatrix<double> eigenvectors;
    matrix.compute_eigenvalues_symmetric(
      -1e300, tolerance, 0., eigenvalues, eigenvectors);
    return eigenvectors;
  }



  template <int dim>
  Tensor<1, dim>
  RigidMotions<dim>::rigid_motion(const unsigned int k,
                                  const Point<dim>  &x) const
  {
    Tensor<1, dim> z;
    if (k < dim)
      {
        z[k] = 1.;
        return z;
      }
    // rotation in the plane (a, b): (x_a, x_b) -> (-x_b, x_a), over the
    // diameter so that all motions are of size one on the body
    static constexpr unsigned int planes[3][2] = {{0, 1}, {1, 2}, {0, 2}};
    const unsigned int   a = planes[k - dim][0], b = planes[k - dim][1];
    const Tensor<1, dim> r = (x - centre) / diameter;
    z[a]                   = -r[b];
    z[b]                   = r[a];
    return z;
  }



  template <int dim>
  void
  RigidMotions<dim>::reinit(
    const DoFHandler<dim>           &dof_handler,
    const AffineConstraints<double> &dirichlet_constraints,
    const AffineConstraints<double> &hanging_node_constraints)
  {
    const auto &triangulation = dof_handler.get_triangulation();
    // (P1: a dof lives at a vertex; every rank holds the whole mesh)
    std::vector<Point<dim>>   position(dof_handler.n_dofs());
    std::vector<unsigned int> component(dof_handler.n_dofs());
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        for (unsigned int c = 0; c < dim; ++c)
          {
            const auto dof = cell->vertex_dof_index(v, c);
            position[dof]  = cell->vertex(v);
            component[dof] = c;
          }
    const BoundingBox<dim> box(triangulation.get_vertices());
    centre = box.center();
    // the diagonal of the box, scaled by its largest side so that huge
    // coordinates do not overflow
    const auto &[low, high] = box.get_boundary_points();
    double largest          = 0;
    for (unsigned int d = 0; d < dim; ++d)
      largest = std::max(largest, high[d] - low[d]);
    double sum = 0;
    for (unsigned int d = 0; d < dim && largest > 0; ++d)
      {
        const double side = (high[d] - low[d]) / largest;
        sum += side * side;
      }
    diameter = std::max(largest * std::sqrt(sum), 1e-300);

    // Gram matrix of the rigid motions on the Dirichlet dofs; its null
    // space is the free motions.
    const IndexSet     owned = dof_handler.locally_owned_dofs();
    const MPI_Comm     comm  = dof_handler.get_communicator();
    FullMatrix<double> gram(n_rigid_motions, n_rigid_motions);
    for (const auto dof : owned)
      if (dirichlet_constraints.is_constrained(dof))
        for (unsigned int k = 0; k < n_rigid_motions; ++k)
          for (unsigned int l = 0; l < n_rigid_motions; ++l)
            gram(k, l) += rigid_motion(k, position[dof])[component[dof]] *
                          rigid_motion(l, position[dof])[component[dof]];
    Utilities::MPI::sum(gram, comm, gram);
    basis = null_space_of_gram(gram, 1e-10);

    motions.assign(n_rigid_motions, LA::Vector(owned, comm));
    for (unsigned int k = 0; k < n_rigid_motions; ++k)
      {
        for (const auto dof : owned)
          motions[k][dof] = rigid_motion(k, position[dof])[component[dof]];
        motions[k].compress(VectorOperation::insert);
      }

    modes.clear();
    for (unsigned int j = 0; j < basis.n(); ++j)
      {
        LA::Vector mode(owned, comm);
        for (const auto dof : owned)
          {
            double value = 0.;
            for (unsigned int k = 0; k < n_rigid_motions; ++k)
              value +=
                basis(k, j) * rigid_motion(k, position[dof])[component[dof]];
            mode[dof] = value;
          }
        mode.compress(VectorOperation::insert);
        modes.push_back(std::move(mode));
      }

    // Supports: greedily the dof whose row of the mode matrix is largest
    // after removing the directions already fixed (pivoted Gram-Schmidt),
    // among the dofs of the extreme vertices of the body, the same on
    // every rank.
    supports.clear();
    if (basis.n() == 0)
      return;
    std::vector<unsigned int> extreme_vertices;
    for (unsigned int d = 0; d < dim; ++d)
      for (const double sign : {-1., 1.})
        {
          unsigned int best = numbers::invalid_unsigned_int;
          for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
            if (triangulation.get_used_vertices()[v] &&
                (best == numbers::invalid_unsigned_int ||
                 sign * triangulation.get_vertices()[v][d] >
                   sign * triangulation.get_vertices()[best][d]))
              best = v;
          extreme_vertices.push_back(best);
        }
    std::vector<types::global_dof_index> candidates;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (std::find(extreme_vertices.begin(),
                      extreme_vertices.end(),
                      cell->vertex_index(v)) != extreme_vertices.end())
          for (unsigned int c = 0; c < dim; ++c)
            {
              const auto dof = cell->vertex_dof_index(v, c);
              if (!dirichlet_constraints.is_constrained(dof) &&
                  !hanging_node_constraints.is_constrained(dof) &&
                  std::find(candidates.begin(), candidates.end(), dof) ==
                    candidates.end())
                candidates.push_back(dof);
            }
    // by position and component, not by dof index: the same supports on
    // any number of ranks (the dof numbering depends on the partition)
    std::sort(candidates.begin(),
              candidates.end(),
              [&](const types::global_dof_index a,
                  const types::global_dof_index b) {
                for (unsigned int d = 0; d < dim; ++d)
                  if (position[a][d] != position[b][d])
                    return position[a][d] < position[b][d];
                return component[a] < component[b];
              });
    std::vector<Vector<double>> rows;
    for (const auto dof : candidates)
      {
        Vector<double> row(basis.n());
        for (unsigned int j = 0; j < basis.n(); ++j)
          for (unsigned int k = 0; k < n_rigid_motions; ++k)
            row[j] +=
              basis(k, j) * rigid_motion(k, position[dof])[component[dof]];
        rows.push_back(row);
      }
    std::vector<Vector<double>> fixed; // orthonormal directions fixed so far
    while (supports.size() < basis.n())
      {
        unsigned int best      = numbers::invalid_unsigned_int;
        double       best_norm = 1e-8;
        for (unsigned int i = 0; i < rows.size(); ++i)
          {
            Vector<double> r = rows[i];
            for (const auto &f : fixed)
              r.add(-(r * f), f);
            if (r.l2_norm() > best_norm)
              {
                best_norm = r.l2_norm();
                best      = i;
              }
          }
        AssertThrow(best != numbers::invalid_unsigned_int,
                    ExcMessage("no support dofs stop the free rigid motions"));
        Vector<double> r = rows[best];
        for (const auto &f : fixed)
          r.add(-(r * f), f);
        r /= r.l2_norm();
        fixed.push_back(r);
        supports.push_back(candidates[best]);
      }
  }



  template <int dim>
  unsigned int
  RigidMotions<dim>::size() const
  {
    return modes.size();
  }



  template <int dim>
  const LA::Vector &
  RigidMotions<dim>::mode(const unsigned int j) const
  {
    return modes[j];
  }



  template <int dim>
  const std::vector<LA::Vector> &
  RigidMotions<dim>::all_motions() const
  {
    return motions;
  }



  template <int dim>
  const std::vector<types::global_dof_index> &
  RigidMotions<dim>::support_dofs() const
  {
    return supports;
  }



  template <int dim>
  void
  RigidMotions<dim>::add_supports(AffineConstraints<double> &constraints) const
  {
    for (const auto dof : supports)
      constraints.add_line(dof);
  }



  template <int dim>
  std::string
  RigidMotions<dim>::describe(const Vector<double> &coefficients) const
  {
    // the motion in the basis of R^dim's rigid motions
    Vector<double> z(n_rigid_motions);
    basis.vmult(z, coefficients);
    Tensor<1, dim> translation;
    for (unsigned int d = 0; d < dim; ++d)
      translation[d] = z[d];
    double rotation = 0.;
    for (unsigned int k = dim; k < n_rigid_motions; ++k)
      rotation = std::max(rotation, std::abs(z[k]));
    const auto round = [](const double x) {
      return std::abs(x) < 1e-12 ? 0. : x;
    };
    std::ostringstream text;
    text.precision(3);
    if (rotation < 1e-8 * translation.norm())
      {
        translation /= translation.norm();
        text << "translation along (";
        for (unsigned int d = 0; d < dim; ++d)
          text << (d > 0 ? ", " : "") << round(translation[d]);
        text << ")";
      }
    else if (dim == 2)
      {
        // z(x) = t + w (x - c)^perp / L vanishes at c + L (t_y, -t_x) / w
        const double w = z[2];
        text << "rotation about (" << round(centre[0] - diameter * z[1] / w)
             << ", " << round(centre[1] + diameter * z[0] / w) << ")";
      }
    else if constexpr (dim == 3)
      {
        // z(x) = t + omega x (x - c) / L, omega from the rotations in the
        // planes (x, y), (y, z), (x, z) of rigid_motion(): a screw about
        // the axis along omega through c + L (omega x t) / |omega|^2, along
        // which it moves by (omega . t) / |omega|
        const Tensor<1, 3> omega({z[4], -z[5], z[3]});
        const Point<3>     on_axis =
          centre +
          diameter * cross_product_3d(omega, translation) / omega.norm_square();
        const Tensor<1, 3> axis = omega / omega.norm();
        text << "rotation about the axis through (" << round(on_axis[0]) << ", "
             << round(on_axis[1]) << ", " << round(on_axis[2]) << ") along ("
             << round(axis[0]) << ", " << round(axis[1]) << ", "
             << round(axis[2]) << ")";
        if (std::abs(axis * translation) > 1e-8 * translation.norm())
          text << " with a translation along it";
      }
    return text.str();
  }

  template class RigidMotions<2>;
  template class RigidMotions<3>;
} // namespace Signorini
