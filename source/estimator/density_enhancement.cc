#include <deal.II/base/parallel.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/estimator/density_enhancement.h>

#include <algorithm>

namespace Signorini
{
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



  FullMatrix<double>
  DensityEnhancement::equilibrium_rows(
    const unsigned int               cell,
    const std::vector<unsigned int> &slots) const
  {
    Point<2> center;
    for (const unsigned int vertex : patches.vertices(cell))
      center += vertices[vertex] / 3.;
    const auto &edges    = patches.edges(cell);
    double      diameter = 0.;
    for (const unsigned int edge : edges)
      diameter = std::max(diameter,
                          vertices[edge_vertices[edge][0]].distance(
                            vertices[edge_vertices[edge][1]]));

    FullMatrix<double> rows(3, slots.size());
    for (unsigned int column = 0; column < slots.size(); ++column)
      {
        const unsigned int edge = slots[column] / 4,
                           end = (slots[column] % 4) / 2, c = slots[column] % 2;
        if (std::find(edges.begin(), edges.end(), edge) == edges.end())
          continue;
        const double       s      = sign(edge, cell);
        const Tensor<1, 2> a      = vertices[edge_vertices[edge][0]] - center;
        const Tensor<1, 2> b      = vertices[edge_vertices[edge][1]] - center;
        const double       length = (b - a).norm();
        // a unit nodal value at one end, linear along the edge: resultant
        // L/2 e_c, moment L (a/3 + b/6) x e_c (end 0) or L (a/6 + b/3) x e_c
        const Tensor<1, 2> arm = end == 0 ? a / 3. + b / 6. : a / 6. + b / 3.;
        rows(c, column)        = s * length / 2.;
        rows(2, column) = s * length * (c == 0 ? -arm[1] : arm[0]) / diameter;
      }
    return rows;
  }



  DensityEnhancement::Patch
  DensityEnhancement::describe_patch(const unsigned int vertex) const
  {
    Patch       patch;
    const auto &cells = patches.cells_of_vertex(vertex);
    for (const unsigned int cell : cells)
      for (const unsigned int edge : patches.edges(cell))
        if (edge_vertices[edge][0] == vertex ||
            edge_vertices[edge][1] == vertex)
          for (unsigned int end = 0; end < 2; ++end)
            for (unsigned int c = 0; c < 2; ++c)
              if (free_components[edge][c] &&
                  std::find(patch.slots.begin(),
                            patch.slots.end(),
                            slot(edge, end, c)) == patch.slots.end())
                patch.slots.push_back(slot(edge, end, c));
    const unsigned int n = patch.slots.size();
    if (n == 0)
      return patch;

    // the kernel of the equilibrium rows of all cells of the patch, by SVD
    // (for an interior vertex three rows are dependent: the sum of the
    // resultants and moments of the changes of shared edges vanishes)
    LAPACKFullMatrix<double> constraints(
      std::max<unsigned int>(3 * cells.size(), n), n);
    for (unsigned int i = 0; i < cells.size(); ++i)
      {
        const FullMatrix<double> rows = equilibrium_rows(cells[i], patch.slots);
        for (unsigned int r = 0; r < 3; ++r)
          for (unsigned int j = 0; j < n; ++j)
            constraints(3 * i + r, j) = rows(r, j);
      }
    constraints.compute_svd();
    double largest = 0.;
    for (unsigned int i = 0; i < n; ++i)
      largest = std::max(largest, constraints.singular_value(i));
    unsigned int rank = 0;
    for (unsigned int i = 0; i < n; ++i)
      rank += (constraints.singular_value(i) > 1e-10 * largest) ? 1 : 0;
    const auto &right_vectors = constraints.get_svd_vt();
    patch.basis.reinit(n, n - rank);
    for (unsigned int k = rank; k < n; ++k)
      for (unsigned int j = 0; j < n; ++j)
        patch.basis(j, k - rank) = right_vectors(k, j);
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

    // the element quadratics of the needed cells
    std::vector<ElementQuadratic> quadratics(n_cells);
    parallel::apply_to_subranges(
      0u,
      n_cells,
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int cell = begin; cell < end; ++cell)
          if (patches.needed(cell))
            quadratics[cell] = element_quadratic(cell);
      },
      64);

    // the patches this rank computes, with the pseudo-inverse of their
    // reduced Hessian Z^T H_i Z
    std::vector<unsigned int> computed;
    for (unsigned int vertex = 0; vertex < patches.n_vertices(); ++vertex)
      if (patches.computes_patch(vertex))
        computed.push_back(vertex);
    std::vector<Patch>              patch_data(computed.size());
    std::vector<FullMatrix<double>> reduced_inverse(computed.size());
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
            for (const unsigned int cell : patches.cells_of_vertex(computed[p]))
              {
                // the patch position of each of the cell's 12 values
                std::array<int, 12> position;
                for (unsigned int e = 0; e < 3; ++e)
                  for (unsigned int j = 0; j < 4; ++j)
                    {
                      const auto found =
                        std::find(patch.slots.begin(),
                                  patch.slots.end(),
                                  4 * patches.edges(cell)[e] + j);
                      position[4 * e + j] =
                        found == patch.slots.end() ?
                          -1 :
                          static_cast<int>(found - patch.slots.begin());
                    }
                for (unsigned int a = 0; a < 12; ++a)
                  for (unsigned int b = 0; b < 12; ++b)
                    if (position[a] >= 0 && position[b] >= 0)
                      hessian(position[a], position[b]) +=
                        quadratics[cell].hessian(a, b);
              }
            FullMatrix<double> hz(n, k), reduced(k, k);
            hessian.mmult(hz, patch.basis);
            patch.basis.Tmmult(reduced, hz);
            LAPACKFullMatrix<double> inverse(k, k);
            inverse = reduced;
            // deal.II 9.4 drops the singular values below threshold times
            // the largest (its documentation says the reciprocal)
            inverse.compute_inverse_svd(1e-10);
            // the entries are not readable after compute_inverse_svd():
            // apply it to the unit vectors
            reduced_inverse[p].reinit(k, k);
            Vector<double> unit(k), column(k);
            for (unsigned int j = 0; j < k; ++j)
              {
                unit    = 0.;
                unit[j] = 1.;
                inverse.vmult(column, unit);
                for (unsigned int i = 0; i < k; ++i)
                  reduced_inverse[p](i, j) = column[i];
              }
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
    // y = sum over the owned cells of H_E x_E (the Hessian of J)
    const auto apply_hessian = [&](const Vector<double> &x, Vector<double> &y) {
      y.reinit(n_slots);
      for (unsigned int cell = 0; cell < n_cells; ++cell)
        if (patches.owned(cell))
          {
            const auto &edges = patches.edges(cell);
            for (unsigned int a = 0; a < 12; ++a)
              {
                double value = 0.;
                for (unsigned int b = 0; b < 12; ++b)
                  value += quadratics[cell].hessian(a, b) *
                           x[4 * edges[b / 4] + b % 4];
                y[4 * edges[a / 4] + a % 4] += value;
              }
          }
      sum_over_ranks(y);
    };
    // z = sum_i Z_i (Z_i^T H_i Z_i)^+ Z_i^T r_i (additive Schwarz), the
    // patch corrections in one flat array (no allocation per iteration)
    std::vector<unsigned int> offset(computed.size() + 1, 0);
    for (unsigned int p = 0; p < computed.size(); ++p)
      offset[p + 1] = offset[p] + patch_data[p].slots.size();
    std::vector<double> corrections(offset.back());
    const auto precondition = [&](const Vector<double> &r, Vector<double> &z) {
      parallel::apply_to_subranges(
        0u,
        static_cast<unsigned int>(computed.size()),
        [&](const unsigned int begin, const unsigned int end) {
          std::vector<double> reduced, step;
          for (unsigned int p = begin; p < end; ++p)
            {
              const Patch       &patch = patch_data[p];
              const unsigned int n = patch.slots.size(), k = patch.basis.n();
              double *const      correction = corrections.data() + offset[p];
              std::fill(correction, correction + n, 0.);
              if (k == 0)
                continue;
              reduced.assign(k, 0.);
              step.assign(k, 0.);
              for (unsigned int j = 0; j < n; ++j)
                for (unsigned int i = 0; i < k; ++i)
                  reduced[i] += patch.basis(j, i) * r[patch.slots[j]];
              for (unsigned int i = 0; i < k; ++i)
                for (unsigned int l = 0; l < k; ++l)
                  step[i] += reduced_inverse[p](i, l) * reduced[l];
              for (unsigned int j = 0; j < n; ++j)
                for (unsigned int i = 0; i < k; ++i)
                  correction[j] += patch.basis(j, i) * step[i];
            }
        },
        64);
      z.reinit(n_slots);
      for (unsigned int p = 0; p < computed.size(); ++p)
        for (unsigned int j = 0; j < patch_data[p].slots.size(); ++j)
          z[patch_data[p].slots[j]] += corrections[offset[p] + j];
      sum_over_ranks(z);
    };

    // the residual -grad J at the given densities
    Vector<double> residual(n_slots);
    for (unsigned int cell = 0; cell < n_cells; ++cell)
      if (patches.owned(cell))
        for (unsigned int a = 0; a < 12; ++a)
          residual[4 * patches.edges(cell)[a / 4] + a % 4] -=
            quadratics[cell].gradient[a];
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
        if (step_decrease <= tolerance * result.decrease)
          break;
        precondition(residual, preconditioned);
        const double new_product = residual * preconditioned;
        direction.sadd(new_product / residual_product, preconditioned);
        residual_product = new_product;
      }
    return result;
  }
} // namespace Signorini
