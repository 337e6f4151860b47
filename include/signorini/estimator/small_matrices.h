#ifndef signorini_estimator_small_matrices_h
#define signorini_estimator_small_matrices_h

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

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
     * The Cholesky factor of a symmetric positive semi-definite @p matrix
     * into its lower triangle, leaving out (a zero column of L) every row
     * whose pivot is not above @p relative_tolerance times its own diagonal
     * entry: a row that depends on the earlier ones. cholesky_solve() with
     * it gives the solution with zero in those entries, a solution of the
     * system if it is consistent. Returns the number of rows left out.
     */
    unsigned int
    semidefinite_cholesky(FullMatrix<double> &matrix,
                          const double        relative_tolerance);

    /// Solve L L^T x = b in place (@p b becomes x) with the factor L of
    /// cholesky() (its lower triangle), or of semidefinite_cholesky() (x is
    /// zero where L has a zero diagonal entry).
    void
    cholesky_solve(const FullMatrix<double> &factor, Vector<double> &b);

    /**
     * A basis (columns, not orthonormal) of the kernel of the m x n matrix
     * @p rows: Gaussian elimination with complete pivoting brings it to
     * [U1 U2] (up to a permutation of the columns), U1 r x r upper
     * triangular, r the numerical rank (pivots above 1e-10 times the
     * first); the basis is [-U1^-1 U2; I]. Complete pivoting keeps the
     * entries of U1^-1 U2 moderate. About half the cost of a Householder QR
     * with column pivoting (a dense 18 x 24 matrix, the size of a vertex
     * patch's constraints: 4.3 against 7.9 microseconds), less on the
     * sparse constraint matrices, whose zero entries it skips.
     */
    FullMatrix<double>
    kernel_basis(const FullMatrix<double> &rows);
  } // namespace SmallMatrices
} // namespace Signorini

#endif
