#ifndef signorini_linear_algebra_h
#define signorini_linear_algebra_h

#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <vector>

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

  /**
   * The entries @p indices of a distributed vector, on every rank: each
   * rank reads the entries it owns, one reduction combines them (the
   * contact nodes are few, so their data are replicated).
   */
  dealii::Vector<double>
  gather(const LA::Vector                                   &v,
         const std::vector<dealii::types::global_dof_index> &indices);

  /// The whole vector on every rank (comparisons across meshes).
  dealii::Vector<double>
  replicate(const LA::Vector &v);

  /// A copy of @p v that can also read the entries of @p ghosts.
  LA::Vector
  with_ghosts(const LA::Vector &v, const dealii::IndexSet &ghosts);

  /// max_i |v_i|, zero for an empty vector (no contact nodes).
  inline double
  max_norm(const dealii::Vector<double> &v)
  {
    return v.size() > 0 ? v.linfty_norm() : 0.;
  }
} // namespace Signorini

#endif
