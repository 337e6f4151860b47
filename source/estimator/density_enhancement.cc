#include <deal.II/base/aligned_vector.h>
#include <deal.II/base/parallel.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <signorini/estimator/density_enhancement.h>
#include <signorini/estimator/small_matrices.h>
#include <signorini/progress.h>

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



    /// Whether the columns of @p basis are a basis of the kernel of
    /// @p constraints (to round-off).
    [[maybe_unused]] bool
    is_kernel_basis(const FullMatrix<double> &constraints,
                    const FullMatrix<double> &basis)
    {
      FullMatrix<double> product(constraints.m(), basis.n());
      constraints.mmult(product, basis);
      return product.frobenius_norm() <=
               1e-10 * constraints.frobenius_norm() * basis.frobenius_norm() &&
             SmallMatrices::kernel_basis(constraints).n() == basis.n() &&
             SmallMatrices::kernel_basis(basis).n() == 0;
    }



    /**
     * The changes of the four slots (rows) of an edge of an Airy patch
     * (columns) from the rows @p at_vertex at the vertex's end @p vertex_end
     * and t = @p shift (DensityEnhancement::AiryColumns), row by row.
     */
    std::array<double, 16>
    airy_slot_changes(const std::array<double, 8> &at_vertex,
                      const double                 shift,
                      const unsigned int           vertex_end)
    {
      const unsigned int     here = 2 * vertex_end, there = 2 - here;
      std::array<double, 16> changes;
      for (unsigned int c = 0; c < 2; ++c)
        for (unsigned int i = 0; i < 4; ++i)
          {
            changes[4 * (here + c) + i]  = at_vertex[4 * c + i];
            changes[4 * (there + c) + i] = -at_vertex[4 * c + i];
          }
      changes[4 * (there + 1) + 1] += shift;
      changes[4 * there + 2] -= shift;
      return changes;
    }



    /// The floats per cell of the element Hessians as they are stored: the
    /// upper triangle, row by row (78 of the 144 entries), padded so that
    /// every cell's starts on a cache line.
    constexpr unsigned int packed_hessian_size = 80;

    /// The position of entry (@p a, @p b) of a cell's Hessian in its
    /// upper triangle, row by row.
    constexpr unsigned int
    packed_position(const unsigned int a, const unsigned int b)
    {
      // (row a starts after 12 + 11 + ... + (13 - a) entries)
      return a <= b ? a * (25 - a) / 2 + (b - a) : packed_position(b, a);
    }

    /// H x for the Hessian @p h of a cell (its upper triangle, row by row).
    inline std::array<double, 12>
    packed_product(const float *h, const std::array<double, 12> &x)
    {
      std::array<double, 12> product = {};
      for (unsigned int a = 0; a < 12; ++a)
        {
          double row_sum = double(*h++) * x[a];
          for (unsigned int b = a + 1; b < 12; ++b, ++h)
            {
              row_sum += double(*h) * x[b];
              product[b] += double(*h) * x[a];
            }
          product[a] += row_sum;
        }
      return product;
    }



    /// The concatenation of @p local of all ranks, in rank order (without
    /// deal.II's serialisation, whose compression dominated the set-up of
    /// the regions).
    template <typename Number>
    std::vector<Number>
    all_ranks(const std::vector<Number> &local, const MPI_Comm communicator)
    {
      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(communicator);
      if (n_ranks == 1)
        return local;
      const int        size = local.size();
      std::vector<int> sizes(n_ranks), offsets(n_ranks + 1, 0);
      int              ierr = MPI_Allgather(
        &size, 1, MPI_INT, sizes.data(), 1, MPI_INT, communicator);
      AssertThrowMPI(ierr);
      for (unsigned int r = 0; r < n_ranks; ++r)
        offsets[r + 1] = offsets[r] + sizes[r];
      std::vector<Number> all(offsets[n_ranks]);
      ierr = MPI_Allgatherv(local.data(),
                            size,
                            Utilities::MPI::mpi_type_id_for_type<Number>,
                            all.data(),
                            sizes.data(),
                            offsets.data(),
                            Utilities::MPI::mpi_type_id_for_type<Number>,
                            communicator);
      AssertThrowMPI(ierr);
      return all;
    }

    /**
     * Adds Z_E^T H_E Z_E of a cell of an Airy patch to @p reduced (k x k):
     * Z the patch's @p basis, @p position the patch positions of the cell's
     * 12 values (-1: not changed), H_E given entry by entry by
     * @p hessian_entry(a, b). The rows of Z of the cell's changed values have
     * their entries in columns 0, 1, 2 and 3 + j (edge j of the patch) only.
     */
    template <typename HessianEntry>
    void
    add_airy_cell_product(const std::array<int, 12> &position,
                          const FullMatrix<double>  &basis,
                          const HessianEntry        &hessian_entry,
                          FullMatrix<double>        &reduced)
    {
      // the changed values of the cell (eight: the two edges through the
      // vertex) and the columns they meet, with Z_E and H_E gathered into
      // arrays of fixed size (products with fixed bounds, no indirection)
      constexpr unsigned int                max_changed = 8, max_columns = 5;
      std::array<unsigned int, 12>          changed;
      unsigned int                          n_changed = 0;
      std::array<unsigned int, max_columns> columns   = {{0, 1, 2, 0, 0}};
      unsigned int                          n_columns = 3;
      for (unsigned int a = 0; a < 12; ++a)
        if (position[a] >= 0)
          {
            AssertIndexRange(n_changed, max_changed);
            changed[n_changed++]      = a;
            const unsigned int column = 3 + position[a] / 4;
            if (std::find(columns.begin() + 3,
                          columns.begin() + n_columns,
                          column) == columns.begin() + n_columns)
              {
                AssertIndexRange(n_columns, columns.size());
                columns[n_columns++] = column;
              }
          }
      std::array<std::array<double, max_columns>, max_changed> z = {};
      std::array<std::array<double, max_changed>, max_changed> h = {};
      for (unsigned int ia = 0; ia < n_changed; ++ia)
        {
          const unsigned int row = position[changed[ia]];
          for (unsigned int m = 0; m < n_columns; ++m)
            z[ia][m] = basis(row, columns[m]);
          for (unsigned int ib = 0; ib < n_changed; ++ib)
            h[ia][ib] = hessian_entry(changed[ia], changed[ib]);
        }
      // H_E Z_E, then Z_E^T (H_E Z_E)
      std::array<std::array<double, max_columns>, max_changed> hz = {};
      for (unsigned int ia = 0; ia < max_changed; ++ia)
        for (unsigned int ib = 0; ib < max_changed; ++ib)
          for (unsigned int m = 0; m < max_columns; ++m)
            hz[ia][m] += h[ia][ib] * z[ib][m];
      for (unsigned int l = 0; l < n_columns; ++l)
        for (unsigned int m = 0; m < n_columns; ++m)
          {
            double value = 0.;
            for (unsigned int ia = 0; ia < max_changed; ++ia)
              value += z[ia][l] * hz[ia][m];
            reduced(columns[l], columns[m]) += value;
          }
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



  std::array<double, 8>
  DensityEnhancement::AiryColumns::at_vertex(const double patch_scale) const
  {
    // with R v = (v_y, -v_x), the reference normal nu = R tau, w = 1 /
    // length and s = +1 if the vertex is end 0, -1 otherwise: grad phi at
    // the midpoint is
    //   G_m = (-3/2 s w phi - G . tau / 4) tau + (G . nu / 2 + beta) nu
    // for (phi, G = grad phi) at the vertex and beta the change of the
    // normal derivative (the cubic Hermite interpolant along the edge,
    // whose derivative integrates to the change of phi: the moment
    // balance), and the traction at the vertex's end
    //   s w R (4 G_m - 3 G)
    // (the derivative of the quadratic through the ends and the midpoint;
    // at the other end s w R (G - 4 G_m), whence the rows there)
    const double  w = inverse_length, s = vertex_end == 0 ? 1. : -1.;
    const double *tau   = tangent.data();
    const double  nu[2] = {tau[1], -tau[0]};
    // phi = 1 / patch_scale: G_m = -3/2 s w phi tau, R tau = nu
    const double phi_change = 6. * w * w / patch_scale;
    // beta = 1: G_m = nu, R nu = -tau
    const double          beta_change = 4. * s * w;
    std::array<double, 8> rows;
    for (unsigned int c = 0; c < 2; ++c)
      {
        rows[4 * c]     = -phi_change * nu[c];
        rows[4 * c + 3] = -beta_change * tau[c];
      }
    // G = e_j: 4 G_m - 3 e_j = -tau_j tau + 2 nu_j nu - 3 e_j
    for (unsigned int j = 0; j < 2; ++j)
      {
        double v[2];
        for (unsigned int c = 0; c < 2; ++c)
          v[c] = -tau[j] * tau[c] + 2. * nu[j] * nu[c] - (c == j ? 3. : 0.);
        // R v = (v_y, -v_x)
        rows[1 + j]     = s * w * v[1];
        rows[4 + 1 + j] = -s * w * v[0];
      }
    return rows;
  }



  void
  DensityEnhancement::describe_patch(const unsigned int vertex,
                                     Patch             &patch) const
  {
    const auto &cells = patches.cells_of_vertex(vertex);
    patch.slots.clear();
    patch.positions.resize(cells.size());
    // the slots, in the order of the cells, their edges, ends and
    // components; the first slot of each edge already met (work space
    // reused by each thread: allocations dominated the set-up)
    thread_local std::vector<std::pair<unsigned int, unsigned int>> edge_start;
    edge_start.clear();
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
    patch.airy_columns.clear();
    if (n == 0)
      {
        patch.basis.reinit(0, 0);
        return;
      }

    // an Airy patch: the basis written out, which costs a fraction of the
    // elimination (most patches: all interior ones)
    const bool airy = std::all_of(edge_start.begin(),
                                  edge_start.end(),
                                  [this](const auto &entry) {
                                    return free_components[entry.first][0] &&
                                           free_components[entry.first][1];
                                  });
    if (airy)
      {
        const unsigned int n_edges = edge_start.size();
        patch.basis.reinit(n, 3 + n_edges);
        double patch_scale = 0.;
        for (unsigned int j = 0; j < n_edges; ++j)
          {
            const unsigned int edge   = edge_start[j].first;
            const Point<2>    &a      = vertices[edge_vertices[edge][0]];
            const Point<2>    &b      = vertices[edge_vertices[edge][1]];
            const double       length = a.distance(b);
            AiryColumns        columns;
            columns.tangent = {
              {(b[0] - a[0]) / length, (b[1] - a[1]) / length}};
            columns.inverse_length = 1. / length;
            columns.first_slot     = slot(edge, 0, 0);
            columns.vertex_end     = edge_vertices[edge][0] == vertex ? 0 : 1;
            patch.airy_columns.push_back(columns);
            if (j == 0)
              patch_scale = columns.inverse_length;
            const std::array<double, 16> changes =
              airy_slot_changes(columns.at_vertex(patch_scale),
                                columns.shift(),
                                columns.vertex_end);
            // (the edge's slots are positions 4 j to 4 j + 3, in slot order)
            for (unsigned int row = 0; row < 4; ++row)
              {
                for (unsigned int column = 0; column < 3; ++column)
                  patch.basis(4 * j + row, column) = changes[4 * row + column];
                patch.basis(4 * j + row, 3 + j) = changes[4 * row + 3];
              }
          }
        Assert(is_kernel_basis(equilibrium_constraints(vertex, patch),
                               patch.basis),
               ExcInternalError());
        return;
      }
    patch.basis =
      SmallMatrices::kernel_basis(equilibrium_constraints(vertex, patch));
  }



  FullMatrix<double>
  DensityEnhancement::equilibrium_constraints(const unsigned int vertex,
                                              const Patch       &patch) const
  {
    const auto        &cells = patches.cells_of_vertex(vertex);
    const unsigned int n     = patch.slots.size();
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
    return constraints;
  }



  void
  DensityEnhancement::RegionCorrection::add_correction(const Vector<double> &r,
                                                       Vector<double> &z) const
  {
    Vector<double> coefficients(columns.size());
    for (unsigned int c = 0; c < columns.size(); ++c)
      for (const auto &[position, value] : columns[c])
        coefficients[c] += value * r[slots[position]];
    SmallMatrices::cholesky_solve(factor, coefficients);
    for (unsigned int c = 0; c < columns.size(); ++c)
      for (const auto &[position, value] : columns[c])
        z[slots[position]] += value * coefficients[c];
  }



  std::vector<unsigned int>
  DensityEnhancement::region_vertices(const unsigned int seed,
                                      const unsigned int rings) const
  {
    // ring by ring: each rank adds the neighbours of the vertices whose
    // patches it treats (it knows all their cells), then the union
    std::vector<unsigned int> region(1, seed);
    for (unsigned int ring = 0; ring < rings; ++ring)
      {
        std::vector<unsigned int> grown;
        for (const unsigned int vertex : region)
          if (patches.treats_patch(vertex))
            for (const unsigned int cell : patches.cells_of_vertex(vertex))
              for (const unsigned int neighbour : patches.vertices(cell))
                grown.push_back(neighbour);
        region = all_ranks(grown, communicator);
        std::sort(region.begin(), region.end());
        region.erase(std::unique(region.begin(), region.end()), region.end());
      }
    return region;
  }



  DensityEnhancement::RegionCorrection
  DensityEnhancement::describe_region(
    const std::vector<unsigned int> &region,
    const ArrayView<const float>    &hessians,
    const ArrayView<const double>   &hessian_scales) const
  {
    // the columns of the patches this rank computes, flat: vertex, edge of
    // the column (the normal derivative of an Airy patch's edge) or -1,
    // number of entries, then (slot, value) pairs
    std::vector<double> local_columns;
    Patch               patch;
    for (const unsigned int vertex : region)
      if (patches.computes_patch(vertex))
        {
          describe_patch(vertex, patch);
          for (unsigned int c = 0; c < patch.basis.n(); ++c)
            {
              local_columns.push_back(vertex);
              local_columns.push_back(
                !patch.airy_columns.empty() && c >= 3 ?
                  double(patch.airy_columns[c - 3].first_slot / 4) :
                  -1.);
              const std::size_t count = local_columns.size();
              local_columns.push_back(0.);
              for (unsigned int i = 0; i < patch.slots.size(); ++i)
                if (patch.basis(i, c) != 0.)
                  {
                    local_columns.push_back(patch.slots[i]);
                    local_columns.push_back(patch.basis(i, c));
                    local_columns[count] += 1.;
                  }
            }
        }
    // all of them on every rank, in the order of the vertices (a patch is
    // computed by one rank; each rank's are in vertex order already)
    struct Column
    {
      unsigned int                                 vertex;
      int                                          edge;
      std::vector<std::pair<unsigned int, double>> entries;
    };
    std::vector<Column>       gathered;
    const std::vector<double> all_columns =
      all_ranks(local_columns, communicator);
    for (std::size_t i = 0; i < all_columns.size();)
      {
        Column             column{static_cast<unsigned int>(all_columns[i]),
                      static_cast<int>(all_columns[i + 1]),
                      {}};
        const unsigned int n_entries =
          static_cast<unsigned int>(all_columns[i + 2]);
        for (unsigned int e = 0; e < n_entries; ++e)
          column.entries.emplace_back(static_cast<unsigned int>(
                                        all_columns[i + 3 + 2 * e]),
                                      all_columns[i + 4 + 2 * e]);
        i += 3 + 2 * n_entries;
        gathered.push_back(std::move(column));
      }
    std::stable_sort(gathered.begin(),
                     gathered.end(),
                     [](const Column &a, const Column &b) {
                       return a.vertex < b.vertex;
                     });

    // W: the normal derivative of an edge is the same change in the Airy
    // patches of both its ends, kept once
    RegionCorrection correction;
    std::vector<int> edges_taken;
    for (const Column &column : gathered)
      {
        if (column.edge >= 0)
          {
            if (std::find(edges_taken.begin(),
                          edges_taken.end(),
                          column.edge) != edges_taken.end())
              continue;
            edges_taken.push_back(column.edge);
          }
        correction.columns.emplace_back();
        for (const auto &[slot, value] : column.entries)
          {
            correction.columns.back().emplace_back(slot, value);
            correction.slots.push_back(slot);
          }
      }
    std::sort(correction.slots.begin(), correction.slots.end());
    correction.slots.erase(std::unique(correction.slots.begin(),
                                       correction.slots.end()),
                           correction.slots.end());
    const auto position = [&correction](const unsigned int slot) {
      const auto found = std::lower_bound(correction.slots.begin(),
                                          correction.slots.end(),
                                          slot);
      return found != correction.slots.end() && *found == slot ?
               int(found - correction.slots.begin()) :
               -1;
    };
    // by position: the columns changing the slot
    std::vector<std::vector<std::pair<unsigned int, double>>> slot_columns(
      correction.slots.size());
    for (unsigned int c = 0; c < correction.columns.size(); ++c)
      for (auto &[slot, value] : correction.columns[c])
        {
          slot = position(slot);
          slot_columns[slot].emplace_back(c, value);
        }

    // the Hessians of the cells of the region's edges, each from its owner:
    // cell, its three edges, 144 entries
    std::vector<double>       local_cells;
    std::vector<unsigned int> owned_cells;
    for (const unsigned int slot : correction.slots)
      for (const unsigned int cell : patches.cells_of_edge(slot / 4))
        if (cell != numbers::invalid_unsigned_int && patches.owned(cell))
          owned_cells.push_back(cell);
    std::sort(owned_cells.begin(), owned_cells.end());
    owned_cells.erase(std::unique(owned_cells.begin(), owned_cells.end()),
                      owned_cells.end());
    for (const unsigned int cell : owned_cells)
      {
        local_cells.push_back(cell);
        for (const unsigned int edge : patches.edges(cell))
          local_cells.push_back(edge);
        const float *hessian =
          hessians.data() + packed_hessian_size * std::size_t(cell);
        for (unsigned int a = 0; a < 12; ++a)
          for (unsigned int b = 0; b < 12; ++b)
            local_cells.push_back(hessian_scales[cell] *
                                  double(hessian[packed_position(a, b)]));
      }
    std::vector<std::vector<double>> cells;
    const std::vector<double> all_cells = all_ranks(local_cells, communicator);
    for (std::size_t i = 0; i < all_cells.size(); i += 148)
      cells.emplace_back(all_cells.begin() + i, all_cells.begin() + i + 148);
    std::sort(cells.begin(), cells.end());

    // W^T H W, cell by cell: W restricted to the cell's 12 values, W_E^T H_E
    // W_E
    const unsigned int n_columns = correction.columns.size();
    FullMatrix<double> reduced(n_columns, n_columns);
    for (const std::vector<double> &cell : cells)
      {
        std::vector<unsigned int>           local_column_numbers;
        std::vector<std::array<double, 12>> local_columns_of_cell;
        for (unsigned int a = 0; a < 12; ++a)
          {
            const int p =
              position(4 * static_cast<unsigned int>(cell[1 + a / 4]) + a % 4);
            if (p < 0)
              continue;
            for (const auto &[c, value] : slot_columns[p])
              {
                const auto known = std::find(local_column_numbers.begin(),
                                             local_column_numbers.end(),
                                             c);
                if (known == local_column_numbers.end())
                  {
                    local_column_numbers.push_back(c);
                    local_columns_of_cell.emplace_back();
                    local_columns_of_cell.back().fill(0.);
                    local_columns_of_cell.back()[a] = value;
                  }
                else
                  local_columns_of_cell[known - local_column_numbers.begin()]
                                       [a] = value;
              }
          }
        const double *hessian = cell.data() + 4;
        for (unsigned int i = 0; i < local_column_numbers.size(); ++i)
          {
            std::array<double, 12> product = {};
            for (unsigned int a = 0; a < 12; ++a)
              for (unsigned int b = 0; b < 12; ++b)
                product[a] += hessian[12 * a + b] * local_columns_of_cell[i][b];
            for (unsigned int j = 0; j < local_column_numbers.size(); ++j)
              {
                double value = 0.;
                for (unsigned int a = 0; a < 12; ++a)
                  value += local_columns_of_cell[j][a] * product[a];
                reduced(local_column_numbers[j], local_column_numbers[i]) +=
                  value;
              }
          }
      }
    SmallMatrices::semidefinite_cholesky(reduced, 1e-10);
    correction.factor = std::move(reduced);
    return correction;
  }



  DensityEnhancement::Result
  DensityEnhancement::run(
    const std::function<ElementQuadratic(unsigned int)> &element_quadratic,
    const unsigned int                                   max_iterations,
    const double                                         tolerance,
    const RegionSettings                                &regions,
    Vector<double>                                      &densities) const
  {
    const unsigned int n_cells = patches.n_cells();
    const unsigned int n_slots = densities.size();

    // the element quadratics of the needed cells, stored flat: the
    // gradients (12 values per cell, in cell_values, which then holds the
    // products of the Hessians: one array less to allocate, 0.15 GB at
    // 1.6M DoFs), and the Hessians' upper triangles in single precision
    // (packed_position()): 0.5 GB at 1.6M DoFs instead of 0.91 for the full
    // matrices, fewer fresh pages to touch in the set-up, at the price of a
    // symmetric product that vectorises less (doc/estimator.md, "Cost"); a
    // rounded Hessian changes the minimiser by 1e-7 relative but not the
    // admissibility of any iterate, which only the patch corrections decide.
    // Each cell's Hessian is stored divided by its largest diagonal entry
    // (kept in double): the entries scale as h^2 / E, and unscaled they
    // left the single precision range for E = 1e40 or 1e-50, where the
    // enhancement silently did nothing
    AlignedVector<float>  hessians(packed_hessian_size * std::size_t(n_cells));
    AlignedVector<double> hessian_scales(n_cells);
    AlignedVector<double> cell_values(12 * std::size_t(n_cells));
    parallel::apply_to_subranges(
      0u,
      n_cells,
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int cell = begin; cell < end; ++cell)
          if (patches.needed(cell))
            {
              const ElementQuadratic quadratic = element_quadratic(cell);
              double                 scale     = 0.;
              for (unsigned int a = 0; a < 12; ++a)
                scale = std::max(scale, std::abs(quadratic.hessian[13 * a]));
              if (!(scale > 0.) || !std::isfinite(scale))
                scale = 1.;
              hessian_scales[cell] = scale;
              float *hessian =
                &hessians[packed_hessian_size * std::size_t(cell)];
              for (unsigned int a = 0; a < 12; ++a)
                for (unsigned int b = a; b < 12; ++b)
                  *hessian++ = quadratic.hessian[12 * a + b] / scale;
              std::copy(quadratic.gradient.begin(),
                        quadratic.gradient.end(),
                        cell_values.begin() + 12 * std::size_t(cell));
            }
      },
      64);
    // entry (a, b) of the Hessian of a cell
    const auto hessian_entry = [&hessians,
                                &hessian_scales](const unsigned int cell,
                                                 const unsigned int a,
                                                 const unsigned int b) {
      return hessian_scales[cell] *
             double(hessians[packed_hessian_size * std::size_t(cell) +
                             packed_position(a, b)]);
    };

    // the patches this rank computes, with the factor B_i of their
    // correction Z_i (Z_i^T H_i Z_i)^+ Z_i^T = B_i B_i^T; kept in blocks of
    // consecutive patches whose slots and factors are contiguous, which the
    // preconditioner streams through (with one heap object per patch it
    // took twice as long)
    std::vector<unsigned int> computed;
    for (unsigned int vertex = 0; vertex < patches.n_vertices(); ++vertex)
      if (patches.computes_patch(vertex))
        computed.push_back(vertex);
    constexpr unsigned int patches_per_block = 256;
    const unsigned int     n_blocks =
      (computed.size() + patches_per_block - 1) / patches_per_block;
    std::vector<PatchBlock> blocks(n_blocks);
    parallel::apply_to_subranges(
      0u,
      n_blocks,
      [&](const unsigned int begin, const unsigned int end) {
        Patch              patch;
        FullMatrix<double> hessian, hz, reduced, factor, lower_inverse, inverse;
        // (a block is assembled in work space reused by the thread, then
        // copied into arrays of its exact size: growing them by doubling
        // cost 0.4 of the 5.3 s of this set-up at 1.6M DoFs)
        thread_local PatchBlock work;
        for (unsigned int block = begin; block < end; ++block)
          {
            work.sizes.clear();
            work.slots.clear();
            work.factors.clear();
            work.airy_columns.clear();
            work.airy_inverses.clear();
            work.airy_scales.clear();
            const unsigned int first = block * patches_per_block;
            const unsigned int last =
              std::min<unsigned int>(first + patches_per_block,
                                     computed.size());
            for (unsigned int p = first; p < last; ++p)
              {
                describe_patch(computed[p], patch);
                const unsigned int n = patch.slots.size(), k = patch.basis.n(),
                                   n_airy = patch.airy_columns.size();
                work.sizes.push_back({{n, k, n_airy}});
                if (n_airy == 0)
                  work.slots.insert(work.slots.end(),
                                    patch.slots.begin(),
                                    patch.slots.end());
                if (k == 0)
                  continue;
                const auto &cells = patches.cells_of_vertex(computed[p]);
                reduced.reinit(k, k);
                if (n_airy > 0)
                  {
                    // Z^T H Z cell by cell: row 4 j + r of an Airy patch's Z
                    // (edge j) has its entries in columns 0, 1, 2 and 3 + j
                    // only, so a cell's changed values meet at most five
                    // columns (a third of the flops of H Z on the patch's
                    // assembled Hessian)
                    for (unsigned int i = 0; i < cells.size(); ++i)
                      add_airy_cell_product(
                        patch.positions[i],
                        patch.basis,
                        [&](const unsigned int a, const unsigned int b) {
                          return hessian_entry(cells[i], a, b);
                        },
                        reduced);

                    // (Z^T H Z)^+ (its upper triangle): (L L^T)^-1 = M^T M,
                    // M = L^-1, when it is definite (in work space: the
                    // matrices allocated per patch were about a tenth of
                    // this set-up at 1.6M DoFs), otherwise F F^T,
                    // F = correction_factor(I, .)
                    factor = reduced;
                    inverse.reinit(k, k);
                    if (SmallMatrices::cholesky(factor, 1e-10))
                      {
                        lower_inverse.reinit(k, k);
                        for (unsigned int j = 0; j < k; ++j)
                          {
                            lower_inverse(j, j) = 1. / factor(j, j);
                            for (unsigned int i = j + 1; i < k; ++i)
                              {
                                double value = 0.;
                                for (unsigned int p = j; p < i; ++p)
                                  value -= factor(i, p) * lower_inverse(p, j);
                                lower_inverse(i, j) = value / factor(i, i);
                              }
                          }
                        for (unsigned int i = 0; i < k; ++i)
                          for (unsigned int l = i; l < k; ++l)
                            for (unsigned int p = l; p < k; ++p)
                              inverse(i, l) +=
                                lower_inverse(p, i) * lower_inverse(p, l);
                      }
                    else
                      {
                        const FullMatrix<double> f = correction_factor(
                          FullMatrix<double>(IdentityMatrix(k)), reduced);
                        f.mTmult(inverse, f);
                      }
                    // (stored divided by its largest diagonal entry, kept
                    // in double: the entries scale as E / h^2, beyond
                    // single precision for extreme units)
                    double scale = 0.;
                    for (unsigned int i = 0; i < k; ++i)
                      scale = std::max(scale, std::abs(inverse(i, i)));
                    if (!(scale > 0.) || !std::isfinite(scale))
                      scale = 1.;
                    work.airy_scales.push_back(scale);
                    for (unsigned int i = 0; i < k; ++i)
                      for (unsigned int l = i; l < k; ++l)
                        work.airy_inverses.push_back(inverse(i, l) / scale);
                    work.airy_columns.insert(work.airy_columns.end(),
                                             patch.airy_columns.begin(),
                                             patch.airy_columns.end());
                  }
                else
                  {
                    hessian.reinit(n, n);
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
                    hz.reinit(n, k);
                    hessian.mmult(hz, patch.basis);
                    patch.basis.Tmmult(reduced, hz);
                    const FullMatrix<double> patch_factor =
                      correction_factor(patch.basis, reduced);
                    work.factors.insert(work.factors.end(),
                                        &patch_factor(0, 0),
                                        &patch_factor(0, 0) + n * k);
                  }
              }
            blocks[block].sizes         = work.sizes;
            blocks[block].slots         = work.slots;
            blocks[block].factors       = work.factors;
            blocks[block].airy_columns  = work.airy_columns;
            blocks[block].airy_inverses = work.airy_inverses;
            blocks[block].airy_scales   = work.airy_scales;
          }
      },
      1);

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
    // y = sum over the owned cells E of the 12 values v_E of @p cell_values
    // (12 per cell) at the slots of E's edges: gathered slot by slot from the
    // (at most two) cells of its edge in increasing cell order, whose
    // positions in cell_values are found once (32 bits: this array and
    // slot_sources are as long as the slot vectors, 0.1 GB more in 64 bits
    // at 1.6M DoFs)
    AssertThrow(12 * std::size_t(n_cells) < numbers::invalid_unsigned_int,
                ExcMessage("too many cells for the enhanced densities"));
    AlignedVector<std::array<unsigned int, 2>> edge_sources(
      n_slots / 4,
      {{numbers::invalid_unsigned_int, numbers::invalid_unsigned_int}});
    parallel::apply_to_subranges(
      0u,
      n_slots / 4,
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int edge = begin; edge < end; ++edge)
          {
            unsigned int found = 0;
            for (const unsigned int cell : patches.cells_of_edge(edge))
              if (cell != numbers::invalid_unsigned_int && patches.owned(cell))
                {
                  const auto        &edges = patches.edges(cell);
                  const unsigned int e =
                    std::find(edges.begin(), edges.end(), edge) - edges.begin();
                  edge_sources[edge][found++] = 12 * cell + 4 * e;
                }
          }
      },
      1024);
    const auto sum_cell_values = [&](const AlignedVector<double> &cell_values,
                                     Vector<double>              &y) {
      y.reinit(n_slots, true);
      parallel::apply_to_subranges(
        0u,
        n_slots / 4,
        [&](const unsigned int begin, const unsigned int end) {
          for (unsigned int edge = begin; edge < end; ++edge)
            {
              std::array<double, 4> sum = {{0., 0., 0., 0.}};
              for (const unsigned int source : edge_sources[edge])
                if (source != numbers::invalid_unsigned_int)
                  for (unsigned int j = 0; j < 4; ++j)
                    sum[j] += cell_values[source + j];
              for (unsigned int j = 0; j < 4; ++j)
                y[4 * edge + j] = sum[j];
            }
        },
        1024);
      sum_over_ranks(y);
    };
    // y = sum over the owned cells of H_E x_E (the Hessian of J): the
    // products of the cells in parallel, then summed per slot
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
                const std::array<double, 12> product = packed_product(
                  &hessians[packed_hessian_size * std::size_t(cell)], local);
                const double scale = hessian_scales[cell];
                for (unsigned int b = 0; b < 12; ++b)
                  cell_values[12 * std::size_t(cell) + b] = scale * product[b];
              }
        },
        256);
      sum_cell_values(cell_values, y);
    };
    // z = sum_i B_i B_i^T r_i (additive Schwarz): the corrections computed
    // patch by patch in parallel into one flat array (block b from
    // block_offset[b], in the order of its slots), then gathered slot by
    // slot from the (at most two) patches of the slot's edge ends, in patch
    // order
    std::vector<std::size_t> block_offset(n_blocks + 1, 0);
    unsigned int             largest_patch = 0;
    for (unsigned int b = 0; b < n_blocks; ++b)
      {
        block_offset[b + 1] = block_offset[b] + blocks[b].n_slots();
        for (const auto &size : blocks[b].sizes)
          largest_patch = std::max(largest_patch, size[0]);
      }
    AssertThrow(block_offset.back() < numbers::invalid_unsigned_int,
                ExcMessage("too many cells for the enhanced densities"));
    AlignedVector<std::array<unsigned int, 2>> slot_sources(
      n_slots,
      {{numbers::invalid_unsigned_int, numbers::invalid_unsigned_int}});
    // (a slot is in the patches of both ends of its edge, if both are
    // computed here: the first source is that of the lower vertex)
    parallel::apply_to_subranges(
      0u,
      n_blocks,
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int b = begin; b < end; ++b)
          {
            blocks[b].for_each_slot([&](const unsigned int q,
                                        const std::size_t  j,
                                        const unsigned int slot) {
              const unsigned int vertex = computed[b * patches_per_block + q];
              const auto        &ends   = edge_vertices[slot / 4];
              const unsigned int other  = ends[0] == vertex ? ends[1] : ends[0];
              const bool         second =
                patches.computes_patch(other) && other < vertex;
              slot_sources[slot][second ? 1 : 0] = block_offset[b] + j;
            });
          }
      },
      1);
    AlignedVector<double> corrections(block_offset.back());
    const auto precondition = [&](const Vector<double> &r, Vector<double> &z) {
      parallel::apply_to_subranges(
        0u,
        n_blocks,
        [&](const unsigned int begin, const unsigned int end) {
          std::vector<double> values(largest_patch), reduced(largest_patch);
          // the rows of Z at the vertex's end of an Airy patch's edges
          std::vector<std::array<double, 8>> edge_rows(largest_patch / 4);
          for (unsigned int b = begin; b < end; ++b)
            {
              const PatchBlock  &block        = blocks[b];
              const double      *factor       = block.factors.data();
              const AiryColumns *airy_columns = block.airy_columns.data();
              const float       *inverse      = block.airy_inverses.data();
              const double      *airy_scale   = block.airy_scales.data();
              double     *correction  = corrections.data() + block_offset[b];
              std::size_t other_slots = 0; // in block.slots
              for (const auto &[n, k, n_airy] : block.sizes)
                {
                  if (k == 0)
                    std::fill(correction, correction + n, 0.);
                  else if (n_airy > 0)
                    {
                      // Z^T r edge by edge, (Z^T H Z)^+, then Z
                      std::fill(reduced.begin(), reduced.begin() + k, 0.);
                      const double patch_scale = airy_columns[0].inverse_length;
                      for (unsigned int j = 0; j < n_airy; ++j)
                        {
                          const AiryColumns           &edge = airy_columns[j];
                          const std::array<double, 8> &at_vertex =
                            edge_rows[j]         = edge.at_vertex(patch_scale);
                          const double  shift    = edge.shift();
                          const double *r_edge   = r.begin() + edge.first_slot;
                          const double *r_vertex = r_edge + 2 * edge.vertex_end;
                          const double *r_other =
                            r_edge + 2 - 2 * edge.vertex_end;
                          const double difference[2] = {
                            r_vertex[0] - r_other[0], r_vertex[1] - r_other[1]};
                          for (unsigned int i = 0; i < 3; ++i)
                            reduced[i] += at_vertex[i] * difference[0] +
                                          at_vertex[4 + i] * difference[1];
                          reduced[1] += shift * r_other[1];
                          reduced[2] -= shift * r_other[0];
                          reduced[3 + j] = at_vertex[3] * difference[0] +
                                           at_vertex[7] * difference[1];
                        }
                      // (the upper triangle, row by row)
                      std::fill(values.begin(), values.begin() + k, 0.);
                      for (unsigned int i = 0; i < k; ++i)
                        {
                          double value = double(*inverse++) * reduced[i];
                          for (unsigned int l = i + 1; l < k; ++l, ++inverse)
                            {
                              value += double(*inverse) * reduced[l];
                              values[l] += double(*inverse) * reduced[i];
                            }
                          values[i] += value;
                        }
                      for (unsigned int i = 0; i < k; ++i)
                        values[i] *= *airy_scale;
                      ++airy_scale;
                      for (unsigned int j = 0; j < n_airy; ++j)
                        {
                          const AiryColumns           &edge = airy_columns[j];
                          const std::array<double, 8> &at_vertex = edge_rows[j];
                          const double                 shift     = edge.shift();
                          double                      *vertex_end =
                            correction + 4 * j + 2 * edge.vertex_end;
                          double *other_end =
                            correction + 4 * j + 2 - 2 * edge.vertex_end;
                          for (unsigned int c = 0; c < 2; ++c)
                            {
                              double value =
                                at_vertex[4 * c + 3] * values[3 + j];
                              for (unsigned int i = 0; i < 3; ++i)
                                value += at_vertex[4 * c + i] * values[i];
                              vertex_end[c] = value;
                              other_end[c]  = -value;
                            }
                          other_end[1] += shift * values[1];
                          other_end[0] -= shift * values[2];
                        }
                      airy_columns += n_airy;
                    }
                  else
                    {
                      const unsigned int *slots =
                        block.slots.data() + other_slots;
                      for (unsigned int j = 0; j < n; ++j)
                        values[j] = r[slots[j]];
                      std::fill(reduced.begin(), reduced.begin() + k, 0.);
                      for (unsigned int j = 0; j < n; ++j)
                        for (unsigned int i = 0; i < k; ++i)
                          reduced[i] += factor[k * j + i] * values[j];
                      for (unsigned int j = 0; j < n; ++j)
                        {
                          double value = 0.;
                          for (unsigned int i = 0; i < k; ++i)
                            value += factor[k * j + i] * reduced[i];
                          correction[j] = value;
                        }
                      factor += std::size_t(n) * k;
                    }
                  if (n_airy == 0)
                    other_slots += n;
                  correction += n;
                }
            }
        },
        4);
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

    // the residual -grad J at the given densities (cell_values holds the
    // gradients until the first product with the Hessian)
    Vector<double> residual;
    sum_cell_values(cell_values, residual);
    residual *= -1.;

    Vector<double> preconditioned, direction, hessian_direction;
    precondition(residual, preconditioned);

    // the regions, seeded where a patch alone would decrease J most (by
    // d_i = r_i^T B_i B_i^T r_i at the initial residual), each seed the best
    // vertex outside the regions so far, over all ranks (the lowest vertex
    // number among equals), as long as d_i is at least 1/200 of the sum of
    // all d_i: a singular point (15 % at the block's clamped loaded corner
    // on every mesh, 0.9 % at the end of its load; on a smooth solution
    // about 1 / the number of vertices)
    std::vector<RegionCorrection> region_corrections;
    if (regions.count > 0)
      {
        std::vector<std::pair<double, unsigned int>> decrease_of_patch;
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            const unsigned int first = b * patches_per_block;
            for (unsigned int q = 0; q < blocks[b].sizes.size(); ++q)
              decrease_of_patch.emplace_back(0., computed[first + q]);
            blocks[b].for_each_slot([&](const unsigned int q,
                                        const std::size_t  j,
                                        const unsigned int slot) {
              decrease_of_patch[first + q].first +=
                residual[slot] * corrections[block_offset[b] + j];
            });
          }
        std::sort(decrease_of_patch.begin(),
                  decrease_of_patch.end(),
                  [](const auto &a, const auto &b) {
                    return a.first > b.first ||
                           (a.first == b.first && a.second < b.second);
                  });
        double total = 0.;
        for (const auto &patch : decrease_of_patch)
          total += patch.first;
        total = Utilities::MPI::sum(total, communicator);
        std::vector<bool> in_region(patches.n_vertices(), false);
        auto              candidate = decrease_of_patch.begin();
        for (unsigned int r = 0; r < regions.count; ++r)
          {
            while (candidate != decrease_of_patch.end() &&
                   in_region[candidate->second])
              ++candidate;
            const double best =
              Utilities::MPI::max(candidate != decrease_of_patch.end() ?
                                    candidate->first :
                                    -1.,
                                  communicator);
            if (!(best > 0.) || !(best >= total / 200.))
              break;
            const unsigned int seed =
              Utilities::MPI::min(candidate != decrease_of_patch.end() &&
                                      candidate->first == best ?
                                    candidate->second :
                                    numbers::invalid_unsigned_int,
                                  communicator);
            const std::vector<unsigned int> region =
              region_vertices(seed, regions.rings);
            for (const unsigned int vertex : region)
              in_region[vertex] = true;
            region_corrections.push_back(describe_region(
              region,
              ArrayView<const float>(hessians.data(), hessians.size()),
              ArrayView<const double>(hessian_scales.data(),
                                      hessian_scales.size())));
            region_corrections.back().add_correction(residual, preconditioned);
          }
      }
    const auto precondition_all = [&](const Vector<double> &r,
                                      Vector<double>       &z) {
      precondition(r, z);
      for (const RegionCorrection &correction : region_corrections)
        correction.add_correction(r, z);
    };

    direction                 = preconditioned;
    double   residual_product = residual * preconditioned;
    Result   result;
    Progress progress("estimate, enhanced densities", communicator);
    while (result.iterations < max_iterations && residual_product > 0.)
      {
        progress.report([&]() {
          return "iteration " + std::to_string(result.iterations) +
                 " of at most " + std::to_string(max_iterations);
        });
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
        precondition_all(residual, preconditioned);
        const double new_product = residual * preconditioned;
        direction.sadd(new_product / residual_product, preconditioned);
        residual_product = new_product;
      }
    return result;
  }
} // namespace Signorini
