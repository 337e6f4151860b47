#include <deal.II/base/parallel.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/estimator/density_enhancement.h>
#include <signorini/estimator/small_matrices.h>

#include <algorithm>

namespace Signorini
{
  namespace
  {
    /**
     * A factor B with B B^T = Z (Z^T H Z)^+ Z^T for the basis @p z and the
     * reduced Hessian @p reduced = Z^T H Z (k x k, symmetric positive
     * semi-definite): B = Z L^-T by Cholesky when it is definite, otherwise
     * B = Z V D^(-1/2) over the eigenpairs (V, D) above 1e-10 times the
     * largest.
     */
    FullMatrix<double>
    correction_factor(const FullMatrix<double> &z,
                      const FullMatrix<double> &reduced)
    {
      const unsigned int k = reduced.m();
      // Cholesky: reduced = L L^T, L lower triangular
      FullMatrix<double> l(reduced);
      const bool         definite = SmallMatrices::cholesky(l, 1e-10);
      FullMatrix<double> factor(z.m(), k);
      if (definite)
        {
          // B = Z L^-T: solve B L^T = Z row by row (forward substitution)
          for (unsigned int r = 0; r < z.m(); ++r)
            for (unsigned int j = 0; j < k; ++j)
              {
                double value = z(r, j);
                for (unsigned int p = 0; p < j; ++p)
                  value -= factor(r, p) * l(j, p);
                factor(r, j) = value / l(j, j);
              }
          return factor;
        }
      LAPACKFullMatrix<double> eigen(k, k);
      eigen = reduced;
      Vector<double>     values;
      FullMatrix<double> vectors;
      eigen.compute_eigenvalues_symmetric(-1e300, 1e300, 0., values, vectors);
      const double largest = values.size() > 0 ? values.linfty_norm() : 0.;
      for (unsigned int e = 0; e < values.size(); ++e)
        if (values[e] > 1e-10 * largest)
          for (unsigned int r = 0; r < z.m(); ++r)
            {
              double value = 0.;
              for (unsigned int j = 0; j < k; ++j)
                value += z(r, j) * vectors(j, e);
              factor(r, e) = value / std::sqrt(values[e]);
            }
      return factor;
    }
  } // namespace



  DensityEnhancement::DensityEnhancement(
    const VertexPatches                        &patches,
    const std::vector<Point<2>>                &vertices,
    const std::vector<std::array<unsigned, 2>> &edge_vertices,
    const std::vector<std::array<bool, 2>>     &free_components,
    const MPI_Comm                              communicator)
    : patches(patches)
    , vertices(vertices)
    , edge_vertices(edge_vertices)
    , free_components(free_components)
    , communicator(communicator)
  {}



  double
  DensityEnhancement::sign(const unsigned int edge,
                           const unsigned int cell) const
  {
    const Point<2>    &a       = vertices[edge_vertices[edge][0]];
    const Point<2>    &b       = vertices[edge_vertices[edge][1]];
    const Tensor<1, 2> tangent = b - a;
    const Tensor<1, 2> normal({tangent[1], -tangent[0]});
    Point<2>           center;
    for (const unsigned int vertex : patches.vertices(cell))
      center += vertices[vertex] / 3.;
    return normal * (0.5 * (a + b) - center) > 0. ? 1. : -1.;
  }



  DensityEnhancement::Patch
  DensityEnhancement::describe_patch(const unsigned int vertex) const
  {
    Patch       patch;
    const auto &cells = patches.cells_of_vertex(vertex);
    patch.positions.resize(cells.size());
    // the slots, in the order of the cells, their edges, ends and
    // components; the first slot of each edge already met
    std::vector<std::pair<unsigned int, unsigned int>> edge_start;
    for (unsigned int i = 0; i < cells.size(); ++i)
      {
        patch.positions[i].fill(-1);
        for (unsigned int e = 0; e < 3; ++e)
          {
            const unsigned int edge = patches.edges(cells[i])[e];
            if (edge_vertices[edge][0] != vertex &&
                edge_vertices[edge][1] != vertex)
              continue;
            const auto   known = std::find_if(edge_start.begin(),
                                            edge_start.end(),
                                            [edge](const auto &entry) {
                                              return entry.first == edge;
                                            });
            unsigned int position =
              known != edge_start.end() ? known->second : patch.slots.size();
            if (known == edge_start.end())
              {
                edge_start.emplace_back(edge, position);
                for (unsigned int end = 0; end < 2; ++end)
                  for (unsigned int c = 0; c < 2; ++c)
                    if (free_components[edge][c])
                      patch.slots.push_back(slot(edge, end, c));
              }
            for (unsigned int end = 0; end < 2; ++end)
              for (unsigned int c = 0; c < 2; ++c)
                if (free_components[edge][c])
                  patch.positions[i][4 * e + 2 * end + c] = position++;
          }
      }
    const unsigned int n = patch.slots.size();
    if (n == 0)
      return patch;

    // the equilibrium of each cell (resultant, moment about its centroid /
    // its diameter) for a unit value of each slot; their kernel (for an
    // interior vertex three rows are dependent: the sum of the resultants
    // and moments of the changes of shared edges vanishes)
    FullMatrix<double> constraints(3 * cells.size(), n);
    for (unsigned int i = 0; i < cells.size(); ++i)
      {
        const auto &cell_vertices = patches.vertices(cells[i]);
        Point<2>    center;
        for (const unsigned int v : cell_vertices)
          center += vertices[v] / 3.;
        double diameter = 0.;
        for (unsigned int e = 0; e < 3; ++e)
          diameter = std::max(diameter,
                              vertices[cell_vertices[e]].distance(
                                vertices[cell_vertices[(e + 1) % 3]]));
        for (unsigned int e = 0; e < 3; ++e)
          {
            const unsigned int edge = patches.edges(cells[i])[e];
            if (patch.positions[i][4 * e] < 0 &&
                patch.positions[i][4 * e + 1] < 0)
              continue;
            const double       s = sign(edge, cells[i]);
            const Tensor<1, 2> a = vertices[edge_vertices[edge][0]] - center;
            const Tensor<1, 2> b = vertices[edge_vertices[edge][1]] - center;
            const double       length = (b - a).norm();
            for (unsigned int end = 0; end < 2; ++end)
              {
                // a unit nodal value at one end, linear along the edge:
                // resultant L/2 e_c, moment L (a/3 + b/6) x e_c (end 0) or
                // L (a/6 + b/3) x e_c
                const Tensor<1, 2> arm =
                  end == 0 ? a / 3. + b / 6. : a / 6. + b / 3.;
                for (unsigned int c = 0; c < 2; ++c)
                  {
                    const int column = patch.positions[i][4 * e + 2 * end + c];
                    if (column < 0)
                      continue;
                    constraints(3 * i + c, column) = s * length / 2.;
                    constraints(3 * i + 2, column) =
                      s * length * (c == 0 ? -arm[1] : arm[0]) / diameter;
                  }
              }
          }
      }
    patch.basis = SmallMatrices::kernel_basis(constraints);
    return patch;
  }



  DensityEnhancement::Result
  DensityEnhancement::run(
    const std::function<ElementQuadratic(unsigned int)> &element_quadratic,
    const unsigned int                                   max_iterations,
    const double                                         tolerance,
    Vector<double>                                      &densities) const
  {
    const unsigned int n_cells = patches.n_cells();
    const unsigned int n_slots = densities.size();

    // the element quadratics of the needed cells, stored flat: the
    // gradients, and the upper triangles of the (symmetric) Hessians
    constexpr unsigned int packed_size = 78;
    std::vector<double>    hessians(packed_size * std::size_t(n_cells));
    std::vector<double>    gradients(12 * std::size_t(n_cells));
    parallel::apply_to_subranges(
      0u,
      n_cells,
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int cell = begin; cell < end; ++cell)
          if (patches.needed(cell))
            {
              const ElementQuadratic quadratic = element_quadratic(cell);
              double *h = &hessians[packed_size * std::size_t(cell)];
              for (unsigned int a = 0; a < 12; ++a)
                for (unsigned int b = a; b < 12; ++b)
                  *h++ = quadratic.hessian(a, b);
              std::copy(quadratic.gradient.begin(),
                        quadratic.gradient.end(),
                        gradients.begin() + 12 * std::size_t(cell));
            }
      },
      64);
    // entry (a, b) of the Hessian of a cell: position a (25 - a) / 2 + b - a
    // of the packed rows of its upper triangle
    const auto hessian_entry = [&hessians](const unsigned int cell,
                                           const unsigned int a,
                                           const unsigned int b) {
      const unsigned int i = std::min(a, b), j = std::max(a, b);
      return double(
        hessians[packed_size * std::size_t(cell) + i * (25 - i) / 2 + j - i]);
    };

    // the patches this rank computes, with the factor B_i of their
    // correction Z_i (Z_i^T H_i Z_i)^+ Z_i^T = B_i B_i^T
    std::vector<unsigned int> computed;
    for (unsigned int vertex = 0; vertex < patches.n_vertices(); ++vertex)
      if (patches.computes_patch(vertex))
        computed.push_back(vertex);
    std::vector<Patch> patch_data(computed.size());
    parallel::apply_to_subranges(
      0u,
      static_cast<unsigned int>(computed.size()),
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int p = begin; p < end; ++p)
          {
            Patch &patch = patch_data[p] = describe_patch(computed[p]);
            const unsigned int n = patch.slots.size(), k = patch.basis.n();
            if (k == 0)
              continue;
            FullMatrix<double> hessian(n, n);
            const auto        &cells = patches.cells_of_vertex(computed[p]);
            for (unsigned int i = 0; i < cells.size(); ++i)
              {
                const auto &position = patch.positions[i];
                for (unsigned int a = 0; a < 12; ++a)
                  if (position[a] >= 0)
                    for (unsigned int b = 0; b < 12; ++b)
                      if (position[b] >= 0)
                        hessian(position[a], position[b]) +=
                          hessian_entry(cells[i], a, b);
              }
            FullMatrix<double> hz(n, k), reduced(k, k);
            hessian.mmult(hz, patch.basis);
            patch.basis.Tmmult(reduced, hz);
            patch.correction = correction_factor(patch.basis, reduced);
            patch.basis      = FullMatrix<double>();
            patch.positions  = {};
          }
      },
      16);

    // the operators on full slot vectors, summed over the ranks
    const auto sum_over_ranks = [&](Vector<double> &vector) {
      if (Utilities::MPI::n_mpi_processes(communicator) > 1)
        {
          const std::vector<double> values(vector.begin(), vector.end());
          std::vector<double>       sum(values.size());
          Utilities::MPI::sum(make_array_view(values),
                              communicator,
                              make_array_view(sum));
          std::copy(sum.begin(), sum.end(), vector.begin());
        }
    };
    // y = sum over the owned cells of H_E x_E (the Hessian of J): the
    // products of the cells in parallel, then gathered slot by slot from
    // the (at most two) cells of its edge in increasing cell order
    std::vector<double> products(12 * std::size_t(n_cells));
    const auto apply_hessian = [&](const Vector<double> &x, Vector<double> &y) {
      parallel::apply_to_subranges(
        0u,
        n_cells,
        [&](const unsigned int begin, const unsigned int end) {
          std::array<double, 12> local;
          for (unsigned int cell = begin; cell < end; ++cell)
            if (patches.owned(cell))
              {
                const auto &edges = patches.edges(cell);
                for (unsigned int b = 0; b < 12; ++b)
                  local[b] = x[4 * edges[b / 4] + b % 4];
                const double *h = &hessians[packed_size * std::size_t(cell)];
                double *const product = &products[12 * std::size_t(cell)];
                std::fill(product, product + 12, 0.);
                for (unsigned int a = 0; a < 12; ++a)
                  {
                    product[a] += *h++ * local[a];
                    for (unsigned int b = a + 1; b < 12; ++b, ++h)
                      {
                        product[a] += *h * local[b];
                        product[b] += *h * local[a];
                      }
                  }
              }
        },
        256);
      y.reinit(n_slots, true);
      parallel::apply_to_subranges(
        0u,
        n_slots / 4,
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int edge = begin; edge < end; ++edge)
            {
              std::array<double, 4> sum = {{0., 0., 0., 0.}};
              for (const unsigned int cell : patches.cells_of_edge(edge))
                if (cell != numbers::invalid_unsigned_int &&
                    patches.owned(cell))
                  {
                    const auto        &edges = patches.edges(cell);
                    const unsigned int e =
                      std::find(edges.begin(), edges.end(), edge) -
                      edges.begin();
                    for (unsigned int j = 0; j < 4; ++j)
                      sum[j] += products[12 * std::size_t(cell) + 4 * e + j];
                  }
              for (unsigned int j = 0; j < 4; ++j)
                y[4 * edge + j] = sum[j];
            }
        },
        1024);
      sum_over_ranks(y);
    };
    // z = sum_i B_i B_i^T r_i (additive Schwarz): the corrections computed
    // patch by patch in parallel into one flat array, then gathered slot by
    // slot from the (at most two) patches of the slot's edge ends, in patch
    // order
    std::vector<unsigned int> offset(computed.size() + 1, 0);
    unsigned int              largest_kernel = 0;
    for (unsigned int p = 0; p < computed.size(); ++p)
      {
        offset[p + 1] = offset[p] + patch_data[p].slots.size();
        largest_kernel =
          std::max<unsigned int>(largest_kernel, patch_data[p].correction.n());
      }
    std::vector<std::array<unsigned int, 2>> slot_sources(
      n_slots,
      {{numbers::invalid_unsigned_int, numbers::invalid_unsigned_int}});
    for (unsigned int p = 0; p < computed.size(); ++p)
      for (unsigned int j = 0; j < patch_data[p].slots.size(); ++j)
        {
          auto &sources = slot_sources[patch_data[p].slots[j]];
          sources[sources[0] == numbers::invalid_unsigned_int ? 0 : 1] =
            offset[p] + j;
        }
    std::vector<double> corrections(offset.back());
    const auto precondition = [&](const Vector<double> &r, Vector<double> &z) {
      parallel::apply_to_subranges(
        0u,
        static_cast<unsigned int>(computed.size()),
        [&](const unsigned int begin, const unsigned int end) {
          std::vector<double> reduced(largest_kernel);
          for (unsigned int p = begin; p < end; ++p)
            {
              const Patch       &patch = patch_data[p];
              const unsigned int n     = patch.slots.size(),
                                 k     = patch.correction.n();
              double *const correction = corrections.data() + offset[p];
              if (k == 0)
                {
                  std::fill(correction, correction + n, 0.);
                  continue;
                }
              const unsigned int *const slots = patch.slots.data();
              const double *const       b     = &patch.correction(0, 0);
              std::fill(reduced.begin(), reduced.begin() + k, 0.);
              for (unsigned int j = 0; j < n; ++j)
                {
                  const double value = r[slots[j]];
                  for (unsigned int i = 0; i < k; ++i)
                    reduced[i] += b[k * j + i] * value;
                }
              for (unsigned int j = 0; j < n; ++j)
                {
                  double value = 0.;
                  for (unsigned int i = 0; i < k; ++i)
                    value += b[k * j + i] * reduced[i];
                  correction[j] = value;
                }
            }
        },
        64);
      z.reinit(n_slots, true);
      parallel::apply_to_subranges(
        0u,
        n_slots,
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int slot = begin; slot < end; ++slot)
            {
              const auto &sources = slot_sources[slot];
              double      value   = 0.;
              for (const unsigned int source : sources)
                if (source != numbers::invalid_unsigned_int)
                  value += corrections[source];
              z[slot] = value;
            }
        },
        4096);
      sum_over_ranks(z);
    };

    // the residual -grad J at the given densities
    Vector<double> residual(n_slots);
    for (unsigned int cell = 0; cell < n_cells; ++cell)
      if (patches.owned(cell))
        for (unsigned int a = 0; a < 12; ++a)
          residual[4 * patches.edges(cell)[a / 4] + a % 4] -=
            gradients[12 * std::size_t(cell) + a];
    sum_over_ranks(residual);

    Vector<double> preconditioned, direction, hessian_direction;
    precondition(residual, preconditioned);
    direction               = preconditioned;
    double residual_product = residual * preconditioned;
    Result result;
    while (result.iterations < max_iterations && residual_product > 0.)
      {
        apply_hessian(direction, hessian_direction);
        const double curvature = direction * hessian_direction;
        if (!(curvature > 0.))
          break;
        const double step = residual_product / curvature;
        densities.add(step, direction);
        residual.add(-step, hessian_direction);
        const double step_decrease = 0.5 * residual_product * step;
        result.decrease += step_decrease;
        ++result.iterations;
        // (a decrease at the level of round-off ends it whatever the
        // tolerance: beyond, the directions are noise that breaks the
        // equilibrium of the elements)
        if (step_decrease <= std::max(tolerance, 1e-13) * result.decrease)
          break;
        precondition(residual, preconditioned);
        const double new_product = residual * preconditioned;
        direction.sadd(new_product / residual_product, preconditioned);
        residual_product = new_product;
      }
    return result;
  }
} // namespace Signorini
