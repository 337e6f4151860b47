#include <signorini/boundary_conditions.h>
#include <signorini/input_error.h>

namespace Signorini
{
  std::set<types::boundary_id>
  parse_boundary_ids(const std::string &text, const std::string &name)
  {
    std::set<types::boundary_id> ids;
    for (const auto &entry : Utilities::split_string_list(text))
      {
        const int id = Utilities::string_to_int(entry);
        if (id < 0 || static_cast<types::boundary_id>(id) >=
                        numbers::internal_face_boundary_id)
          throw InputError(name + ": invalid boundary id <" + entry + ">");
        ids.insert(static_cast<types::boundary_id>(id));
      }
    return ids;
  }



  template <int dim>
  void
  BoundaryConditions<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Boundary conditions");
    {
      for (unsigned int p = 1; p <= max_dirichlet_parts; ++p)
        {
          prm.enter_subsection("Dirichlet " + std::to_string(p));
          prm.declare_entry("Boundary ids",
                            "",
                            Patterns::List(Patterns::Integer(0)),
                            "Boundary ids where the displacement is "
                            "prescribed (empty: part unused).");
          prm.declare_entry("Components",
                            dim == 2 ? "x, y" : "x, y, z",
                            Patterns::List(Patterns::Selection("x|y|z"),
                                           1,
                                           dim),
                            "Displacement components prescribed there "
                            "(e.g. 'y' for a roller).");
          Functions::ParsedFunction<dim>::declare_parameters(prm, dim);
          prm.leave_subsection();
        }
      for (unsigned int p = 1; p <= max_traction_parts; ++p)
        {
          prm.enter_subsection("Traction " + std::to_string(p));
          prm.declare_entry("Boundary ids",
                            "",
                            Patterns::List(Patterns::Integer(0)),
                            "Boundary ids loaded by the traction F_d "
                            "(force per unit length; empty: part unused).");
          Functions::ParsedFunction<dim>::declare_parameters(prm, dim);
          prm.leave_subsection();
        }
      prm.enter_subsection("Body force");
      Functions::ParsedFunction<dim>::declare_parameters(prm, dim);
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }



  template <int dim>
  void
  BoundaryConditions<dim>::parse_parameters(ParameterHandler &prm)
  {
    dirichlet.clear();
    tractions.clear();
    prm.enter_subsection("Boundary conditions");
    {
      for (unsigned int p = 1; p <= max_dirichlet_parts; ++p)
        {
          const std::string name = "Dirichlet " + std::to_string(p);
          prm.enter_subsection(name);
          DirichletPart part;
          part.ids =
            parse_boundary_ids(prm.get("Boundary ids"),
                               "Boundary conditions/" + name + "/Boundary ids");
          std::vector<bool> mask(dim, false);
          for (const auto &c :
               Utilities::split_string_list(prm.get("Components")))
            {
              const unsigned int component = c[0] - 'x';
              if (component >= dim)
                throw InputError("Boundary conditions/" + name +
                                 "/Components: no component <" + c + ">");
              mask[component] = true;
            }
          part.mask = ComponentMask(mask);
          part.displacement =
            parse_function<dim>(prm, dim, "Boundary conditions/" + name);
          prm.leave_subsection();
          if (!part.ids.empty())
            dirichlet.emplace_back(std::move(part));
        }
      for (unsigned int p = 1; p <= max_traction_parts; ++p)
        {
          const std::string name = "Traction " + std::to_string(p);
          prm.enter_subsection(name);
          TractionPart part;
          part.ids =
            parse_boundary_ids(prm.get("Boundary ids"),
                               "Boundary conditions/" + name + "/Boundary ids");
          part.traction =
            parse_function<dim>(prm, dim, "Boundary conditions/" + name);
          prm.leave_subsection();
          if (!part.ids.empty())
            tractions.emplace_back(std::move(part));
        }
      prm.enter_subsection("Body force");
      body_force =
        parse_function<dim>(prm, dim, "Boundary conditions/Body force");
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }



  template <int dim>
  std::set<types::boundary_id>
  BoundaryConditions<dim>::used_boundary_ids() const
  {
    std::set<types::boundary_id> ids;
    for (const auto &part : dirichlet)
      ids.insert(part.ids.begin(), part.ids.end());
    for (const auto &part : tractions)
      ids.insert(part.ids.begin(), part.ids.end());
    return ids;
  }

  namespace
  {
    /// the last of @p parts naming @p id, or nullptr
    template <typename Part>
    const Part *
    part_naming(const std::vector<Part> &parts, const types::boundary_id id)
    {
      const Part *found = nullptr;
      for (const auto &part : parts)
        if (part.ids.count(id) != 0)
          found = &part;
      return found;
    }
  } // namespace



  template <int dim>
  const typename BoundaryConditions<dim>::DirichletPart *
  BoundaryConditions<dim>::dirichlet_part(const types::boundary_id id) const
  {
    return part_naming(dirichlet, id);
  }



  template <int dim>
  const typename BoundaryConditions<dim>::TractionPart *
  BoundaryConditions<dim>::traction_part(const types::boundary_id id) const
  {
    return part_naming(tractions, id);
  }

  template class BoundaryConditions<2>;
} // namespace Signorini
