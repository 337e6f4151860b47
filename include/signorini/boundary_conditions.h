#ifndef signorini_boundary_conditions_h
#define signorini_boundary_conditions_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>

#include <deal.II/fe/component_mask.h>

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
   * (x, y) (components separated by ';'); unused parts have no ids.
   */
  template <int dim>
  class BoundaryConditions
  {
  public:
    static constexpr unsigned int max_dirichlet_parts = 3;
    static constexpr unsigned int max_traction_parts  = 4;

    struct DirichletPart
    {
      std::set<types::boundary_id>                    ids;
      ComponentMask                                   mask;
      std::unique_ptr<Functions::ParsedFunction<dim>> displacement;
    };

    struct TractionPart
    {
      std::set<types::boundary_id>                    ids;
      std::unique_ptr<Functions::ParsedFunction<dim>> traction;
    };

    static void
    declare_parameters(ParameterHandler &prm);

    void
    parse_parameters(ParameterHandler &prm);

    /// Every boundary id named by a Dirichlet or traction part.
    std::set<types::boundary_id>
    used_boundary_ids() const;

    /// The Dirichlet part naming boundary @p id, or nullptr.
    const DirichletPart *
    dirichlet_part(const types::boundary_id id) const;

    /// The traction part naming boundary @p id, or nullptr.
    const TractionPart *
    traction_part(const types::boundary_id id) const;

    std::vector<DirichletPart>                      dirichlet;
    std::vector<TractionPart>                       tractions;
    std::unique_ptr<Functions::ParsedFunction<dim>> body_force;
  };

  /// Parse a comma separated list of boundary ids; @p name is used in errors.
  std::set<types::boundary_id>
  parse_boundary_ids(const std::string &text, const std::string &name);
} // namespace Signorini

#endif
