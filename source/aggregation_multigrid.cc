#include <deal.II/base/exceptions.h>

#include <deal.II/lac/tridiagonal_matrix.h>

#include <signorini/aggregation_multigrid.h>

#include <Amesos.h>
#include <Epetra_Import.h>
#include <Epetra_Map.h>
#include <algorithm>
#include <cmath>

namespace Signorini
{
  namespace
  {
    /**
     * Aggregates of the local vertices (groups of @p block consecutive rows)
     * as ML's "Uncoupled" scheme forms them: a vertex whose neighbours are
     * all free starts an aggregate with them; a vertex left over joins the
     * neighbouring aggregate it is most connected to; the rest start
     * aggregates of their own. A vertex all of whose rows are masked belongs
     * to none. Returns the aggregate of every vertex (-1: none) and their
     * number.
     */
    std::pair<std::vector<int>, int>
    aggregate_vertices(const Epetra_CrsMatrix  &matrix,
                       const std::vector<char> &masked_row,
                       const unsigned int       block)
    {
      const int n_rows     = matrix.NumMyRows();
      const int n_vertices = n_rows / static_cast<int>(block);
      // local vertex of each column (-1: another rank's)
      std::vector<int> vertex_of_column(matrix.NumMyCols());
      for (int c = 0; c < matrix.NumMyCols(); ++c)
        {
          const int row       = matrix.RowMap().LID(matrix.ColMap().GID(c));
          vertex_of_column[c] = row < 0 ? -1 : row / static_cast<int>(block);
        }
      std::vector<char> free_vertex(n_vertices, 0);
      for (int r = 0; r < n_rows; ++r)
        if (masked_row.empty() || !masked_row[r])
          free_vertex[r / block] = 1;

      // the neighbours of vertex v (local, free, other than v)
      std::vector<int> neighbours;
      const auto       collect = [&](const int v) {
        neighbours.clear();
        for (unsigned int k = 0; k < block; ++k)
          {
            const int r = v * block + k;
            if (!masked_row.empty() && masked_row[r])
              continue;
            int     n_entries;
            double *values;
            int    *columns;
            matrix.ExtractMyRowView(r, n_entries, values, columns);
            for (int e = 0; e < n_entries; ++e)
              {
                const int w = vertex_of_column[columns[e]];
                if (w >= 0 && w != v && free_vertex[w] && values[e] != 0.)
                  neighbours.push_back(w);
              }
          }
        std::sort(neighbours.begin(), neighbours.end());
        neighbours.erase(std::unique(neighbours.begin(), neighbours.end()),
                         neighbours.end());
      };

      std::vector<int> aggregate(n_vertices, -1);
      int              n_aggregates = 0;
      // phase 1: a vertex and its neighbours, none of them taken yet
      for (int v = 0; v < n_vertices; ++v)
        if (free_vertex[v] && aggregate[v] < 0)
          {
            collect(v);
            if (std::all_of(neighbours.begin(),
                            neighbours.end(),
                            [&](const int w) { return aggregate[w] < 0; }))
              {
                aggregate[v] = n_aggregates;
                for (const int w : neighbours)
                  aggregate[w] = n_aggregates;
                ++n_aggregates;
              }
          }
      // phase 2: the rest join the aggregate most of their neighbours are in
      // (decided on the phase 1 aggregates, so that the order does not chain)
      const std::vector<int> phase_1 = aggregate;
      std::vector<int>       candidates;
      for (int v = 0; v < n_vertices; ++v)
        if (free_vertex[v] && phase_1[v] < 0)
          {
            collect(v);
            candidates.clear();
            for (const int w : neighbours)
              if (phase_1[w] >= 0)
                candidates.push_back(phase_1[w]);
            if (candidates.empty())
              continue;
            std::sort(candidates.begin(), candidates.end());
            int best = candidates[0], best_count = 0;
            for (std::size_t i = 0; i < candidates.size();)
              {
                std::size_t j = i;
                while (j < candidates.size() && candidates[j] == candidates[i])
                  ++j;
                if (static_cast<int>(j - i) > best_count)
                  {
                    best       = candidates[i];
                    best_count = static_cast<int>(j - i);
                  }
                i = j;
              }
            aggregate[v] = best;
          }
      // phase 3: what is still alone (no aggregated neighbour) with its free
      // neighbours
      for (int v = 0; v < n_vertices; ++v)
        if (free_vertex[v] && aggregate[v] < 0)
          {
            collect(v);
            aggregate[v] = n_aggregates;
            for (const int w : neighbours)
              if (aggregate[w] < 0)
                aggregate[w] = n_aggregates;
            ++n_aggregates;
          }
      return {aggregate, n_aggregates};
    }



    /// A deterministic vector with entries in [0.5, 1.5] (by global index,
    /// so the same on any number of ranks).
    void
    fill_pseudo_random(Epetra_Vector &v)
    {
      for (int i = 0; i < v.MyLength(); ++i)
        {
          const unsigned int gid  = v.Map().GID(i);
          const unsigned int hash = (gid + 1) * 2654435761ULL % 4294967296ULL;
          v[i]                    = 0.5 + double(hash) / 4294967296.;
        }
    }
  } // namespace



  void
  AggregationMultigrid::initialize(const LA::SparseMatrix  &K,
                                   const std::vector<bool> &eliminated,
                                   const unsigned int       dofs_per_vertex,
                                   const std::vector<LA::Vector> &null_vectors,
                                   const unsigned int             n_modes,
                                   const AdditionalData &additional_data)
  {
    data = additional_data;
    levels.clear();
    coarsest_solver.reset();
    coarsest_problem.reset();
    Assert(n_modes > 0 && n_modes <= null_vectors.size(), ExcInternalError());

    const Epetra_CrsMatrix &finest = K.trilinos_matrix();
    AssertThrow(finest.NumMyRows() % dofs_per_vertex == 0,
                ExcMessage("the rows of a rank are not whole vertices"));
    levels.emplace_back();
    levels[0].matrix = &finest;
    // the masked rows, as a list (for the products) and per row (for the
    // aggregation, finest level only)
    std::vector<char> masked_row(finest.NumMyRows(), 0);
    for (int r = 0; r < finest.NumMyRows(); ++r)
      if (eliminated[finest.GRID(r)])
        {
          masked_row[r] = 1;
          levels[0].masked_rows.push_back(r);
        }

    auto null_space =
      std::make_unique<Epetra_MultiVector>(finest.RowMap(),
                                           static_cast<int>(n_modes));
    for (unsigned int m = 0; m < n_modes; ++m)
      for (int r = 0; r < finest.NumMyRows(); ++r)
        (*null_space)[m][r] =
          null_vectors[m][static_cast<types::global_dof_index>(finest.GRID(r))];

    unsigned int block = dofs_per_vertex;
    while (true)
      {
        Level                  &level = levels.back();
        const Epetra_CrsMatrix &A     = *level.matrix;
        allocate_work_vectors(level);

        // (the finest level is always coarsened: it is only smoothed, its
        // masked operator is not the matrix a direct solver would see)
        if (levels.size() > 1 &&
            (A.NumGlobalRows() <= static_cast<int>(data.coarsest_size) ||
             levels.size() == data.max_levels))
          break;

        // the aggregates, the tentative prolongator and the coarse null
        // space, then the Galerkin product P^T A P
        const unsigned int            n_null = null_space->NumVectors();
        std::vector<std::vector<int>> rows_of;
        const int                     n_aggregates =
          aggregate_rows(level, masked_row, block, n_null, rows_of);
        const Epetra_Map coarse_map(-1,
                                    n_aggregates * static_cast<int>(n_null),
                                    0,
                                    A.Comm());
        auto             coarse_null =
          tentative_prolongator(level, *null_space, rows_of, coarse_map);
        auto coarse = galerkin_product(level, rows_of, coarse_map);

        const int fine_rows   = A.NumGlobalRows();
        const int coarse_rows = coarse->NumGlobalRows();
        if (coarse_rows == 0 || coarse_rows > 0.9 * fine_rows)
          {
            // no coarsening left: this level is the coarsest
            level.aggregate_of_row.clear();
            level.prolongator.clear();
            level.n_null = 0;
            break;
          }
        levels.emplace_back();
        levels.back().coarse_matrix = std::move(coarse);
        levels.back().matrix        = levels.back().coarse_matrix.get();
        null_space                  = std::move(coarse_null);
        block                       = n_null;
        masked_row.clear(); // (the coarse levels mask nothing)
      }

    factor_coarsest();
  }



  void
  AggregationMultigrid::allocate_work_vectors(Level &level) const
  {
    const Epetra_CrsMatrix &A      = *level.matrix;
    const int               n_rows = A.NumMyRows();
    level.inverse_diagonal = std::make_unique<Epetra_Vector>(A.RowMap());
    A.ExtractDiagonalCopy(*level.inverse_diagonal);
    for (int r = 0; r < n_rows; ++r)
      {
        double &d = (*level.inverse_diagonal)[r];
        d         = (d > 0. ? 1. / d : 1.);
      }
    // (the finest level's right-hand side and solution are the caller's)
    level.residual = std::make_unique<Epetra_Vector>(A.RowMap());
    if (data.smoother_degree > 1)
      level.update = std::make_unique<Epetra_Vector>(A.RowMap());
    if (levels.size() > 1)
      for (auto *v : {&level.rhs, &level.solution})
        *v = std::make_unique<Epetra_Vector>(A.RowMap());
    if (levels.size() > 1 && data.w_cycle)
      for (auto *v : {&level.second_rhs, &level.second_solution})
        *v = std::make_unique<Epetra_Vector>(A.RowMap());
    level.max_eigenvalue = estimate_max_eigenvalue(level);
  }



  int
  AggregationMultigrid::aggregate_rows(
    Level                         &level,
    const std::vector<char>       &masked_row,
    const unsigned int             block,
    const unsigned int             n_null,
    std::vector<std::vector<int>> &rows_of) const
  {
    const Epetra_CrsMatrix &A      = *level.matrix;
    const int               n_rows = A.NumMyRows();
    const auto [aggregate_of_vertex, n_aggregates] =
      aggregate_vertices(A, masked_row, block);
    level.n_null = n_null;
    level.aggregate_of_row.assign(n_rows, -1);
    level.prolongator.assign(std::size_t(n_rows) * n_null, 0.);
    rows_of.assign(n_aggregates, {});
    for (int r = 0; r < n_rows; ++r)
      {
        const int a = aggregate_of_vertex[r / block];
        if (a >= 0 && (masked_row.empty() || !masked_row[r]))
          {
            level.aggregate_of_row[r] = a;
            rows_of[a].push_back(r);
          }
      }
    return n_aggregates;
  }



  std::unique_ptr<Epetra_MultiVector>
  AggregationMultigrid::tentative_prolongator(
    Level                               &level,
    const Epetra_MultiVector            &null_space,
    const std::vector<std::vector<int>> &rows_of,
    const Epetra_Map                    &coarse_map) const
  {
    // the near null space orthonormalised on each aggregate (modified
    // Gram-Schmidt, twice); a direction it does not span there (few free
    // dofs) gets a zero column
    const unsigned int n_null       = null_space.NumVectors();
    const int          n_aggregates = rows_of.size();
    auto coarse_null = std::make_unique<Epetra_MultiVector>(coarse_map, n_null);
    std::vector<double> q; // (the aggregate's columns, in double)
    for (int a = 0; a < n_aggregates; ++a)
      {
        const auto       &rows = rows_of[a];
        const std::size_t n    = rows.size();
        q.assign(n * n_null, 0.);
        for (unsigned int m = 0; m < n_null; ++m)
          {
            double norm0 = 0.;
            for (std::size_t i = 0; i < n; ++i)
              {
                q[i * n_null + m] = null_space[m][rows[i]];
                norm0 += q[i * n_null + m] * q[i * n_null + m];
              }
            for (unsigned int pass = 0; pass < 2; ++pass)
              for (unsigned int k = 0; k < m; ++k)
                {
                  double dot = 0.;
                  for (std::size_t i = 0; i < n; ++i)
                    dot += q[i * n_null + k] * q[i * n_null + m];
                  for (std::size_t i = 0; i < n; ++i)
                    q[i * n_null + m] -= dot * q[i * n_null + k];
                  (*coarse_null)[m][a * n_null + k] += dot;
                }
            double norm = 0.;
            for (std::size_t i = 0; i < n; ++i)
              norm += q[i * n_null + m] * q[i * n_null + m];
            norm               = std::sqrt(norm);
            const bool spanned = norm > 1e-10 * std::sqrt(norm0);
            for (std::size_t i = 0; i < n; ++i)
              q[i * n_null + m] = spanned ? q[i * n_null + m] / norm : 0.;
            (*coarse_null)[m][a * n_null + m] = spanned ? norm : 0.;
          }
        for (std::size_t i = 0; i < n; ++i)
          for (unsigned int m = 0; m < n_null; ++m)
            level.prolongator[rows[i] * n_null + m] = q[i * n_null + m];
      }

    return coarse_null;
  }



  std::unique_ptr<Epetra_CrsMatrix>
  AggregationMultigrid::galerkin_product(
    const Level                         &level,
    const std::vector<std::vector<int>> &rows_of,
    const Epetra_Map                    &coarse_map) const
  {
    const Epetra_CrsMatrix &A            = *level.matrix;
    const int               n_rows       = A.NumMyRows();
    const unsigned int      n_null       = level.n_null;
    const int               n_aggregates = rows_of.size();
    // the aggregate (global) and prolongator row of every column of A:
    // the rank's own rows, and the other ranks' (imported)
    const int        first_coarse = coarse_map.MinMyGID() / n_null;
    std::vector<int> row_of_column(A.NumMyCols()),
      ghost_of_column(A.NumMyCols(), -1);
    std::vector<int> ghost_gids;
    for (int c = 0; c < A.NumMyCols(); ++c)
      {
        row_of_column[c] = A.RowMap().LID(A.ColMap().GID(c));
        if (row_of_column[c] < 0)
          {
            ghost_of_column[c] = ghost_gids.size();
            ghost_gids.push_back(A.ColMap().GID(c));
          }
      }
    int n_ghosts = ghost_gids.size(), max_ghosts = 0;
    A.Comm().MaxAll(&n_ghosts, &max_ghosts, 1);
    std::unique_ptr<Epetra_MultiVector> ghosts;
    if (max_ghosts > 0)
      {
        Epetra_MultiVector by_row(A.RowMap(), n_null + 1);
        for (int r = 0; r < n_rows; ++r)
          {
            const int a  = level.aggregate_of_row[r];
            by_row[0][r] = a < 0 ? -1. : double(first_coarse + a);
            for (unsigned int m = 0; m < n_null; ++m)
              by_row[m + 1][r] = level.prolongator[r * n_null + m];
          }
        const Epetra_Map ghost_map(
          -1, n_ghosts, ghost_gids.data(), 0, A.Comm());
        ghosts = std::make_unique<Epetra_MultiVector>(ghost_map, n_null + 1);
        ghosts->Import(by_row, Epetra_Import(ghost_map, A.RowMap()), Insert);
      }
    const auto aggregate_of_column = [&](const int c) {
      if (const int r = row_of_column[c]; r >= 0)
        return level.aggregate_of_row[r] < 0 ?
                 -1 :
                 first_coarse + level.aggregate_of_row[r];
      return static_cast<int>((*ghosts)[0][ghost_of_column[c]]);
    };
    const auto prolongator_of_column = [&](const int c, const int l) {
      if (const int r = row_of_column[c]; r >= 0)
        return double(level.prolongator[r * n_null + l]);
      return (*ghosts)[l + 1][ghost_of_column[c]];
    };

    // P^T A P, aggregate by aggregate: the n_null x n_null blocks of its
    // rows with the aggregates its rows couple to; first their number
    // (the matrix is then allocated once, at its size)
    std::vector<int>    neighbour_aggregates;
    std::vector<double> blocks; // n_null^2 per neighbour
    const auto          find_neighbours = [&](const int a) {
      neighbour_aggregates.clear();
      for (const int r : rows_of[a])
        {
          int     n_entries;
          double *entries;
          int    *columns;
          A.ExtractMyRowView(r, n_entries, entries, columns);
          for (int e = 0; e < n_entries; ++e)
            if (const int b = aggregate_of_column(columns[e]);
                b >= 0 && entries[e] != 0. &&
                std::find(neighbour_aggregates.begin(),
                          neighbour_aggregates.end(),
                          b) == neighbour_aggregates.end())
              neighbour_aggregates.push_back(b);
        }
      std::sort(neighbour_aggregates.begin(), neighbour_aggregates.end());
    };
    std::vector<int> row_lengths(std::size_t(n_aggregates) * n_null);
    for (int a = 0; a < n_aggregates; ++a)
      {
        find_neighbours(a);
        const int length =
          std::max<int>(1, neighbour_aggregates.size() * n_null);
        for (unsigned int k = 0; k < n_null; ++k)
          row_lengths[a * n_null + k] = length;
      }
    auto coarse = std::make_unique<Epetra_CrsMatrix>(Copy,
                                                     coarse_map,
                                                     row_lengths.data(),
                                                     /*static=*/true);
    row_lengths = std::vector<int>();
    std::vector<int>    indices;
    std::vector<double> values;
    for (int a = 0; a < n_aggregates; ++a)
      {
        find_neighbours(a);
        blocks.assign(neighbour_aggregates.size() * n_null * n_null, 0.);
        for (const int r : rows_of[a])
          {
            int     n_entries;
            double *entries;
            int    *columns;
            A.ExtractMyRowView(r, n_entries, entries, columns);
            const float *q_r = &level.prolongator[r * n_null];
            for (int e = 0; e < n_entries; ++e)
              {
                const int c = columns[e];
                const int b = aggregate_of_column(c);
                if (b < 0 || entries[e] == 0.)
                  continue;
                const std::size_t slot =
                  std::lower_bound(neighbour_aggregates.begin(),
                                   neighbour_aggregates.end(),
                                   b) -
                  neighbour_aggregates.begin();
                double *block_values = &blocks[slot * n_null * n_null];
                for (unsigned int l = 0; l < n_null; ++l)
                  {
                    const double a_q = entries[e] * prolongator_of_column(c, l);
                    for (unsigned int k = 0; k < n_null; ++k)
                      block_values[k * n_null + l] += q_r[k] * a_q;
                  }
              }
          }
        const int self = first_coarse + a;
        for (unsigned int k = 0; k < n_null; ++k)
          {
            indices.clear();
            values.clear();
            for (std::size_t s = 0; s < neighbour_aggregates.size(); ++s)
              for (unsigned int l = 0; l < n_null; ++l)
                {
                  double value = blocks[(s * n_null + k) * n_null + l];
                  // a direction the aggregate does not span: decoupled
                  if (neighbour_aggregates[s] == self && k == l && value == 0.)
                    value = 1.;
                  indices.push_back(neighbour_aggregates[s] * n_null + l);
                  values.push_back(value);
                }
            if (indices.empty()) // (an aggregate with no coupling at all)
              {
                indices.push_back(self * n_null + k);
                values.push_back(1.);
              }
            const int error =
              coarse->InsertGlobalValues(self * n_null + k,
                                         static_cast<int>(indices.size()),
                                         values.data(),
                                         indices.data());
            AssertThrow(error >= 0,
                        ExcMessage("coarse operator: insertion failed"));
          }
      }
    coarse->FillComplete(coarse_map, coarse_map);
    coarse->OptimizeStorage();
    return coarse;
  }



  void
  AggregationMultigrid::factor_coarsest()
  {
    // the coarsest level is solved directly, unless it is the masked finest
    // (then it is only smoothed)
    if (levels.size() > 1)
      {
        Level &last = levels.back();
        coarsest_problem =
          std::make_unique<Epetra_LinearProblem>(last.coarse_matrix.get(),
                                                 last.solution.get(),
                                                 last.rhs.get());
        Amesos factory;
        coarsest_solver.reset(factory.Create("Amesos_Klu", *coarsest_problem));
        AssertThrow(coarsest_solver != nullptr,
                    ExcMessage("Amesos_Klu is not available"));
        coarsest_solver->SymbolicFactorization();
        coarsest_solver->NumericFactorization();
      }
  }



  void
  AggregationMultigrid::apply(const Level   &level,
                              Epetra_Vector &x,
                              Epetra_Vector &y) const
  {
    if (level.masked_rows.empty())
      {
        level.matrix->Multiply(false, x, y);
        return;
      }
    // K with the masked rows and columns zeroed but for the diagonal: the
    // masked entries of x are zeroed for the product and restored after
    // (they are few: no copy of x)
    level.masked_values.clear();
    for (const int r : level.masked_rows)
      {
        level.masked_values.push_back(x[r]);
        x[r] = 0.;
      }
    level.matrix->Multiply(false, x, y);
    for (std::size_t k = 0; k < level.masked_rows.size(); ++k)
      {
        const int r = level.masked_rows[k];
        x[r]        = level.masked_values[k];
        y[r]        = x[r] / (*level.inverse_diagonal)[r];
      }
  }



  double
  AggregationMultigrid::estimate_max_eigenvalue(const Level &level) const
  {
    // preconditioned CG on A x = b (b pseudo-random), its Lanczos
    // tridiagonal matrix from the CG coefficients
    Epetra_Vector &r = *level.residual;
    Epetra_Vector  p(r.Map()), q(r.Map()), z(r.Map());
    fill_pseudo_random(r);
    z.Multiply(1., *level.inverse_diagonal, r, 0.);
    p = z;
    double rz;
    r.Dot(z, &rz);
    std::vector<double> alpha, beta;
    for (unsigned int k = 0; k < 10 && rz > 0.; ++k)
      {
        apply(level, p, q);
        double pq;
        p.Dot(q, &pq);
        if (!(pq > 0.))
          break;
        alpha.push_back(rz / pq);
        r.Update(-alpha.back(), q, 1.);
        z.Multiply(1., *level.inverse_diagonal, r, 0.);
        double rz_new;
        r.Dot(z, &rz_new);
        beta.push_back(rz_new / rz);
        rz = rz_new;
        p.Update(1., z, beta.back());
      }
    if (alpha.empty())
      return 1.;
    const unsigned int        n = alpha.size();
    TridiagonalMatrix<double> T(n, /*symmetric=*/true);
    for (unsigned int k = 0; k < n; ++k)
      {
        T(k, k) = 1. / alpha[k] + (k > 0 ? beta[k - 1] / alpha[k - 1] : 0.);
        if (k + 1 < n)
          T(k + 1, k) = T(k, k + 1) = std::sqrt(beta[k]) / alpha[k];
      }
    T.compute_eigenvalues();
    double largest = 0.;
    for (unsigned int k = 0; k < n; ++k)
      largest = std::max(largest, T.eigenvalue(k));
    return 1.2 * largest; // (the Lanczos estimate is from below)
  }



  void
  AggregationMultigrid::smooth(const Level         &level,
                               const Epetra_Vector &b,
                               Epetra_Vector       &x,
                               const bool           zero_start) const
  {
    // Chebyshev iteration on D^{-1} A over [lambda_max / range, lambda_max]
    const double         lambda_max = level.max_eigenvalue;
    const double         lambda_min = lambda_max / data.smoothing_range;
    const double         theta      = 0.5 * (lambda_max + lambda_min);
    const double         delta      = 0.5 * (lambda_max - lambda_min);
    const double         sigma      = theta / delta;
    double               rho        = 1. / sigma;
    Epetra_Vector       &r          = *level.residual;
    const Epetra_Vector *first      = &b; // the first residual
    if (!zero_start)
      {
        apply(level, x, r);
        r.Update(1., b, -1.);
        first = &r;
      }
    if (data.smoother_degree == 1) // (no update to keep)
      {
        x.Multiply(1. / theta,
                   *level.inverse_diagonal,
                   *first,
                   zero_start ? 0. : 1.);
        return;
      }
    Epetra_Vector &d = *level.update;
    d.Multiply(1. / theta, *level.inverse_diagonal, *first, 0.);
    if (zero_start)
      x = d;
    else
      x.Update(1., d, 1.);
    for (unsigned int k = 1; k < data.smoother_degree; ++k)
      {
        const double rho_new = 1. / (2. * sigma - rho);
        apply(level, x, r);
        r.Update(1., b, -1.);
        d.Multiply(2. * rho_new / delta,
                   *level.inverse_diagonal,
                   r,
                   rho_new * rho);
        x.Update(1., d, 1.);
        rho = rho_new;
      }
  }



  void
  AggregationMultigrid::cycle(const unsigned int   l,
                              const Epetra_Vector &b,
                              Epetra_Vector       &x) const
  {
    const Level &level = levels[l];
    if (l + 1 == levels.size())
      {
        if (coarsest_solver)
          {
            *level.rhs = b;
            coarsest_solver->Solve();
            x = *level.solution;
          }
        else
          smooth(level, b, x, /*zero_start=*/true);
        return;
      }
    smooth(level, b, x, /*zero_start=*/true);
    const Level   &coarse = levels[l + 1];
    Epetra_Vector &r      = *level.residual;
    apply(level, x, r);
    r.Update(1., b, -1.);
    // restrict: coarse rhs = P^T r
    Epetra_Vector &coarse_b = *coarse.rhs;
    coarse_b.PutScalar(0.);
    const unsigned int n_null = level.n_null;
    for (int i = 0; i < r.MyLength(); ++i)
      if (const int a = level.aggregate_of_row[i]; a >= 0)
        for (unsigned int m = 0; m < n_null; ++m)
          coarse_b[a * n_null + m] += level.prolongator[i * n_null + m] * r[i];
    // coarse correction (twice in a W-cycle: the second on the residual of
    // the first; once when the coarse level is solved exactly)
    Epetra_Vector &coarse_x = *coarse.solution;
    cycle(l + 1, coarse_b, coarse_x);
    if (data.w_cycle && l + 2 < levels.size())
      {
        Epetra_Vector &coarse_r = *coarse.second_rhs,
                      &coarse_e = *coarse.second_solution;
        apply(coarse, coarse_x, coarse_r);
        coarse_r.Update(1., coarse_b, -1.);
        cycle(l + 1, coarse_r, coarse_e);
        coarse_x.Update(1., coarse_e, 1.);
      }
    // prolongate and post-smooth
    for (int i = 0; i < x.MyLength(); ++i)
      if (const int a = level.aggregate_of_row[i]; a >= 0)
        {
          double correction = 0.;
          for (unsigned int m = 0; m < n_null; ++m)
            correction +=
              level.prolongator[i * n_null + m] * coarse_x[a * n_null + m];
          x[i] += correction;
        }
    smooth(level, b, x, /*zero_start=*/false);
  }



  void
  AggregationMultigrid::vmult(LA::Vector &dst, const LA::Vector &src) const
  {
    Assert(!levels.empty(), ExcNotInitialized());
    const Epetra_Vector &b = *src.trilinos_vector()(0);
    Epetra_Vector       &x = *dst.trilinos_vector()(0);
    cycle(0, b, x);
  }



  std::vector<int>
  AggregationMultigrid::level_sizes() const
  {
    std::vector<int> sizes;
    for (const auto &level : levels)
      sizes.push_back(level.matrix->NumGlobalRows());
    return sizes;
  }
} // namespace Signorini
