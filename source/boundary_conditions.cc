#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>

#include <signorini/boundary_conditions.h>
#include <signorini/function_check.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cstdlib>

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
                            std::string("Boundary ids loaded by the traction "
                                        "F_d (force per unit ") +
                              (dim == 2 ? "length" : "area") +
                              "; empty: part unused).");
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
          part.name = "Boundary conditions/" + name;
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
          part.mask         = ComponentMask(mask);
          part.displacement = std::make_unique<LoadPathFunction<dim>>(
            parse_function<dim>(prm, dim, "Boundary conditions/" + name));
          prm.leave_subsection();
          // The solver would apply both values (the last one wins) and the
          // estimator needs one prescribed value per component: refuse.
          for (const auto &earlier : dirichlet)
            for (const auto id : part.ids)
              if (earlier.ids.count(id) != 0)
                for (unsigned int c = 0; c < dim; ++c)
                  if (part.mask[c] && earlier.mask[c])
                    throw InputError(
                      part.name + ": boundary id " + std::to_string(id) +
                      ", component " + static_cast<char>('x' + c) +
                      " is already prescribed by " +
                      earlier.name.substr(earlier.name.find('/') + 1));
          if (!part.ids.empty())
            dirichlet.emplace_back(std::move(part));
        }
      for (unsigned int p = 1; p <= max_traction_parts; ++p)
        {
          const std::string name = "Traction " + std::to_string(p);
          prm.enter_subsection(name);
          TractionPart part;
          part.name = "Boundary conditions/" + name;
          part.ids =
            parse_boundary_ids(prm.get("Boundary ids"),
                               "Boundary conditions/" + name + "/Boundary ids");
          part.traction = std::make_unique<LoadPathFunction<dim>>(
            parse_function<dim>(prm, dim, "Boundary conditions/" + name));
          prm.leave_subsection();
          if (!part.ids.empty())
            tractions.emplace_back(std::move(part));
        }
      prm.enter_subsection("Body force");
      body_force = std::make_unique<LoadPathFunction<dim>>(
        parse_function<dim>(prm, dim, "Boundary conditions/Body force"));
      body_force_zero = true;
      for (const std::string &component :
           Utilities::split_string_list(prm.get("Function expression"), ';'))
        {
          char        *end   = nullptr;
          const double value = std::strtod(component.c_str(), &end);
          if (end == component.c_str() || *end != '\0' || value != 0.)
            body_force_zero = false;
        }
      prm.leave_subsection();
    }
    prm.leave_subsection();
    set_load_step(LoadPath(), 1);
  }



  template <int dim>
  void
  BoundaryConditions<dim>::set_load_step(const LoadPath    &path,
                                         const unsigned int step)
  {
    for (auto &part : dirichlet)
      part.displacement->set_step(path, step);
    for (auto &part : tractions)
      part.traction->set_step(path, step);
    body_force->set_step(path, step);
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

  template <int dim>
  typename BoundaryConditions<dim>::DataMagnitudes
  BoundaryConditions<dim>::check_finite(
    const Mapping<dim>       &mapping,
    const Triangulation<dim> &triangulation,
    const Function<dim>      *exact_solution) const
  {
    // the quadrature rules of the assembly; only the points are needed
    const FE_SimplexP<dim>       fe(1);
    const QGaussSimplex<dim>     quadrature(3);
    const QGaussSimplex<dim - 1> face_quadrature(3);
    FEValues<dim> fe_values(mapping, fe, quadrature, update_quadrature_points);
    FEFaceValues<dim>       fe_face_values(mapping,
                                     fe,
                                     face_quadrature,
                                     update_quadrature_points);
    std::vector<Point<dim>> points;
    DataMagnitudes          largest;

    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const types::boundary_id id = cell->face(f)->boundary_id();
            fe_face_values.reinit(cell, f);
            points = fe_face_values.get_quadrature_points();
            for (const unsigned int v : cell->face(f)->vertex_indices())
              points.push_back(cell->face(f)->vertex(v));
            for (const auto &part : dirichlet)
              if (part.ids.count(id) != 0)
                largest.displacement =
                  std::max(largest.displacement,
                           Signorini::check_finite(
                             *part.displacement, points, part.name, part.mask));
            for (const auto &part : tractions)
              if (part.ids.count(id) != 0)
                largest.traction = std::max(
                  largest.traction,
                  Signorini::check_finite(*part.traction, points, part.name));
          }

    // the vertices once, then the quadrature points of each cell
    points.clear();
    for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
      if (triangulation.get_used_vertices()[v])
        points.push_back(triangulation.get_vertices()[v]);
    // (a body force of plain zeros is finite everywhere: its values are
    // not evaluated at every cell)
    if (!body_force_zero)
      largest.body_force =
        Signorini::check_finite(*body_force,
                                points,
                                "Boundary conditions/Body force");
    if (exact_solution != nullptr)
      Signorini::check_finite(*exact_solution, points, "Exact solution");
    if (body_force_zero && exact_solution == nullptr)
      return largest;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        fe_values.reinit(cell);
        if (!body_force_zero)
          largest.body_force =
            std::max(largest.body_force,
                     Signorini::check_finite(*body_force,
                                             fe_values.get_quadrature_points(),
                                             "Boundary conditions/Body force"));
        if (exact_solution != nullptr)
          Signorini::check_finite(*exact_solution,
                                  fe_values.get_quadrature_points(),
                                  "Exact solution");
      }
    return largest;
  }



  template <int dim>
  ComponentMask
  BoundaryConditions<dim>::dirichlet_mask(const types::boundary_id id) const
  {
    std::vector<bool> mask(dim, false);
    for (const auto &part : dirichlet)
      if (part.ids.count(id) != 0)
        for (unsigned int c = 0; c < dim; ++c)
          mask[c] = mask[c] || part.mask[c];
    return ComponentMask(mask);
  }



  template <int dim>
  bool
  BoundaryConditions<dim>::has_traction(const types::boundary_id id) const
  {
    for (const auto &part : tractions)
      if (part.ids.count(id) != 0)
        return true;
    return false;
  }



  template <int dim>
  void
  BoundaryConditions<dim>::traction_values(
    const types::boundary_id       id,
    const std::vector<Point<dim>> &points,
    std::vector<Vector<double>>   &values) const
  {
    values.assign(points.size(), Vector<double>(dim));
    std::vector<Vector<double>> part_values(points.size(), Vector<double>(dim));
    for (const auto &part : tractions)
      if (part.ids.count(id) != 0)
        {
          part.traction->vector_value_list(points, part_values);
          for (unsigned int q = 0; q < points.size(); ++q)
            values[q] += part_values[q];
        }
  }

  template class BoundaryConditions<2>;
  template class BoundaryConditions<3>;
} // namespace Signorini
