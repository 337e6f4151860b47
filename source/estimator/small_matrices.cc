#include <signorini/estimator/small_matrices.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace Signorini
{
  namespace SmallMatrices
  {
    bool
    cholesky(FullMatrix<double> &matrix, const double relative_tolerance)
    {
      const unsigned int n       = matrix.m();
      double             largest = 0.;
      for (unsigned int i = 0; i < n; ++i)
        largest = std::max(largest, matrix(i, i));
      for (unsigned int j = 0; j < n; ++j)
        {
          double pivot = matrix(j, j);
          for (unsigned int k = 0; k < j; ++k)
            pivot -= matrix(j, k) * matrix(j, k);
          if (!(pivot > relative_tolerance * largest) || !(pivot > 0.))
            return false;
          matrix(j, j) = std::sqrt(pivot);
          for (unsigned int i = j + 1; i < n; ++i)
            {
              double value = matrix(i, j);
              for (unsigned int k = 0; k < j; ++k)
                value -= matrix(i, k) * matrix(j, k);
              matrix(i, j) = value / matrix(j, j);
            }
        }
      return true;
    }



    FullMatrix<double>
    kernel_basis(const FullMatrix<double> &rows)
    {
      const unsigned int m = rows.m(), n = rows.n();
      // the columns of rows^T, i.e. the rows, each of length n
      std::vector<double> a(m * n);
      for (unsigned int j = 0; j < m; ++j)
        for (unsigned int i = 0; i < n; ++i)
          a[j * n + i] = rows(j, i);
      std::vector<double> tau;
      double              first_pivot = 0.;
      for (unsigned int k = 0; k < std::min(m, n); ++k)
        {
          // the remaining column of largest norm (below row k)
          unsigned int pivot             = k;
          double       pivot_norm_square = -1.;
          for (unsigned int j = k; j < m; ++j)
            {
              double norm_square = 0.;
              for (unsigned int i = k; i < n; ++i)
                norm_square += a[j * n + i] * a[j * n + i];
              if (norm_square > pivot_norm_square)
                {
                  pivot             = j;
                  pivot_norm_square = norm_square;
                }
            }
          const double norm = std::sqrt(pivot_norm_square);
          if (k == 0)
            first_pivot = norm;
          if (!(norm > 1e-10 * first_pivot))
            break;
          if (pivot != k)
            for (unsigned int i = 0; i < n; ++i)
              std::swap(a[k * n + i], a[pivot * n + i]);
          // the reflector I - t v v^T with v stored in place (v_k = x_k -
          // alpha), zeroing column k below row k
          double *const v     = &a[k * n];
          const double  alpha = v[k] >= 0. ? -norm : norm;
          v[k] -= alpha;
          const double t = 1. / (norm * (norm + std::abs(v[k] + alpha)));
          tau.push_back(t);
          for (unsigned int j = k + 1; j < m; ++j)
            {
              double *const w   = &a[j * n];
              double        dot = 0.;
              for (unsigned int i = k; i < n; ++i)
                dot += v[i] * w[i];
              dot *= t;
              for (unsigned int i = k; i < n; ++i)
                w[i] -= dot * v[i];
            }
        }
      const unsigned int rank = tau.size();

      // Q e_c for c = rank..n-1: the reflectors applied in reverse order
      FullMatrix<double>  basis(n, n - rank);
      std::vector<double> column(n);
      for (unsigned int c = rank; c < n; ++c)
        {
          std::fill(column.begin(), column.end(), 0.);
          column[c] = 1.;
          for (unsigned int k = rank; k-- > 0;)
            {
              const double *const v   = &a[k * n];
              double              dot = 0.;
              for (unsigned int i = k; i < n; ++i)
                dot += v[i] * column[i];
              dot *= tau[k];
              for (unsigned int i = k; i < n; ++i)
                column[i] -= dot * v[i];
            }
          for (unsigned int i = 0; i < n; ++i)
            basis(i, c - rank) = column[i];
        }
      return basis;
    }
  } // namespace SmallMatrices
} // namespace Signorini
