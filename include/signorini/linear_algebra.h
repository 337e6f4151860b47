#ifndef signorini_linear_algebra_h
#define signorini_linear_algebra_h

#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

namespace Signorini
{
  /**
   * The global linear algebra types. They are Trilinos' distributed objects
   * even in a serial run (one rank owning every row), so that the MPI version
   * only has to hand them partitioned index sets.
   */
  namespace LA
  {
    using Vector       = dealii::TrilinosWrappers::MPI::Vector;
    using SparseMatrix = dealii::TrilinosWrappers::SparseMatrix;
  } // namespace LA

  /// max_i |v_i|, zero for an empty vector (no contact nodes).
  inline double
  max_norm(const dealii::Vector<double> &v)
  {
    return v.size() > 0 ? v.linfty_norm() : 0.;
  }
} // namespace Signorini

#endif
