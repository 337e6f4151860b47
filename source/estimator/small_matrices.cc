#include <signorini/estimator/small_matrices.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace Signorini
{
  namespace SmallMatrices
  {
    namespace
    {
      /**
       * The Cholesky factor of @p matrix into its lower triangle. A pivot
       * of row j not above @p tolerance(j) ends it with -1 if
       * @p drop_small is false; otherwise the row is left out (a zero
       * column of L). Returns the number of rows left out.
       */
      template <typename Tolerance>
      int
      factorise(FullMatrix<double> &matrix,
                const Tolerance    &tolerance,
                const bool          drop_small)
      {
        const unsigned int n       = matrix.m();
        int                dropped = 0;
        for (unsigned int j = 0; j < n; ++j)
          {
            double pivot = matrix(j, j);
            for (unsigned int k = 0; k < j; ++k)
              pivot -= matrix(j, k) * matrix(j, k);
            if (!(pivot > tolerance(j)) || !(pivot > 0.))
              {
                if (!drop_small)
                  return -1;
                for (unsigned int i = j; i < n; ++i)
                  matrix(i, j) = 0.;
                ++dropped;
                continue;
              }
            matrix(j, j) = std::sqrt(pivot);
            for (unsigned int i = j + 1; i < n; ++i)
              {
                double value = matrix(i, j);
                for (unsigned int k = 0; k < j; ++k)
                  value -= matrix(i, k) * matrix(j, k);
                matrix(i, j) = value / matrix(j, j);
              }
          }
        return dropped;
      }
    } // namespace



    bool
    cholesky(FullMatrix<double> &matrix, const double relative_tolerance)
    {
      double largest = 0.;
      for (unsigned int i = 0; i < matrix.m(); ++i)
        largest = std::max(largest, matrix(i, i));
      const double tolerance = relative_tolerance * largest;
      return factorise(
               matrix,
               [tolerance](unsigned int) { return tolerance; },
               false) == 0;
    }



    unsigned int
    semidefinite_cholesky(FullMatrix<double> &matrix,
                          const double        relative_tolerance)
    {
      // (row j's diagonal entry is still the original one when j is reached)
      return factorise(
        matrix,
        [&matrix, relative_tolerance](const unsigned int j) {
          return relative_tolerance * matrix(j, j);
        },
        true);
    }



    void
    cholesky_solve(const FullMatrix<double> &factor, Vector<double> &b)
    {
      const unsigned int n = factor.m();
      for (unsigned int i = 0; i < n; ++i)
        {
          if (factor(i, i) == 0.)
            {
              b[i] = 0.;
              continue;
            }
          double value = b[i];
          for (unsigned int k = 0; k < i; ++k)
            value -= factor(i, k) * b[k];
          b[i] = value / factor(i, i);
        }
      for (unsigned int i = n; i-- > 0;)
        {
          if (factor(i, i) == 0.)
            continue;
          double value = b[i];
          for (unsigned int k = i + 1; k < n; ++k)
            value -= factor(k, i) * b[k];
          b[i] = value / factor(i, i);
        }
    }



    FullMatrix<double>
    kernel_basis(const FullMatrix<double> &rows)
    {
      const unsigned int m = rows.m(), n = rows.n();
      // (work space reused by each thread: it is called once per patch)
      thread_local std::vector<double>       a, z;
      thread_local std::vector<unsigned int> permutation;
      a.resize(m * n); // row by row
      for (unsigned int i = 0; i < m; ++i)
        for (unsigned int j = 0; j < n; ++j)
          a[i * n + j] = rows(i, j);
      // column j of a is column permutation[j] of rows
      permutation.resize(n);
      for (unsigned int j = 0; j < n; ++j)
        permutation[j] = j;

      // Gaussian elimination with complete pivoting, to an upper
      // trapezoidal [U1 U2] of rank r (pivots above 1e-10 times the first)
      unsigned int rank        = 0;
      double       first_pivot = 0.;
      for (unsigned int k = 0; k < std::min(m, n); ++k)
        {
          unsigned int pivot_row = k, pivot_column = k;
          double       largest = -1.;
          for (unsigned int i = k; i < m; ++i)
            for (unsigned int j = k; j < n; ++j)
              if (std::abs(a[i * n + j]) > largest)
                {
                  largest      = std::abs(a[i * n + j]);
                  pivot_row    = i;
                  pivot_column = j;
                }
          if (k == 0)
            first_pivot = largest;
          if (!(largest > 1e-10 * first_pivot))
            break;
          if (pivot_row != k)
            for (unsigned int j = 0; j < n; ++j)
              std::swap(a[k * n + j], a[pivot_row * n + j]);
          if (pivot_column != k)
            {
              for (unsigned int i = 0; i < m; ++i)
                std::swap(a[i * n + k], a[i * n + pivot_column]);
              std::swap(permutation[k], permutation[pivot_column]);
            }
          const double *const pivot = &a[k * n];
          for (unsigned int i = k + 1; i < m; ++i)
            {
              double *const row = &a[i * n];
              if (row[k] == 0.) // (the patch systems are sparse)
                continue;
              const double factor = row[k] / pivot[k];
              for (unsigned int j = k + 1; j < n; ++j)
                row[j] -= factor * pivot[j];
              row[k] = 0.;
            }
          ++rank;
        }

      // the kernel [-U1^-1 U2; I], back in the original column order
      FullMatrix<double> basis(n, n - rank);
      z.resize(rank);
      for (unsigned int c = rank; c < n; ++c)
        {
          for (unsigned int i = rank; i-- > 0;)
            {
              const double *const row   = &a[i * n];
              double              value = -row[c];
              for (unsigned int j = i + 1; j < rank; ++j)
                value -= row[j] * z[j];
              z[i] = value / row[i];
            }
          for (unsigned int i = 0; i < rank; ++i)
            basis(permutation[i], c - rank) = z[i];
          basis(permutation[c], c - rank) = 1.;
        }
      return basis;
    }
  } // namespace SmallMatrices
} // namespace Signorini
