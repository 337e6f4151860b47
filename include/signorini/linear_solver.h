#ifndef signorini_linear_solver_h
#define signorini_linear_solver_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_precondition.h>

#include <signorini/aggregation_multigrid.h>
#include <signorini/linear_algebra.h>

#include <Epetra_MultiVector.h>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

class Amesos_BaseSolver;
class Epetra_LinearProblem;

namespace Signorini
{
  using namespace dealii;

  /**
   * Solves linear elasticity problems K u = f under a set of affine
   * constraints that changes from call to call (hanging nodes and Dirichlet
   * data always, plus the active contact constraints of the current active
   * set), without reassembling K.
   *
   * The system solved is deal.II's constrained form
   *   (C^T K C + Id_c) u = C^T (f - K k) + Id_c k
   * (see constrained_linear_operator()), by CG. The preconditioner is built
   * from a copy of K in which the constrained dofs of the base constraints
   * (and of a recent active set) are eliminated, i.e. their rows and columns
   * zeroed but for the diagonal: a sparse direct factorisation on small
   * meshes (then the base problem converges in one CG step and a changed
   * active set in a few), Trilinos ML algebraic multigrid on large ones.
   * Restricted to the dofs left free by the current constraints it stays
   * symmetric positive definite. (A hanging node eliminated rather than
   * condensed only weakens the preconditioner: the operator is exact.) K and
   * that copy are the only matrices: no condensed K is stored. With
   * Linear solver/AMG/Low memory, K is the only one: AggregationMultigrid
   * masks the eliminated dofs in its products instead.
   */
  class ElasticitySolver
  {
  public:
    ElasticitySolver();
    ~ElasticitySolver();

    /// Entries (row, column, value) added to K: friction's springs.
    using Springs = std::vector<
      std::tuple<types::global_dof_index, types::global_dof_index, double>>;

    /// The preconditioner of the CG solves (Linear solver/Type).
    enum class Type
    {
      /// direct up to direct_solver_limit DoFs, AMG above
      automatic,
      /// sparse direct factorisation
      direct,
      /// Trilinos ML algebraic multigrid
      amg_cg
    };

    /// Section Linear solver.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read it.
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * @p stiffness is the unconstrained K (singular without its constraints),
     * @p base_constraints the constraints every solve has (hanging nodes,
     * Dirichlet data), whose dofs the preconditioner eliminates; @p
     * constant_modes the translation modes per component and @p rigid_motions
     * the translations then rotations as vectors, the near null space of AMG
     * (Linear solver/AMG/Null space). The preconditioners always eliminate @p
     * support_dofs (see RigidMotions) too: with them the eliminated matrix is
     * invertible even for a body held only by the contact, whose operators
     * differ from it by a low-rank term.
     *
     * With @p prefer_direct (and Type automatic) the direct factorisation
     * is used whatever the size. No preconditioner is built yet: the first
     * update_preconditioner() or solve() builds the one it needs (a solve
     * started from a guess of the active set builds only the preconditioner of
     * that set).
     */
    void
    initialize(const LA::SparseMatrix                     &stiffness,
               const AffineConstraints<double>            &base_constraints,
               const std::vector<std::vector<bool>>       &constant_modes,
               const std::vector<LA::Vector>              &rigid_motions,
               const std::vector<types::global_dof_index> &support_dofs = {},
               const bool prefer_direct = false);

    /**
     * Rebuild the preconditioner from K with the base constraints' dofs and
     * the given dofs eliminated as if they carried homogeneous Dirichlet
     * data: the active contact constraints of an active set, so that CG on
     * that set converges as fast as on the base problem. (For the integral
     * condition an active dof is in fact tied to its neighbours; the
     * difference is a low-rank perturbation CG resolves in a few steps.)
     * @p springs (row, column, value), in K's pattern, are added to the
     * rows and columns that remain (friction's sliding nodes; not by the
     * low-memory hierarchy, which masks K itself). An empty list restores
     * the base preconditioner.
     */
    void
    update_preconditioner(
      const std::vector<types::global_dof_index> &eliminated_dofs,
      const Springs                              &springs = {});

    /**
     * Solve with the constraints @p constraints (closed), the unconstrained
     * load @p load, starting from @p solution. Returns the CG iterations.
     * A @p relative_tolerance of zero means the parameter's value. Builds
     * the base preconditioner if none is built. @p springs (row, column,
     * value) are added to K as a symmetric matrix S, which like K acts on
     * the constrained vector (C^T (K + S) C; the friction of sliding nodes
     * in 3D); the preconditioner does not see them.
     */
    unsigned int
    solve(const AffineConstraints<double> &constraints,
          const LA::Vector                &load,
          LA::Vector                      &solution,
          const double                     relative_tolerance = 0.,
          const Springs                   &springs            = {});

    /// Free the preconditioner (its matrix and its hierarchy or
    /// factorisation); the next solve() or update_preconditioner() builds
    /// one again.
    void
    release_preconditioner();

    /// Whether initialize() chose the direct factorisation.
    bool
    uses_direct_solver() const;

    /// "direct (Amesos_Klu)" or "AMG-CG": what initialize() chose.
    std::string
    method() const;

    /// The preconditioner asked for.
    Type type = Type::automatic;
    /// Trilinos Amesos package of the direct factorisation, or "automatic"
    /// (chosen by the dimension in initialize()).
    std::string direct_package = "automatic";
    /// With Type::automatic: the largest problem solved with the direct
    /// factorisation.
    types::global_dof_index direct_solver_limit = 10000;
    /// Relative residual reduction asked of CG.
    double relative_tolerance = 1e-10;
    /// CG iteration limit per solve.
    unsigned int max_iterations = 5000;

  private:
    /// (Re)build the direct factorisation or the AMG hierarchy of @p matrix.
    void
    build_preconditioner(const LA::SparseMatrix &matrix);

    /// K (unconstrained)
    const LA::SparseMatrix *stiffness_matrix = nullptr;
    /// The dofs of the base constraints and the supports, sorted.
    std::vector<types::global_dof_index> base_eliminated_dofs;
    /// K with the base and the active dofs eliminated, the matrix of the
    /// preconditioner (update_preconditioner())
    LA::SparseMatrix modified_matrix;
    /// Translation modes per component, for AMG
    std::vector<std::vector<bool>> translation_modes;
    /// Translations and rotations, the near null space of AMG
    const std::vector<LA::Vector> *rigid_motions = nullptr;
    /// Linear solver/AMG: give AMG the rotations too?
    bool with_rotations = true;
    /// Linear solver/AMG: ML's aggregation threshold
    double aggregation_threshold = 0.;
    /// Linear solver/AMG: smoother sweeps
    unsigned int smoother_sweeps = 1;
    /// Linear solver/AMG: W-cycles rather than V-cycles?
    bool w_cycle = true;
    /// Linear solver/AMG: smoothed (true) or plain aggregation?
    bool smoothed_aggregation = true;
    /// Linear solver/AMG: our own plain aggregation from K, no copy of K?
    bool low_memory = false;
    /// The near null space handed to ML (which reads it at setup)
    std::unique_ptr<Epetra_MultiVector> null_space;
    /// The active dofs eliminated in the current preconditioner (sorted),
    /// {invalid} when none is built
    std::vector<types::global_dof_index> current_eliminated_dofs;
    /// Whether the preconditioner was built with springs.
    bool preconditioned_springs = false;
    /// What initialize() chose: direct factorisation or AMG
    bool use_direct = true;
    /// The Amesos package initialize() chose.
    std::string package = "Amesos_Klu";
    /// The direct factorisation's problem, whose operator is modified_matrix
    std::unique_ptr<Epetra_LinearProblem> direct_problem;
    /// The direct factorisation. Eliminations keep modified_matrix's pattern
    /// (the entries are zeroed, not removed), so its symbolic factorisation
    /// is made once per stiffness matrix and each active set only factorises
    /// the values again.
    std::unique_ptr<Amesos_BaseSolver> direct;
    /// The matrix whose pattern direct has analysed. (modified_matrix's
    /// copy_from() keeps its Epetra matrix when the pattern is the same and
    /// allocates a new one, at another address, when it is not.)
    const Epetra_CrsMatrix *analysed_matrix = nullptr;
    /// The AMG hierarchy
    std::unique_ptr<TrilinosWrappers::PreconditionAMG> amg;
    /// The low-memory AMG hierarchy (Linear solver/AMG/Low memory)
    std::unique_ptr<AggregationMultigrid> aggregation_amg;
  };
} // namespace Signorini

#endif
