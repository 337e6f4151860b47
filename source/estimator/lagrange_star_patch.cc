#include <deal.II/base/parallel.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/table.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/estimator/lagrange_star_patch.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <map>
#include <mutex>

namespace Signorini
{
  namespace
  {
    /// The rigid motions of R^dim (dim (dim + 1) / 2): translations, then
    /// rotations; their value at @p x in component @p c.
    template <int dim>
    double
    rigid_motion(const unsigned int k,
                 const Point<dim>  &x,
                 const unsigned int c)
    {
      if (k < dim)
        return (c == k) ? 1. : 0.;
      // rotation in the plane (a, b): (x_a, x_b) -> (-x_b, x_a)
      static constexpr unsigned int planes[3][2] = {{0, 1}, {1, 2}, {0, 2}};
      const unsigned int a = planes[k - dim][0], b = planes[k - dim][1];
      return (c == a) ? -x[b] : (c == b) ? x[a] : 0.;
    }

    /// A quadrature on the faces of a cell: Gauss points on the edges of
    /// triangles, a triangle rule on those of tetrahedra.
    template <int dim>
    Quadrature<dim - 1>
    face_rule(const unsigned int n_points)
    {
      if constexpr (dim == 2)
        return QGauss<dim - 1>(n_points);
      else
        return QGaussSimplex<dim - 1>(n_points);
    }

    /// The objects the patch problems evaluate on their cells (one per
    /// range of patches a worker thread takes).
    template <int dim>
    struct Scratch
    {
      Scratch(const Mapping<dim> &mapping, const FESystem<dim> &fe)
        : hat(1)
        , quadrature(std::min(fe.degree + 1, 4u))
        , face_quadrature(face_rule<dim>(std::min(fe.degree + 1, 4u)))
        , values(mapping,
                 fe,
                 quadrature,
                 update_values | update_gradients | update_quadrature_points |
                   update_JxW_values)
        , hat_values(mapping, hat, quadrature, update_values | update_gradients)
        , face_values(mapping,
                      fe,
                      face_quadrature,
                      update_values | update_quadrature_points |
                        update_JxW_values)
        , hat_face_values(mapping, hat, face_quadrature, update_values)
      {}

      const FE_SimplexP<dim>    hat;
      const QGaussSimplex<dim>  quadrature;
      const Quadrature<dim - 1> face_quadrature;
      FEValues<dim>             values;
      FEValues<dim>             hat_values;
      FEFaceValues<dim>         face_values;
      FEFaceValues<dim>         hat_face_values;
    };
  } // namespace



  template <int dim>
  StarPatchDefects
  compute_lagrange_star_patch(const EquilibrationInput<dim> &input,
                              const LA::Vector  &admissible_displacement,
                              const unsigned int degree,
                              Vector<double>    &error_squared,
                              Vector<double>    &sum_squared)
  {
    const auto &triangulation = input.dof_handler.get_triangulation();
    AssertThrow(!triangulation.has_hanging_nodes(),
                ExcMessage("the star-patch equilibration needs a conforming "
                           "mesh"));
    const unsigned int n_cells = triangulation.n_active_cells();
    error_squared.reinit(n_cells);
    sum_squared.reinit(n_cells);

    const FESystem<dim> fe(FE_SimplexP<dim>(degree), dim);
    DoFHandler<dim>     dofs(triangulation);
    dofs.distribute_dofs(fe);
    const unsigned int n       = fe.n_dofs_per_cell();
    const auto         p1_cell = [&](const auto &cell) {
      return typename DoFHandler<dim>::active_cell_iterator(&triangulation,
                                                            cell->level(),
                                                            cell->index(),
                                                            &input.dof_handler);
    };

    // the nodes of the Dirichlet components. A node lies on face f of the
    // reference simplex where the barycentric coordinate of the vertex
    // opposite f vanishes (deal.II 9.4's has_support_on_face() is true for
    // every node of FE_SimplexP on tetrahedra)
    const auto    &reference = fe.reference_cell();
    const auto     support   = fe.get_unit_support_points();
    Table<2, bool> on_face(reference.n_faces(), n);
    for (const unsigned int f : reference.face_indices())
      {
        std::vector<bool> in_face(dim + 1, false);
        for (unsigned int v = 0; v < dim; ++v)
          in_face[reference.face_to_cell_vertices(f, v, 1)] = true;
        const unsigned int opposite =
          std::find(in_face.begin(), in_face.end(), false) - in_face.begin();
        for (unsigned int j = 0; j < n; ++j)
          {
            double coordinate = 1.;
            for (unsigned int d = 0; d < dim; ++d)
              coordinate -= support[j][d];
            if (opposite > 0)
              coordinate = support[j][opposite - 1];
            on_face(f, j) = std::abs(coordinate) < 1e-12;
          }
      }
    std::vector<bool>                    fixed(dofs.n_dofs(), false);
    std::vector<types::global_dof_index> cell_dof_indices(n);
    for (const auto &cell : dofs.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const ComponentMask mask = input.boundary_conditions.dirichlet_mask(
              cell->face(f)->boundary_id());
            if (mask.n_selected_components(dim) == 0)
              continue;
            cell->get_dof_indices(cell_dof_indices);
            for (unsigned int j = 0; j < n; ++j)
              if (on_face(f, j) && mask[fe.system_to_component_index(j).first])
                fixed[cell_dof_indices[j]] = true;
          }

    // the nodes' positions and components, for the rigid motions
    std::map<types::global_dof_index, Point<dim>> node_positions;
    DoFTools::map_dofs_to_support_points(input.mapping, dofs, node_positions);
    std::vector<unsigned int> node_component(dofs.n_dofs());
    for (const auto &cell : dofs.active_cell_iterators())
      {
        cell->get_dof_indices(cell_dof_indices);
        for (unsigned int j = 0; j < n; ++j)
          node_component[cell_dof_indices[j]] =
            fe.system_to_component_index(j).first;
      }

    // the patches this rank needs: those of the vertices of its cells
    std::vector<std::vector<typename DoFHandler<dim>::active_cell_iterator>>
                      cells_around(triangulation.n_vertices());
    std::vector<bool> needed_vertex(triangulation.n_vertices(), false);
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          needed_vertex[cell->vertex_index(v)] = true;
    for (const auto &cell : dofs.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (needed_vertex[cell->vertex_index(v)])
          cells_around[cell->vertex_index(v)].push_back(cell);

    // sigma_h of the displacement in FE equilibrium on the needed cells (P1:
    // constant), once for the patches that share a cell
    std::vector<SymmetricTensor<2, dim>> sigma_h_of(n_cells);
    {
      const FEValuesExtractors::Vector displacement(0);
      FEValues<dim>                    p1_values(input.mapping,
                              input.dof_handler.get_fe(),
                              QGaussSimplex<dim>(1),
                              update_gradients);
      std::vector<Tensor<2, dim>>      gradient(1);
      for (const auto &cell : dofs.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          if (needed_vertex[cell->vertex_index(v)])
            {
              p1_values.reinit(p1_cell(cell));
              p1_values[displacement].get_function_gradients(
                input.equilibrated_displacement, gradient);
              sigma_h_of[cell->active_cell_index()] =
                input.material.stress(symmetrize(gradient[0]));
              break;
            }
    }
    std::vector<unsigned int> patch_vertices;
    for (unsigned int v = 0; v < needed_vertex.size(); ++v)
      if (needed_vertex[v] && !cells_around[v].empty())
        patch_vertices.push_back(v);

    // the corrections sum_i z_i on the cells this rank owns
    std::vector<Vector<double>> corrections(n_cells);
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        corrections[cell->active_cell_index()].reinit(n);
    std::mutex       corrections_mutex;
    StarPatchDefects defects;

    const auto        &bc      = input.boundary_conditions;
    const auto        &contact = input.contact_boundary;
    const unsigned int n_rigid = dim * (dim + 1) / 2;

    const auto solve_patch = [&](const unsigned int vertex,
                                 Scratch<dim>      &scratch,
                                 StarPatchDefects  &patch_defects) {
      const auto &patch = cells_around[vertex];
      // the patch's unknowns: its free nodes, in the order met
      std::map<types::global_dof_index, unsigned int>   local;
      std::vector<types::global_dof_index>              constrained;
      std::vector<types::global_dof_index>              cell_dofs(n);
      std::vector<std::vector<types::global_dof_index>> patch_dofs;
      for (const auto &cell : patch)
        {
          cell->get_dof_indices(cell_dofs);
          patch_dofs.push_back(cell_dofs);
          for (const auto i : cell_dofs)
            if (fixed[i])
              constrained.push_back(i);
            else
              local.emplace(i, local.size());
        }
      std::sort(constrained.begin(), constrained.end());
      constrained.erase(std::unique(constrained.begin(), constrained.end()),
                        constrained.end());
      const unsigned int m = local.size();
      if (m == 0)
        return; // every node of the patch is fixed: z_i = 0

      FullMatrix<double>                       matrix(m, m);
      Vector<double>                           rhs(m);
      std::array<double, dim>                  galerkin{}, galerkin_scale{};
      std::array<types::global_dof_index, dim> vertex_dofs{};
      const FEValuesExtractors::Vector         displacement(0);
      std::vector<Vector<double>> body_force(scratch.quadrature.size(),
                                             Vector<double>(dim));
      std::vector<Vector<double>> traction;
      for (unsigned int e = 0; e < patch.size(); ++e)
        {
          const auto  &cell = patch[e];
          unsigned int a    = 0; // the patch's vertex in this cell
          while (cell->vertex_index(a) != vertex)
            ++a;
          scratch.values.reinit(cell);
          scratch.hat_values.reinit(
            typename Triangulation<dim>::cell_iterator(cell));
          const auto &fe_values = scratch.values;
          const auto &hat       = scratch.hat_values;

          const SymmetricTensor<2, dim> &sigma_h =
            sigma_h_of[cell->active_cell_index()];
          if (e == 0)
            for (unsigned int c = 0; c < dim; ++c)
              vertex_dofs[c] =
                patch_dofs[e][fe.component_to_system_index(c, a)];
          if (bc.body_force)
            bc.body_force->vector_value_list(fe_values.get_quadrature_points(),
                                             body_force);

          std::vector<unsigned int> index(n);
          for (unsigned int j = 0; j < n; ++j)
            {
              const auto it = local.find(patch_dofs[e][j]);
              index[j] = (it == local.end()) ? numbers::invalid_unsigned_int :
                                               it->second;
            }

          for (const unsigned int q : fe_values.quadrature_point_indices())
            {
              const double JxW = fe_values.JxW(q);
              for (unsigned int j = 0; j < n; ++j)
                {
                  if (index[j] == numbers::invalid_unsigned_int)
                    continue;
                  const auto [c, node] = fe.system_to_component_index(j);
                  // v_j - Pi_h v_j: the P1 interpolant is the hat of the
                  // node's vertex for a vertex node, zero otherwise
                  double         w      = fe_values.shape_value(j, q);
                  Tensor<1, dim> grad_w = fe_values.shape_grad(j, q);
                  if (node <= dim)
                    {
                      w -= hat.shape_value(node, q);
                      grad_w -= hat.shape_grad(node, q);
                    }
                  // phi_i (v - Pi_h v)
                  const Tensor<1, dim> g =
                    w * hat.shape_grad(a, q) + hat.shape_value(a, q) * grad_w;
                  double value = 0.;
                  for (unsigned int d = 0; d < dim; ++d)
                    value -= sigma_h[c][d] * g[d];
                  if (bc.body_force)
                    value += body_force[q][c] * hat.shape_value(a, q) * w;
                  rhs[index[j]] += value * JxW;
                  // the stiffness
                  const SymmetricTensor<2, dim> strain_j =
                    fe_values[displacement].symmetric_gradient(j, q);
                  const SymmetricTensor<2, dim> stress_j =
                    input.material.stress(strain_j);
                  for (unsigned int k = 0; k < n; ++k)
                    if (index[k] != numbers::invalid_unsigned_int)
                      matrix(index[j], index[k]) +=
                        stress_j *
                        fe_values[displacement].symmetric_gradient(k, q) * JxW;
                }
              // R(phi_i e_c)
              for (unsigned int c = 0; c < dim; ++c)
                {
                  double stress_term = 0.;
                  for (unsigned int d = 0; d < dim; ++d)
                    stress_term += sigma_h[c][d] * hat.shape_grad(a, q)[d];
                  const double term =
                    -stress_term * JxW +
                    (bc.body_force ?
                       body_force[q][c] * hat.shape_value(a, q) * JxW :
                       0.);
                  galerkin[c] += term;
                  galerkin_scale[c] += std::abs(term);
                }
            }

          // the loads on the cell's boundary faces: F_d and R^ = R^_n nu_c
          for (const unsigned int f : cell->face_indices())
            {
              const auto face = cell->face(f);
              if (!face->at_boundary())
                continue;
              const auto id         = face->boundary_id();
              const bool loaded     = bc.has_traction(id);
              const bool in_contact = contact.boundary_ids().count(id) != 0;
              if (!loaded && !in_contact)
                continue;
              scratch.face_values.reinit(cell, f);
              scratch.hat_face_values.reinit(
                typename Triangulation<dim>::cell_iterator(cell), f);
              const auto &face_values = scratch.face_values;
              const auto &hat_face    = scratch.hat_face_values;
              if (loaded)
                bc.traction_values(id,
                                   face_values.get_quadrature_points(),
                                   traction);
              for (const unsigned int q :
                   face_values.quadrature_point_indices())
                {
                  Tensor<1, dim> load;
                  if (loaded)
                    for (unsigned int c = 0; c < dim; ++c)
                      load[c] = traction[q][c];
                  if (in_contact)
                    {
                      for (const unsigned int v : face->vertex_indices())
                        for (const unsigned int w : cell->vertex_indices())
                          if (cell->vertex_index(w) == face->vertex_index(v))
                            load += input.contact_reaction(contact.node_index(
                                      cell->vertex_index(w))) *
                                    hat_face.shape_value(w, q);
                    }
                  const double JxW = face_values.JxW(q);
                  for (unsigned int j = 0; j < n; ++j)
                    {
                      if (index[j] == numbers::invalid_unsigned_int)
                        continue;
                      const auto [c, node] = fe.system_to_component_index(j);
                      double w             = face_values.shape_value(j, q);
                      if (node <= dim)
                        w -= hat_face.shape_value(node, q);
                      rhs[index[j]] +=
                        load[c] * hat_face.shape_value(a, q) * w * JxW;
                    }
                  for (unsigned int c = 0; c < dim; ++c)
                    {
                      const double term =
                        load[c] * hat_face.shape_value(a, q) * JxW;
                      galerkin[c] += term;
                      galerkin_scale[c] += std::abs(term);
                    }
                }
            }
        }

      // R(phi_i e_c) = 0 for the components free at the vertex (relative
      // to the largest term of all patches, below)
      for (unsigned int c = 0; c < dim; ++c)
        {
          if (!fixed[vertex_dofs[c]])
            patch_defects.galerkin =
              std::max(patch_defects.galerkin, std::abs(galerkin[c]));
          patch_defects.galerkin_scale =
            std::max(patch_defects.galerkin_scale, galerkin_scale[c]);
        }

      // the rigid motions vanishing at the Dirichlet nodes: the kernel
      FullMatrix<double> kernel(m, 0);
      {
        // (about the vertex, in units of the patch size: well scaled)
        const Point<dim> centre = triangulation.get_vertices()[vertex];
        const double     size   = patch.front()->diameter();
        const auto       motion = [&](const unsigned int            k,
                                const types::global_dof_index i) {
          return rigid_motion<dim>(k,
                                   Point<dim>((node_positions.at(i) - centre) /
                                              size),
                                   node_component[i]);
        };
        LAPACKFullMatrix<double> at_fixed(
          std::max<std::size_t>(constrained.size(), 1), n_rigid);
        for (unsigned int r = 0; r < constrained.size(); ++r)
          for (unsigned int k = 0; k < n_rigid; ++k)
            at_fixed(r, k) = motion(k, constrained[r]);
        // the right singular vectors of (nearly) zero singular values
        std::vector<Vector<double>> null_space;
        if (constrained.empty())
          for (unsigned int k = 0; k < n_rigid; ++k)
            {
              null_space.emplace_back(n_rigid);
              null_space.back()[k] = 1.;
            }
        else
          {
            at_fixed.compute_svd();
            const LAPACKFullMatrix<double> &vt = at_fixed.get_svd_vt();
            const unsigned int              n_values =
              std::min<unsigned int>(constrained.size(), n_rigid);
            const double largest = at_fixed.singular_value(0);
            for (unsigned int k = 0; k < n_rigid; ++k)
              if (k >= n_values || at_fixed.singular_value(k) <= 1e-8 * largest)
                {
                  null_space.emplace_back(n_rigid);
                  for (unsigned int l = 0; l < n_rigid; ++l)
                    null_space.back()[l] = vt(k, l);
                }
          }
        kernel.reinit(m, null_space.size());
        for (const auto &[i, row] : local)
          for (unsigned int k = 0; k < null_space.size(); ++k)
            for (unsigned int l = 0; l < n_rigid; ++l)
              kernel(row, k) += null_space[k][l] * motion(l, i);
      }

      for (unsigned int k = 0; k < kernel.n(); ++k)
        {
          double norm = 0.;
          for (unsigned int i = 0; i < m; ++i)
            norm += kernel(i, k) * kernel(i, k);
          // (not zero: a rigid motion vanishing at every node is zero)
          for (unsigned int i = 0; i < m; ++i)
            kernel(i, k) /= std::sqrt(norm);
        }

      // definite on the kernel (on which the data vanish), then Cholesky
      LAPACKFullMatrix<double> definite(m, m);
      double                   scale = 0.;
      for (unsigned int i = 0; i < m; ++i)
        scale = std::max(scale, matrix(i, i));
      for (unsigned int i = 0; i < m; ++i)
        for (unsigned int j = 0; j < m; ++j)
          {
            double value = matrix(i, j);
            for (unsigned int k = 0; k < kernel.n(); ++k)
              value += scale * kernel(i, k) * kernel(j, k);
            definite(i, j) = value;
          }
      definite.set_property(LAPACKSupport::symmetric);
      definite.compute_cholesky_factorization();
      Vector<double> z(rhs);
      definite.solve(z);
      Vector<double> residual(m);
      matrix.vmult(residual, z);
      residual -= rhs;
      if (rhs.l2_norm() > 0.)
        patch_defects.equilibrium =
          std::max(patch_defects.equilibrium,
                   residual.l2_norm() / rhs.l2_norm());

      // add z_i to the corrections of the owned cells
      std::lock_guard<std::mutex> lock(corrections_mutex);
      for (unsigned int e = 0; e < patch.size(); ++e)
        if (patch[e]->is_locally_owned())
          {
            Vector<double> &correction =
              corrections[patch[e]->active_cell_index()];
            for (unsigned int j = 0; j < n; ++j)
              {
                const auto it = local.find(patch_dofs[e][j]);
                if (it != local.end())
                  correction[j] += z[it->second];
              }
          }
    };

    // the patches, on the worker threads (each range with its own scratch)
    std::mutex defects_mutex;
    parallel::apply_to_subranges(
      0u,
      static_cast<unsigned int>(patch_vertices.size()),
      [&](const unsigned int begin, const unsigned int end) {
        Scratch<dim>     scratch(input.mapping, fe);
        StarPatchDefects range_defects;
        for (unsigned int p = begin; p < end; ++p)
          solve_patch(patch_vertices[p], scratch, range_defects);
        std::lock_guard<std::mutex> lock(defects_mutex);
        defects.equilibrium =
          std::max(defects.equilibrium, range_defects.equilibrium);
        defects.galerkin = std::max(defects.galerkin, range_defects.galerkin);
        defects.galerkin_scale =
          std::max(defects.galerkin_scale, range_defects.galerkin_scale);
      },
      64);

    // sigma^ = sigma_h + K eps(sum z_i) and the terms of e [14] per cell
    Scratch<dim>                     scratch(input.mapping, fe);
    const FEValuesExtractors::Vector displacement(0);
    FEValues<dim>                    p1_values(input.mapping,
                            input.dof_handler.get_fe(),
                            scratch.quadrature,
                            update_gradients);
    std::vector<Tensor<2, dim>> grad_equilibrated(scratch.quadrature.size()),
      grad_admissible(scratch.quadrature.size());
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          scratch.values.reinit(cell);
          p1_values.reinit(p1_cell(cell));
          p1_values[displacement].get_function_gradients(
            input.equilibrated_displacement, grad_equilibrated);
          p1_values[displacement].get_function_gradients(
            admissible_displacement, grad_admissible);
          const Vector<double> &z     = corrections[cell->active_cell_index()];
          double                error = 0., sum = 0.;
          for (const unsigned int q : scratch.values.quadrature_point_indices())
            {
              SymmetricTensor<2, dim> strain_z;
              for (unsigned int j = 0; j < n; ++j)
                strain_z +=
                  z[j] * scratch.values[displacement].symmetric_gradient(j, q);
              const SymmetricTensor<2, dim> hat_strain =
                symmetrize(grad_equilibrated[q]) + strain_z;
              const SymmetricTensor<2, dim> d =
                hat_strain - symmetrize(grad_admissible[q]);
              const SymmetricTensor<2, dim> s =
                hat_strain + symmetrize(grad_admissible[q]);
              error += input.material.stress(d) * d * scratch.values.JxW(q);
              sum += input.material.stress(s) * s * scratch.values.JxW(q);
            }
          error_squared[cell->active_cell_index()] = error;
          sum_squared[cell->active_cell_index()]   = sum;
        }
    if (defects.galerkin_scale > 0.)
      defects.galerkin /= defects.galerkin_scale;
    return defects;
  }

  template StarPatchDefects
  compute_lagrange_star_patch<2>(const EquilibrationInput<2> &,
                                 const LA::Vector &,
                                 const unsigned int,
                                 Vector<double> &,
                                 Vector<double> &);
  template StarPatchDefects
  compute_lagrange_star_patch<3>(const EquilibrationInput<3> &,
                                 const LA::Vector &,
                                 const unsigned int,
                                 Vector<double> &,
                                 Vector<double> &);
} // namespace Signorini
