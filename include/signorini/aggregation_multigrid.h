#ifndef signorini_aggregation_multigrid_h
#define signorini_aggregation_multigrid_h

#include <signorini/linear_algebra.h>

#include <Amesos_BaseSolver.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_MultiVector.h>
#include <Epetra_Vector.h>
#include <memory>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * Algebraic multigrid by plain (unsmoothed) aggregation, built for the
   * largest meshes: its memory is a fraction of one copy of K.
   *
   * What Trilinos ML does with "aggregation: damping factor" = 0 (vertices
   * grouped into aggregates of a vertex and its neighbours, the near null
   * space orthonormalised on each aggregate as the tentative prolongator P,
   * coarse operators P^T A P, Chebyshev smoothers, a direct solve on the
   * coarsest level), with two differences that halve the peak memory of the
   * setup at 1.6M DoFs:
   * - the dofs to eliminate (Dirichlet and active contact dofs, the supports)
   *   are masked when K is applied, instead of zeroed in a copy of K: the
   *   finest operator is K itself;
   * - each coarse operator is summed directly from the rows of A, block by
   *   block, instead of through the product A P (ML's largest allocation).
   *
   * vmult() applies one V- or W-cycle: a symmetric positive definite
   * preconditioner of K restricted to the free dofs (the eliminated dofs see
   * the inverse of their diagonal).
   */
  class AggregationMultigrid
  {
  public:
    struct AdditionalData
    {
      /// Degree of the Chebyshev smoother (matrix-vector products per
      /// smoothing).
      unsigned int smoother_degree = 1;
      /// Ratio of the largest to the smallest eigenvalue of D^{-1} A the
      /// smoother damps.
      double smoothing_range = 10.;
      /// W-cycles (true) or V-cycles.
      bool w_cycle = true;
      /// Coarsen until at most this many rows remain, solved directly.
      unsigned int coarsest_size = 2000;
      /// The largest number of levels.
      unsigned int max_levels = 10;
    };

    /**
     * Build the hierarchy of @p matrix (which must outlive this object)
     * with the dofs @p eliminated (by global index) masked. The dofs of a
     * vertex are @p dofs_per_vertex consecutive rows; @p near_null_space
     * (its first @p n_modes vectors: the rigid motions, or the translations)
     * spans what the aggregates must represent.
     */
    void
    initialize(const LA::SparseMatrix        &matrix,
               const std::vector<bool>       &eliminated,
               const unsigned int             dofs_per_vertex,
               const std::vector<LA::Vector> &near_null_space,
               const unsigned int             n_modes,
               const AdditionalData          &data);

    /// dst = one multigrid cycle applied to src.
    void
    vmult(LA::Vector &dst, const LA::Vector &src) const;

    /// Rows per level, finest first (global).
    std::vector<int>
    level_sizes() const;

  private:
    struct Level
    {
      /// The operator of the level (the finest: the caller's K).
      const Epetra_CrsMatrix *matrix = nullptr;
      /// The coarse operators are owned here.
      std::unique_ptr<Epetra_CrsMatrix> coarse_matrix;
      /// Finest level: the masked rows (local index); empty on the others.
      std::vector<int> masked_rows;
      /// apply()'s buffer of the masked entries of its argument
      mutable std::vector<double> masked_values;
      /// Diagonal of the operator, inverted.
      std::unique_ptr<Epetra_Vector> inverse_diagonal;
      /// Upper bound of the spectrum of D^{-1} A.
      double max_eigenvalue = 1.;
      /// Tentative prolongator to the next level: per local row its local
      /// aggregate (-1: none) and its n_null values (in single precision:
      /// P^T A P is formed from the same rounded values, so the cycle stays
      /// symmetric; CG's operator is exact)
      std::vector<int>   aggregate_of_row;
      std::vector<float> prolongator;
      unsigned int       n_null = 0;
      /// Work vectors of this level: on the coarse ones the right-hand side
      /// and solution of the correction (the coarsest: of its direct solve),
      /// and of the W-cycle's second visit; the update: for smoothers of
      /// degree > 1.
      mutable std::unique_ptr<Epetra_Vector> rhs, solution, second_rhs,
        second_solution, residual, update;
    };

    /// y = A x on @p level (masked on the finest: x is changed during the
    /// product, and restored).
    void
    apply(const Level &level, Epetra_Vector &x, Epetra_Vector &y) const;

    /// Chebyshev smoothing of A x = b, from x (zero if @p zero_start).
    void
    smooth(const Level         &level,
           const Epetra_Vector &b,
           Epetra_Vector       &x,
           const bool           zero_start) const;

    /// x = the cycle from level @p l on b.
    void
    cycle(const unsigned int l, const Epetra_Vector &b, Epetra_Vector &x) const;

    /// Largest eigenvalue of D^{-1} A by a few preconditioned CG steps.
    double
    estimate_max_eigenvalue(const Level &level) const;

    /// The inverse diagonal, the work vectors and the largest eigenvalue of
    /// @p level's matrix.
    void
    allocate_work_vectors(Level &level) const;

    /// The aggregates of @p level's rows (groups of @p block, the masked
    /// rows of the finest level left out): sets its aggregate of each row,
    /// sizes its prolongator for @p n_null columns, and returns their
    /// number with the rows of each in @p rows_of.
    int
    aggregate_rows(Level                         &level,
                   const std::vector<char>       &masked_row,
                   const unsigned int             block,
                   const unsigned int             n_null,
                   std::vector<std::vector<int>> &rows_of) const;

    /// The tentative prolongator of @p level from the near null space
    /// @p null_space on the aggregates @p rows_of; returns the coarse near
    /// null space, on @p coarse_map (n_null rows per aggregate).
    std::unique_ptr<Epetra_MultiVector>
    tentative_prolongator(Level                               &level,
                          const Epetra_MultiVector            &null_space,
                          const std::vector<std::vector<int>> &rows_of,
                          const Epetra_Map &coarse_map) const;

    /// P^T A P of @p level, on @p coarse_map.
    std::unique_ptr<Epetra_CrsMatrix>
    galerkin_product(const Level                         &level,
                     const std::vector<std::vector<int>> &rows_of,
                     const Epetra_Map                    &coarse_map) const;

    /// The direct factorisation of the coarsest level, unless it is the
    /// masked finest (then it is only smoothed).
    void
    factor_coarsest();

    AdditionalData                        data;
    std::vector<Level>                    levels;
    std::unique_ptr<Epetra_LinearProblem> coarsest_problem;
    std::unique_ptr<Amesos_BaseSolver>    coarsest_solver;
  };
} // namespace Signorini

#endif
