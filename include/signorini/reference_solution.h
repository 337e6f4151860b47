#ifndef signorini_reference_solution_h
#define signorini_reference_solution_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/vector.h>

#include <deal.II/distributed/shared_tria.h>

#include <signorini/adaptation/adaptive_mesh.h>
#include <signorini/contact_computation.h>
#include <signorini/linear_algebra.h>
#include <signorini/mesh_input.h>
#include <signorini/phase_timer.h>

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
      /// eps_ex,E = ||U_ref - U_h||_E / ||U_ref + U_h|| per active cell E of
      /// the computation's mesh (the global denominator, as eps_E: the sum
      /// of the squares is eps_ex^2); filled by compare(), empty from
      /// compare_kept()
      Vector<double> local;
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

    /**
     * Compare (U_h, U^) of a computation on @p dof_handler with the
     * reference (no U^: an empty @p u_hat, then only eps_ex), and split
     * eps_ex^2 over the cells of the computation (Comparison::local).
     *
     * The split: the energy of U_ref - U_h on each reference cell (U_h
     * interpolated at the reference's vertices, as for eps_ex) goes to the
     * computational cell that contains the reference cell's centre, found
     * by point location (CellLocator). The hierarchy cannot be used: every
     * computational mesh is a flat triangulation (AdaptiveMesh builds the
     * conforming mesh anew, Gmsh remeshes), and a reference on the initial
     * mesh is another flat mesh, so no reference cell has a computational
     * cell as ancestor (only a final-mesh reference, a refined copy of the
     * last mesh, shares the hierarchy, and compare_kept() does not split).
     * Where the reference refines the computational mesh (uniform cycles)
     * every reference cell lies in one computational cell and the split is
     * exact; across the green edges of an adapted mesh or a remeshed mesh,
     * a reference cell the edge crosses goes whole to one side. Every rank
     * holds both meshes and splits every reference cell in the same order:
     * the same split on any number of ranks (the values differ only as
     * U_ref does, by the round-off of its solve).
     */
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
    /// compare(), with or without the split of eps_ex over the cells.
    Comparison
    comparison(const DoFHandler<dim> &dof_handler,
               const Vector<double>  &u_h,
               const Vector<double>  &u_hat,
               const double           eps,
               const double           e,
               const bool             with_local) const;

    /// ||@p difference||_E^2 (on the reference) per active cell E of the
    /// mesh of @p dof_handler, see compare().
    Vector<double>
    local_energies(const DoFHandler<dim> &dof_handler,
                   const LA::Vector      &difference) const;

    unsigned int extra_levels = 0;
    Mesh         mesh_choice  = Mesh::initial_mesh;

    /// Times of the reference's steps (not printed: the application times
    /// the reference as a whole)
    PhaseTimer                               timer;
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
