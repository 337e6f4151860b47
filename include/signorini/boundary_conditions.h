#ifndef signorini_boundary_conditions_h
#define signorini_boundary_conditions_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>

#include <deal.II/fe/component_mask.h>
#include <deal.II/fe/mapping.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/vector.h>

#include <signorini/load_path.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * The data of the elastic problem other than contact: prescribed
   * displacements (part G1, any component mask), tractions F_d (part G2) and
   * the body force f_d. Each Dirichlet or traction part is a numbered
   * subsection with a list of boundary ids and a parsed vector function of
   * (x, y), or (x, y, z) in 3D (components separated by ';'); unused parts
   * have no ids.
   *
   * Several parts may name the same boundary id: Dirichlet parts with
   * disjoint components (e.g. x by one part, y by another), traction parts
   * whose loads add up.
   */
  template <int dim>
  class BoundaryConditions
  {
  public:
    static constexpr unsigned int max_dirichlet_parts = 3;
    static constexpr unsigned int max_traction_parts  = 4;

    struct DirichletPart
    {
      /// The parameter subsection, e.g. "Boundary conditions/Dirichlet 2",
      /// for messages.
      std::string                            name;
      std::set<types::boundary_id>           ids;
      ComponentMask                          mask;
      std::unique_ptr<LoadPathFunction<dim>> displacement;
    };

    struct TractionPart
    {
      /// The parameter subsection, e.g. "Boundary conditions/Traction 1".
      std::string                            name;
      std::set<types::boundary_id>           ids;
      std::unique_ptr<LoadPathFunction<dim>> traction;
    };

    /// The largest magnitudes of the data where they are used.
    struct DataMagnitudes
    {
      double displacement = 0.; ///< prescribed Dirichlet components
      double traction     = 0.;
      double body_force   = 0.;
    };

    static void
    declare_parameters(ParameterHandler &prm);

    /// Read the parts; two Dirichlet parts prescribing the same component
    /// on the same boundary id are an InputError.
    void
    parse_parameters(ParameterHandler &prm);

    /// Every datum at step @p step of @p path (after parsing: the data of
    /// step 1 of 1, the static problem).
    void
    set_load_step(const LoadPath &path, const unsigned int step);

    /**
     * Throw an InputError naming the parameter and the point unless every
     * function is finite where it is used on @p triangulation: each
     * Dirichlet displacement (its prescribed components) and each traction
     * at the vertices and face quadrature points of the boundary faces with
     * its ids, the body force, and @p exact_solution if not null, at the
     * vertices and cell quadrature points (the quadrature rules of the
     * assembly). Called for every mesh: refined meshes have new points.
     * Returns the largest magnitudes found.
     */
    DataMagnitudes
    check_finite(const Mapping<dim>       &mapping,
                 const Triangulation<dim> &triangulation,
                 const Function<dim>      *exact_solution = nullptr) const;

    /// Every boundary id named by a Dirichlet or traction part.
    std::set<types::boundary_id>
    used_boundary_ids() const;

    /// The components prescribed on boundary @p id by all Dirichlet parts
    /// naming it (none selected if there is no such part).
    ComponentMask
    dirichlet_mask(const types::boundary_id id) const;

    /// Whether some traction part names boundary @p id.
    bool
    has_traction(const types::boundary_id id) const;

    /// The traction on boundary @p id at @p points: the sum over all
    /// traction parts naming it (zero if there is none).
    void
    traction_values(const types::boundary_id       id,
                    const std::vector<Point<dim>> &points,
                    std::vector<Vector<double>>   &values) const;

    std::vector<DirichletPart>             dirichlet;
    std::vector<TractionPart>              tractions;
    std::unique_ptr<LoadPathFunction<dim>> body_force;
    /// Whether every component of the body force is the literal constant 0
    /// (the element equilibration and check_finite() then skip its
    /// evaluation per cell).
    bool body_force_zero = false;
  };

  /// Parse a comma separated list of boundary ids; @p name is used in errors.
  std::set<types::boundary_id>
  parse_boundary_ids(const std::string &text, const std::string &name);
} // namespace Signorini

#endif
