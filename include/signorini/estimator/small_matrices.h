#ifndef signorini_estimator_small_matrices_h
#define signorini_estimator_small_matrices_h

#include <deal.II/lac/full_matrix.h>

namespace Signorini
{
  using namespace dealii;

  /**
   * Dense linear algebra on the small matrices of the patch problems (tens
   * of rows), written out because they are solved by the hundred thousand
   * on the worker threads, where the per-call overhead of LAPACK dominated.
   */
  namespace SmallMatrices
  {
    /**
     * Replace the lower triangle of the symmetric @p matrix by its Cholesky
     * factor L (matrix = L L^T; the upper triangle is left as it was).
     * Returns false, with the matrix partly overwritten, when a pivot is not
     * above @p relative_tolerance times the largest diagonal entry (not
     * positive definite, numerically).
     */
    bool
    cholesky(FullMatrix<double> &matrix, const double relative_tolerance = 0.);

    /**
     * An orthonormal basis (columns) of the kernel of the m x n matrix
     * @p rows: the last n - r columns of Q in the Householder QR with column
     * pivoting of rows^T = Q R, r its numerical rank (pivots above 1e-10
     * times the first).
     */
    FullMatrix<double>
    kernel_basis(const FullMatrix<double> &rows);
  } // namespace SmallMatrices
} // namespace Signorini

#endif
