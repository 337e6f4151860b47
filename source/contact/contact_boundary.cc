#include <deal.II/base/bounding_box.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <signorini/boundary_conditions.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/discretisation_check.h>
#include <signorini/function_check.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// The value of Contact/Direction that asks for the normal of GC.
    const std::string outward_normal = "outward normal";

    /// "(x, y)" or "(x, y, z)" with a few digits, for messages
    template <int dim>
    std::string
    point_text(const Point<dim> &p)
    {
      std::ostringstream text;
      text.precision(4);
      text << "(";
      for (unsigned int d = 0; d < dim; ++d)
        text << (d > 0 ? ", " : "") << p[d];
      text << ")";
      return text.str();
    }
  } // namespace



  template <int dim>
  void
  ContactBoundary<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    {
      prm.declare_entry("Boundary ids",
                        "",
                        Patterns::List(Patterns::Integer(0)),
                        "Boundary ids forming the candidate contact part GC "
                        "(empty: pure elasticity).");
      prm.declare_entry("Direction",
                        outward_normal,
                        Patterns::Anything(),
                        std::string("Unit vector nu_c from the body into "
                                    "the foundation, as ") +
                          (dim == 2 ? "'x, y'" : "'x, y, z'") +
                          " (normalised on input), or 'outward normal' for a "
                          "flat GC.");
      prm.enter_subsection("Gap");
      Functions::ParsedFunction<dim>::declare_parameters(prm, 1);
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }



  template <int dim>
  void
  ContactBoundary<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    {
      ids = parse_boundary_ids(prm.get("Boundary ids"), "Contact/Boundary ids");
      const std::string direction_text = prm.get("Direction");
      use_outward_normal               = (direction_text == outward_normal);
      if (!use_outward_normal)
        {
          const auto entries = Utilities::split_string_list(direction_text);
          if (entries.size() != dim)
            throw InputError("Contact/Direction = <" + direction_text +
                             ">: expected '" + outward_normal + "' or " +
                             std::to_string(dim) + " numbers");
          try
            {
              for (unsigned int d = 0; d < dim; ++d)
                contact_direction[d] = Utilities::string_to_double(entries[d]);
            }
          catch (...)
            {
              throw InputError("Contact/Direction = <" + direction_text +
                               ">: not a vector of numbers");
            }
          double largest = 0.;
          for (unsigned int d = 0; d < dim; ++d)
            {
              if (!std::isfinite(contact_direction[d]))
                throw InputError("Contact/Direction = <" + direction_text +
                                 ">: component " + static_cast<char>('x' + d) +
                                 " is not finite");
              largest = std::max(largest, std::abs(contact_direction[d]));
            }
          if (largest == 0.)
            throw InputError("Contact/Direction must not be the zero vector");
          // scaled first: the squares of 1e300 or 1e-300 overflow/underflow
          contact_direction /= largest;
          contact_direction /= contact_direction.norm();
        }
      prm.enter_subsection("Gap");
      gap_function = parse_function<dim>(prm, 1, "Contact/Gap");
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }



  template <int dim>
  void
  ContactBoundary<dim>::reinit(
    const Mapping<dim>              &mapping,
    const DoFHandler<dim>           &dof_handler,
    const AffineConstraints<double> &dirichlet_constraints,
    const AffineConstraints<double> &hanging_node_constraints)
  {
    check_discretisation(dof_handler,
                         "ContactBoundary::reinit()",
                         &hanging_node_constraints);
    reinitialised = true;
    nodes.clear();
    multiplier_node_indices.clear();
    contact_cell_count = 0;
    if (ids.empty())
      {
        mass.clear();
        gap_at_nodes.reinit(0);
        weighted_gap_at_nodes.reinit(0);
        return;
      }

    const auto                  &fe = dof_handler.get_fe();
    const QGaussSimplex<dim - 1> face_quadrature(3);
    FEFaceValues<dim>            fe_face_values(mapping,
                                     fe,
                                     face_quadrature,
                                     update_values | update_quadrature_points |
                                       update_normal_vectors |
                                       update_JxW_values);

    // 1. Nodes, numbered in the order met; faces remembered for step 2.
    node_of_vertex.clear();
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    Tensor<1, dim>                       first_normal;
    bool                                 have_normal = false;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        bool cell_touches = false;
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              ids.count(cell->face(f)->boundary_id()) != 0)
            {
              cell_touches = true;
              cell->get_dof_indices(dofs);
              fe_face_values.reinit(cell, f);
              const Tensor<1, dim> normal = fe_face_values.normal_vector(0);
              if (!have_normal)
                {
                  first_normal = normal;
                  have_normal  = true;
                }
              else if (use_outward_normal &&
                       (normal - first_normal).norm() > 1e-8)
                {
                  const auto shown = [](Tensor<1, dim> n) {
                    for (unsigned int d = 0; d < dim; ++d)
                      n[d] = (std::abs(n[d]) < 1e-12 ? 0. : n[d]); // (no -0)
                    return n;
                  };
                  std::ostringstream text;
                  text << "Contact/Direction = " << outward_normal
                       << " needs one flat contact boundary, but the "
                          "outward normal of GC (Contact/Boundary ids) is ("
                       << shown(first_normal) << ") on one face and ("
                       << shown(normal)
                       << ") on another: give the direction as a vector";
                  throw InputError(text.str());
                }
              for (const unsigned int v : cell->face(f)->vertex_indices())
                {
                  const unsigned int vertex = cell->face(f)->vertex_index(v);
                  if (node_of_vertex.count(vertex) != 0)
                    continue;
                  Node node;
                  node.position = cell->face(f)->vertex(v);
                  node.vertex   = vertex;
                  // the cell-local vertex number of this face vertex
                  unsigned int cell_vertex = numbers::invalid_unsigned_int;
                  for (const unsigned int w : cell->vertex_indices())
                    if (cell->vertex_index(w) == vertex)
                      cell_vertex = w;
                  for (unsigned int c = 0; c < dim; ++c)
                    node.dofs[c] =
                      dofs[fe.component_to_system_index(c, cell_vertex)];
                  node_of_vertex[vertex] = nodes.size();
                  nodes.push_back(node);
                }
            }
        contact_cell_count += cell_touches ? 1 : 0;
      }
    // (every rank holds the whole mesh: check_discretisation())
    std::set<types::boundary_id> found;
    for (const auto &face :
         dof_handler.get_triangulation().active_face_iterators())
      if (face->at_boundary())
        found.insert(face->boundary_id());
    for (const types::boundary_id id : ids)
      if (found.count(id) == 0)
        throw InputError("Contact/Boundary ids: boundary id " +
                         std::to_string(id) + " is on no face of the mesh");
    if (nodes.empty())
      return;
    if (use_outward_normal)
      contact_direction = first_normal;

    // 2. Which nodes carry a multiplier.
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        Node &node          = nodes[k];
        node.has_multiplier = true;
        for (unsigned int c = 0; c < dim; ++c)
          {
            if (hanging_node_constraints.is_constrained(node.dofs[c]))
              throw std::runtime_error(
                "a hanging node lies on the contact boundary at " +
                point_text(node.position) +
                "; meshes must be conforming on GC");
            if (std::abs(contact_direction[c]) > 1e-12 &&
                dirichlet_constraints.is_constrained(node.dofs[c]))
              node.has_multiplier = false;
          }
        if (node.has_multiplier)
          multiplier_node_indices.push_back(k);
      }

    // 3. M and ghat by face quadrature (P1 traces are the component-0 shape
    // functions of the vector element), G by nodal evaluation.
    DynamicSparsityPattern dsp(nodes.size(), nodes.size());
    std::vector<
      std::pair<typename DoFHandler<dim>::active_cell_iterator, unsigned int>>
      faces;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            ids.count(cell->face(f)->boundary_id()) != 0)
          {
            faces.emplace_back(cell, f);
            for (const unsigned int v : cell->face(f)->vertex_indices())
              for (const unsigned int w : cell->face(f)->vertex_indices())
                dsp.add(node_of_vertex[cell->face(f)->vertex_index(v)],
                        node_of_vertex[cell->face(f)->vertex_index(w)]);
          }
    mass_sparsity.copy_from(dsp);
    mass.reinit(mass_sparsity);
    weighted_gap_at_nodes.reinit(nodes.size());
    gap_at_nodes.reinit(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      gap_at_nodes[k] = gap_function->value(nodes[k].position);

    for (const auto &[cell, f] : faces)
      {
        fe_face_values.reinit(cell, f);
        // local scalar basis: component-0 dofs of the face's vertices
        std::vector<std::pair<unsigned int, unsigned int>> local_to_node;
        for (const unsigned int w : cell->vertex_indices())
          {
            const auto it      = node_of_vertex.find(cell->vertex_index(w));
            bool       on_face = false;
            for (const unsigned int v : cell->face(f)->vertex_indices())
              on_face |=
                (cell->face(f)->vertex_index(v) == cell->vertex_index(w));
            if (on_face)
              local_to_node.emplace_back(fe.component_to_system_index(0, w),
                                         it->second);
          }
        for (const unsigned int q : fe_face_values.quadrature_point_indices())
          {
            const double gap =
              gap_function->value(fe_face_values.quadrature_point(q));
            const double JxW = fe_face_values.JxW(q);
            for (const auto &[i, node_i] : local_to_node)
              {
                const double psi_i =
                  fe_face_values.shape_value_component(i, q, 0);
                weighted_gap_at_nodes[node_i] += gap * psi_i * JxW;
                for (const auto &[j, node_j] : local_to_node)
                  mass.add(node_i,
                           node_j,
                           psi_i *
                             fe_face_values.shape_value_component(j, q, 0) *
                             JxW);
              }
          }
      }
    check_data(mapping, dof_handler);
    check_prescribed_nodes(dirichlet_constraints);
  }



  template <int dim>
  void
  ContactBoundary<dim>::check_prescribed_nodes(
    const AffineConstraints<double> &dirichlet_constraints) const
  {
    // (lengths, compared relative to the size of GC and of the data: a gap
    // and a prescribed displacement that agree up to round-off pass)
    const double length = size();
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        if (nodes[k].has_multiplier)
          continue;
        double prescribed = 0.;
        bool   held       = true;
        for (unsigned int c = 0; c < dim; ++c)
          if (std::abs(contact_direction[c]) > 1e-12)
            {
              const types::global_dof_index dof = nodes[k].dofs[c];
              const auto                   *entries =
                dirichlet_constraints.get_constraint_entries(dof);
              if (entries == nullptr || !entries->empty())
                held = false;
              else
                prescribed += contact_direction[c] *
                              dirichlet_constraints.get_inhomogeneity(dof);
            }
        if (held && prescribed - gap_at_nodes[k] >
                      1e-10 * (length + std::abs(prescribed) +
                               std::abs(gap_at_nodes[k])))
          {
            std::ostringstream text;
            text.precision(4);
            text << "Contact/Gap and Boundary conditions/Dirichlet: the node "
                    "of GC at "
                 << point_text(nodes[k].position)
                 << " is held by a Dirichlet condition at a displacement of "
                 << prescribed << " along Contact/Direction, beyond its gap "
                 << gap_at_nodes[k]
                 << ": the body is held in penetration there, and no "
                    "displacement meets the contact condition (give a gap at "
                    "least the prescribed displacement there, or leave the "
                    "node free)";
            throw InputError(text.str());
          }
      }
  }



  template <int dim>
  void
  ContactBoundary<dim>::check_data(const Mapping<dim>    &mapping,
                                   const DoFHandler<dim> &dof_handler) const
  {
    std::vector<Point<dim>> positions;
    for (const Node &node : nodes)
      positions.push_back(node.position);
    check_finite(*gap_function, positions, "Contact/Gap");
    // a foundation that moves along the load path is not implemented: the
    // gap is computed once per mesh (at t = 0), so its time t is refused
    // (at t = 0 and 1 the gap must be the same)
    for (const auto &x : positions)
      {
        gap_function->set_time(0.);
        const double at_start = gap_function->value(x);
        gap_function->set_time(1.);
        const double at_end = gap_function->value(x);
        gap_function->set_time(0.);
        if (at_start != at_end)
          throw InputError("Contact/Gap depends on the time t (a foundation "
                           "that moves along the load path is not "
                           "implemented); only the data of Boundary "
                           "conditions and the Friction threshold may use t");
      }

    // the quadrature of the weighted gap in reinit()
    const QGaussSimplex<dim - 1> face_quadrature(3);
    FEFaceValues<dim>            fe_face_values(mapping,
                                     dof_handler.get_fe(),
                                     face_quadrature,
                                     update_quadrature_points |
                                       update_normal_vectors);
    // |nu_c . n| below this (about 84 degrees between them): nearly tangent
    const double tangent_limit = 0.1;
    unsigned int n_faces = 0, n_tangent = 0, n_inward = 0;
    double       tangent_worst = std::numeric_limits<double>::infinity();
    double       inward_worst  = std::numeric_limits<double>::infinity();
    Point<dim>   tangent_where, inward_where;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            ids.count(cell->face(f)->boundary_id()) != 0)
          {
            fe_face_values.reinit(cell, f);
            check_finite(*gap_function,
                         fe_face_values.get_quadrature_points(),
                         "Contact/Gap");
            ++n_faces;
            // straight faces: one outward normal
            const double dot =
              contact_direction * fe_face_values.normal_vector(0);
            if (std::abs(dot) < tangent_limit)
              {
                ++n_tangent;
                if (std::abs(dot) < tangent_worst)
                  {
                    tangent_worst = std::abs(dot);
                    tangent_where = cell->face(f)->center();
                  }
              }
            else if (dot < 0.)
              {
                ++n_inward;
                if (dot < inward_worst)
                  {
                    inward_worst = dot;
                    inward_where = cell->face(f)->center();
                  }
              }
          }

    const MPI_Comm communicator =
      dof_handler.get_triangulation().get_communicator();
    const auto degrees = [](const double cosine) {
      std::ostringstream text;
      text.precision(3);
      text << std::acos(std::clamp(cosine, -1., 1.)) * 180. / numbers::PI;
      return text.str();
    };
    if (n_tangent > 0)
      warn_once("tangent direction",
                "Contact/Direction is nearly tangent to the contact boundary "
                "at " +
                  std::to_string(n_tangent) + " of " + std::to_string(n_faces) +
                  " contact faces (worst at " + point_text(tangent_where) +
                  ": " + degrees(tangent_worst) +
                  " degrees from the outward normal); there u . nu_c <= g "
                  "restrains sliding along the boundary rather than "
                  "penetration",
                communicator);
    if (n_inward > 0)
      warn_once("inward direction",
                "Contact/Direction points into the body at " +
                  std::to_string(n_inward) + " of " + std::to_string(n_faces) +
                  " contact faces (worst at " + point_text(inward_where) +
                  ": " + degrees(inward_worst) +
                  " degrees from the outward normal); nu_c should point from "
                  "the body to the foundation",
                communicator);

    unsigned int n_negative = 0, worst = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (gap_at_nodes[k] < 0.)
        {
          ++n_negative;
          if (gap_at_nodes[k] < gap_at_nodes[worst])
            worst = k;
        }
    if (n_negative > 0)
      {
        std::ostringstream value;
        value.precision(4);
        value << gap_at_nodes[worst];
        warn_once("negative gap",
                  "Contact/Gap is negative (" + value.str() + ") at " +
                    point_text(nodes[worst].position) +
                    ": the body starts in penetration (" +
                    std::to_string(n_negative) + " of " +
                    std::to_string(nodes.size()) + " contact nodes)",
                  communicator);
      }
  }



  template <int dim>
  unsigned int
  ContactBoundary<dim>::node_index(const unsigned int vertex) const
  {
    const auto it = node_of_vertex.find(vertex);
    Assert(it != node_of_vertex.end(), ExcMessage("vertex not on GC"));
    return it->second;
  }



  template <int dim>
  unsigned int
  ContactBoundary<dim>::n_nodes() const
  {
    return nodes.size();
  }



  template <int dim>
  const typename ContactBoundary<dim>::Node &
  ContactBoundary<dim>::node(const unsigned int k) const
  {
    return nodes[k];
  }



  template <int dim>
  const std::vector<unsigned int> &
  ContactBoundary<dim>::multiplier_nodes() const
  {
    return multiplier_node_indices;
  }



  template <int dim>
  const Tensor<1, dim> &
  ContactBoundary<dim>::direction() const
  {
    return contact_direction;
  }



  template <int dim>
  unsigned int
  ContactBoundary<dim>::constrained_component() const
  {
    unsigned int c_max = 0;
    for (unsigned int c = 1; c < dim; ++c)
      if (std::abs(contact_direction[c]) > std::abs(contact_direction[c_max]))
        c_max = c;
    return c_max;
  }



  template <int dim>
  const SparseMatrix<double> &
  ContactBoundary<dim>::mass_matrix() const
  {
    return mass;
  }



  template <int dim>
  Vector<double>
  ContactBoundary<dim>::nodal_areas() const
  {
    Vector<double> areas(n_nodes());
    for (unsigned int k = 0; k < n_nodes(); ++k)
      for (auto entry = mass.begin(k); entry != mass.end(k); ++entry)
        areas[k] += entry->value();
    return areas;
  }



  template <int dim>
  Vector<double>
  ContactBoundary<dim>::nodal_pressures(const Vector<double> &forces) const
  {
    const Vector<double> areas = nodal_areas();
    Vector<double>       pressures(n_nodes());
    for (unsigned int k = 0; k < n_nodes(); ++k)
      if (forces[k] != 0.)
        pressures[k] = -forces[k] / areas[k];
    return pressures;
  }



  template <int dim>
  double
  ContactBoundary<dim>::size() const
  {
    if (nodes.empty())
      return 0.;
    std::vector<Point<dim>> positions;
    for (const Node &node : nodes)
      positions.push_back(node.position);
    const BoundingBox<dim> box(positions);
    const auto             corners = box.get_boundary_points();
    return corners.first.distance(corners.second);
  }



  template <int dim>
  const Vector<double> &
  ContactBoundary<dim>::nodal_gap() const
  {
    return gap_at_nodes;
  }



  template <int dim>
  const Vector<double> &
  ContactBoundary<dim>::weighted_gap() const
  {
    return weighted_gap_at_nodes;
  }



  template <int dim>
  double
  ContactBoundary<dim>::gap(const Point<dim> &x) const
  {
    return gap_function->value(x);
  }



  template <int dim>
  Vector<double>
  ContactBoundary<dim>::normal_components(const LA::Vector &v) const
  {
    std::vector<types::global_dof_index> dofs;
    for (const Node &node : nodes)
      dofs.insert(dofs.end(), node.dofs.begin(), node.dofs.end());
    const Vector<double> values = gather(v, dofs);
    Vector<double>       normal(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        normal[k] += contact_direction[c] * values[dim * k + c];
    return normal;
  }



  template <int dim>
  void
  ContactBoundary<dim>::add_normal_forces(const Vector<double> &forces,
                                          LA::Vector           &v) const
  {
    AssertDimension(forces.size(), nodes.size());
    // (the forces are known on every rank: each adds those of its dofs)
    const IndexSet owned = v.locally_owned_elements();
    for (unsigned int k = 0; k < nodes.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        if (contact_direction[c] != 0. && owned.is_element(nodes[k].dofs[c]))
          v[nodes[k].dofs[c]] += forces[k] * contact_direction[c];
  }



  template <int dim>
  const std::set<types::boundary_id> &
  ContactBoundary<dim>::boundary_ids() const
  {
    return ids;
  }



  template <int dim>
  unsigned int
  ContactBoundary<dim>::n_contact_cells() const
  {
    return contact_cell_count;
  }

  template class ContactBoundary<2>;
  template class ContactBoundary<3>;
} // namespace Signorini
