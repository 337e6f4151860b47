#ifndef signorini_reference_solution_h
#define signorini_reference_solution_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/vector.h>

#include <deal.II/distributed/shared_tria.h>

#include <signorini/adaptation/adaptive_mesh.h>
#include <signorini/contact_computation.h>
#include <signorini/mesh_input.h>

#include <memory>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * A reference solution, section "Reference solution": the same problem
   * solved once on a finer mesh (the initial mesh refined uniformly, before
   * the computations, or the last computational mesh refined uniformly,
   * after them), and the comparison of computations with it: eps_ex, the
   * effectivity of the estimate and the Prager-Synge check
   * (doc/theory.md section 7).
   */
  template <int dim>
  class ReferenceSolution
  {
  public:
    /// Which mesh is refined for the reference (Reference solution/Mesh).
    enum class Mesh
    {
      initial_mesh,
      final_mesh
    };

    /// A computation against the reference.
    struct Comparison
    {
      double eps_ex             = 0.; ///< ||U_ref - U_h|| / ||U_ref + U_h||
      double effectivity        = 0.; ///< eps / eps_ex
      double prager_synge_ratio = 0.; ///< ||U_ref - U^|| / e
    };

    static void
    declare_parameters(ParameterHandler &prm);

    ReferenceSolution();

    /// Read the section and the model the reference solves (the sections
    /// of ContactComputation in @p prm).
    void
    parse_parameters(ParameterHandler &prm);

    /// Is a reference asked for (Extra refinements > 0)?
    bool
    enabled() const;

    Mesh
    mesh() const;

    unsigned int
    extra_refinements() const;

    /// Solve on the mesh of @p input refined @p levels times. The
    /// computation is checked by the caller (computation().converged()).
    void
    solve_on_initial_mesh(const MeshInput<dim> &input,
                          const unsigned int    levels);

    /// Solve on a copy of @p fine_mesh, the active set started from
    /// @p state.
    void
    solve_on(const Triangulation<dim>                             &fine_mesh,
             const typename ContactComputation<dim>::ContactState &state);

    /// Has a reference been solved?
    bool
    solved() const;

    const ContactComputation<dim> &
    computation() const;

    /// The refinement level of a reference on the initial mesh (solved).
    unsigned int
    level() const;

    /// Compare (U_h, U^) of a computation on @p dof_handler with the
    /// reference (no U^: an empty @p u_hat, then only eps_ex).
    Comparison
    compare(const DoFHandler<dim> &dof_handler,
            const Vector<double>  &u_h,
            const Vector<double>  &u_hat,
            const double           eps,
            const double           e) const;

    /// Keep the mesh and fields of a computation for a comparison with a
    /// reference solved later (compare_kept()).
    void
    keep(const ContactComputation<dim> &computation,
         const Vector<double>          &u_hat,
         const double                   eps,
         const double                   e);

    /// The kept computations against the reference, in order.
    std::vector<Comparison>
    compare_kept() const;

  private:
    unsigned int extra_levels = 0;
    Mesh         mesh_choice  = Mesh::initial_mesh;

    /// Times of the reference's steps (not printed: the application times
    /// the reference as a whole)
    TimerOutput                              timer;
    parallel::shared::Triangulation<dim>     triangulation;
    AdaptiveMesh<dim>                        adaptive_mesh;
    std::unique_ptr<ContactComputation<dim>> reference;
    bool                                     is_solved = false;

    /// What a later comparison needs of each computation
    struct Computation
    {
      Triangulation<dim> mesh;
      DoFHandler<dim>    dof_handler;
      Vector<double>     displacement;
      Vector<double>     admissible_displacement;
      double             eps = 0.;
      double             e   = 0.;
    };
    std::vector<std::unique_ptr<Computation>> computations;
  };
} // namespace Signorini

#endif
