#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_values.h>

#include <signorini/discretisation_check.h>
#include <signorini/estimator/constitutive_relation_error.h>
#include <signorini/input_error.h>

#include <limits>
#include <map>
#include <numeric>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /**
     * Throw unless @p boundary_conditions say where @p constraints prescribe
     * displacements: on the boundary faces of the cells this rank owns,
     * every dof fixed to a value (a constraint without entries) has a
     * Dirichlet part with its component on one of the boundary faces it
     * lies on (of any cell, owned or ghost), and every dof
     * such a part names is constrained. The stress reconstructions leave
     * the tractions free exactly there: a program of its own (doc/
     * library.md) that constrains dofs the boundary conditions do not name
     * would get a wrong estimate, not an error.
     */
    template <int dim>
    void
    check_dirichlet_data(const AffineConstraints<double> &constraints,
                         const DoFHandler<dim>           &dof_handler,
                         const BoundaryConditions<dim>   &boundary_conditions)
    {
      const auto                          &fe = dof_handler.get_fe();
      std::vector<bool>                    named(dof_handler.n_dofs(), false);
      std::vector<types::global_dof_index> face_dofs(fe.n_dofs_per_face());
      // (@p owned_only false: the ghost cells too, whose faces may carry the
      // Dirichlet part of a vertex of an owned cell)
      const auto for_each_boundary_dof = [&](const bool  owned_only,
                                             const auto &function) {
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (owned_only ? cell->is_locally_owned() : !cell->is_artificial())
            for (const auto &face : cell->face_iterators())
              if (face->at_boundary())
                {
                  face->get_dof_indices(face_dofs);
                  const ComponentMask mask =
                    boundary_conditions.dirichlet_mask(face->boundary_id());
                  for (unsigned int i = 0; i < face_dofs.size(); ++i)
                    function(face_dofs[i],
                             mask[fe.face_system_to_component_index(i).first]);
                }
      };
      for_each_boundary_dof(false,
                            [&](const types::global_dof_index dof,
                                const bool                    prescribed) {
                              if (prescribed)
                                named[dof] = true;
                            });
      std::string mismatch;
      for_each_boundary_dof(true, [&](const types::global_dof_index dof, bool) {
        const auto *entries = constraints.get_constraint_entries(dof);
        if (named[dof] && entries == nullptr)
          mismatch = "dof " + std::to_string(dof) +
                     " has a Dirichlet part but is not constrained";
        else if (!named[dof] && entries != nullptr && entries->empty())
          mismatch = "dof " + std::to_string(dof) +
                     " is constrained to a value but no Dirichlet part of "
                     "the boundary conditions names its component on its "
                     "boundary";
      });
      const int anywhere = Utilities::MPI::max(mismatch.empty() ? 0 : 1,
                                               dof_handler.get_communicator());
      if (anywhere != 0)
        throw std::invalid_argument(
          "ConstitutiveRelationError::estimate(): the constraints and the "
          "boundary conditions prescribe displacements in different places" +
          (mismatch.empty() ? std::string(" (on another rank)") :
                              ": " + mismatch));
    }

    /// R^, the friction bound and where the nodes slide from at a
    /// quadrature point of a face of GC, with the hat functions of the
    /// face's nodes there.
    template <int dim>
    struct ContactPoint
    {
      Point<dim> position;
      /// g interpolated between the face's nodes (the gap G_k = g(x_k) the
      /// admissible displacement meets: the foundation of the bound).
      double         gap             = 0.;
      double         normal_reaction = 0., bound = 0., JxW = 0.;
      Tensor<1, dim> tangential_reaction, origin;
      /// (node of GC, its hat function at the point)
      std::vector<std::pair<unsigned int, double>> hats;
    };

    /// The integrand of the contact term for the displacement @p w at
    /// @p point: R^_n (W_n - G), G the gap interpolated between the nodes
    /// (>= 0: both factors are linear along the face, with a fixed sign at
    /// its nodes; with g itself it may be negative where g is not linear
    /// along the face), with friction plus the bipotential's
    /// friction part s |W_t| + R^_t . W_t (>= 0 with |R^_t| <= s, both P1;
    /// s = mu |R^_n| for Coulomb; W_t the slip since the previous load step:
    /// origin has tangential components only).
    template <int dim>
    double
    contact_integrand(const ContactPoint<dim>    &point,
                      const Tensor<1, dim>       &w,
                      const ContactBoundary<dim> &boundary,
                      const bool                  with_friction)
    {
      const double w_n  = w * boundary.direction();
      double       term = point.normal_reaction * (w_n - point.gap);
      if (with_friction)
        {
          const Tensor<1, dim> w_t =
            w - w_n * boundary.direction() - point.origin;
          // (where nothing slides the term is zero whatever the bound: s =
          // mu |R^_n| overflows for a huge mu, and inf times 0 is NaN)
          if (w_t.norm() > 0.)
            term += point.bound * w_t.norm() + point.tangential_reaction * w_t;
        }
      return term;
    }

    /// Call @p visit(cell index, point, w) at the quadrature points of the
    /// faces of GC of the cells this rank owns, w the value of @p ghosted_u
    /// there (with friction interpolated from its nodal values by the hat
    /// functions that interpolate the origin).
    template <int dim, typename Visitor>
    void
    for_each_contact_point(const Mapping<dim>                 &mapping,
                           const DoFHandler<dim>              &dof_handler,
                           const ContactBoundary<dim>         &boundary,
                           const AdmissibleContactFields<dim> &fields,
                           const std::vector<Tensor<1, dim>>  *origin,
                           const LA::Vector                   &ghosted_u,
                           const Visitor                      &visit)
    {
      // a segment rule in 2D, a triangle rule on the faces of tetrahedra
      const Quadrature<dim - 1> face_quadrature =
        (dim == 2) ? Quadrature<dim - 1>(QGauss<dim - 1>(4)) :
                     Quadrature<dim - 1>(QGaussSimplex<dim - 1>(4));
      const auto                      &fe = dof_handler.get_fe();
      FEFaceValues<dim>                fe_face_values(mapping,
                                       fe,
                                       face_quadrature,
                                       update_values |
                                         update_quadrature_points |
                                         update_JxW_values);
      const FEValuesExtractors::Vector displacement(0);
      std::vector<Tensor<1, dim>>      w(face_quadrature.size());
      const bool        with_friction = !fields.tangential_reaction.empty();
      ContactPoint<dim> point;
      for (const auto &cell : dof_handler.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          if (cell->is_locally_owned() && cell->face(f)->at_boundary() &&
              boundary.boundary_ids().count(cell->face(f)->boundary_id()) != 0)
            {
              fe_face_values.reinit(cell, f);
              fe_face_values[displacement].get_function_values(ghosted_u, w);
              // R^ is P1 on the face: in 2D linear along the edge between
              // its two vertices, otherwise the sum of its nodal values
              // times the hat functions of the face's vertices (the
              // component-0 shape functions of the cell's vertices)
              const auto face = cell->face(f);
              // (node of GC, shape function index or -1 in 2D)
              std::vector<std::pair<unsigned int, unsigned int>> face_nodes;
              for (const unsigned int v : cell->vertex_indices())
                for (const unsigned int i : face->vertex_indices())
                  if (cell->vertex_index(v) == face->vertex_index(i))
                    face_nodes.emplace_back(boundary.node_index(
                                              cell->vertex_index(v)),
                                            fe.component_to_system_index(0, v));
              const Point<dim>   a      = face->vertex(0);
              const double       length = face->measure();
              const unsigned int first =
                boundary.node_index(face->vertex_index(0));
              for (const unsigned int q :
                   fe_face_values.quadrature_point_indices())
                {
                  point.position        = fe_face_values.quadrature_point(q);
                  point.JxW             = fe_face_values.JxW(q);
                  point.normal_reaction = point.bound = point.gap = 0.;
                  point.tangential_reaction = point.origin = Tensor<1, dim>();
                  point.hats.clear();
                  for (const auto &[k, i] : face_nodes)
                    {
                      double hat = 0.;
                      if (dim == 2)
                        {
                          const double s = point.position.distance(a) / length;
                          hat            = (k == first) ? 1. - s : s;
                        }
                      else
                        hat = fe_face_values.shape_value_component(i, q, 0);
                      point.hats.emplace_back(k, hat);
                      point.gap += hat * boundary.nodal_gap()[k];
                      point.normal_reaction += hat * fields.normal_reaction[k];
                      if (with_friction)
                        {
                          point.tangential_reaction +=
                            hat * fields.tangential_reaction[k];
                          point.bound += hat * fields.friction_bound[k];
                          point.origin += hat * (*origin)[k];
                        }
                    }
                  // with friction w from the same hats as the origin, so
                  // that a node that does not slide has no slip, not the
                  // difference of two interpolations: the friction term
                  // multiplies it by s = mu |R^_n| (on a load path of the
                  // block, every node sticking, eps was 21 % at mu = 1e18
                  // and 85 % at 1e20 for 14 % at 1e10)
                  if (with_friction)
                    {
                      w[q] = Tensor<1, dim>();
                      for (unsigned int j = 0; j < face_nodes.size(); ++j)
                        for (unsigned int c = 0; c < dim; ++c)
                          w[q][c] +=
                            point.hats[j].second *
                            ghosted_u[boundary.node(face_nodes[j].first)
                                        .dofs[c]];
                    }
                  visit(cell->active_cell_index(), point, w[q]);
                }
            }
    }

    /**
     * What lower_friction_term() needs of K on GC, the same in every sweep:
     * the nodes of GC with a cell in common with each (an entry of K), and
     * the node's diagonal block K_kk. The same on every rank (each row is
     * taken from the rank owning it, the others add zeros).
     */
    template <int dim>
    struct ContactNodeCoupling
    {
      std::vector<std::vector<unsigned int>> neighbours;
      std::vector<Tensor<2, dim>>            diagonal_blocks;
    };

    template <int dim>
    ContactNodeCoupling<dim>
    contact_node_coupling(const DiscreteContactProblem<dim> &problem,
                          const IndexSet                    &owned,
                          const MPI_Comm                     communicator)
    {
      const auto        &boundary  = problem.boundary();
      const unsigned int n_nodes   = boundary.n_nodes();
      const auto        &stiffness = problem.stiffness();
      std::map<types::global_dof_index, std::pair<unsigned int, unsigned int>>
        node_of_dof; // (node, component)
      for (unsigned int k = 0; k < n_nodes; ++k)
        for (unsigned int c = 0; c < dim; ++c)
          node_of_dof[boundary.node(k).dofs[c]] = {k, c};
      std::vector<unsigned int> pairs;
      Vector<double>            blocks(n_nodes * dim * dim);
      for (unsigned int k = 0; k < n_nodes; ++k)
        for (unsigned int c = 0; c < dim; ++c)
          {
            const types::global_dof_index dof = boundary.node(k).dofs[c];
            if (!owned.is_element(dof))
              continue;
            for (auto entry = stiffness.begin(dof); entry != stiffness.end(dof);
                 ++entry)
              {
                const auto other = node_of_dof.find(entry->column());
                if (other == node_of_dof.end())
                  continue;
                const auto [j, b] = other->second;
                if (j != k)
                  pairs.insert(pairs.end(), {k, j});
                else
                  blocks[(k * dim + c) * dim + b] = entry->value();
              }
          }
      Utilities::MPI::sum(blocks, communicator, blocks);
      ContactNodeCoupling<dim> coupling;
      coupling.neighbours.resize(n_nodes);
      for (const auto &part : Utilities::MPI::all_gather(communicator, pairs))
        for (std::size_t p = 0; p + 1 < part.size(); p += 2)
          coupling.neighbours[part[p]].push_back(part[p + 1]);
      coupling.diagonal_blocks.resize(n_nodes);
      for (unsigned int k = 0; k < n_nodes; ++k)
        for (unsigned int c = 0; c < dim; ++c)
          for (unsigned int b = 0; b < dim; ++b)
            coupling.diagonal_blocks[k][c][b] = blocks[(k * dim + c) * dim + b];
      return coupling;
    }

    /**
     * Lower the error bound by the choice of U^ on GC, with friction. Any
     * kinematically admissible U^ gives a bound, and the tangential
     * components of U^ at a node of GC are free (non-penetration concerns
     * the normal one). Where a node in contact (R^_n > 0) sticks next to a
     * separated node that slides, both P1 fields are non-zero on the face
     * between them and the friction term s |W^_t| grows with mu (doc/
     * theory.md section 8). For each node of GC this tries U^_t - t W^_t
     * (t = 1/4, 1/2, 3/4, 1: less slip at the node) and keeps the best
     * choice if it lowers e^2. Its change is exact for any statically
     * admissible sigma^: the energy term changes by t^2 d^T K_kk d + 2 t
     * d . g_k, d the node's slip W^_t and g_k = (F - K U^)_k + int_GC R^_t
     * psi_k (int sigma^ : eps(v) = l(v) + int_GC R^ . v), the contact term
     * by its integrals over the faces at the node. Nodes are changed in
     * increasing order, none next to one changed before (no cell in
     * common: the changes add up), the same on every rank. The estimate
     * that follows uses the changed U^: it remains a bound whatever these
     * choices. Returns the number of nodes changed, and adds the change of
     * e^2 it predicts to @p predicted_change.
     */
    template <int dim>
    unsigned int
    lower_friction_term(double                             &predicted_change,
                        const DiscreteContactProblem<dim>  &problem,
                        const ContactNodeCoupling<dim>     &coupling,
                        const Mapping<dim>                 &mapping,
                        const DoFHandler<dim>              &dof_handler,
                        const AdmissibleContactFields<dim> &fields,
                        const std::vector<Tensor<1, dim>>  &origin,
                        LA::Vector                         &admissible)
    {
      const auto        &boundary = problem.boundary();
      const unsigned int n_nodes  = boundary.n_nodes();
      const unsigned int c_star   = boundary.constrained_component();
      const MPI_Comm     communicator =
        dof_handler.get_triangulation().get_communicator();
      const IndexSet         owned       = admissible.locally_owned_elements();
      const auto            &constraints = problem.constraints();
      constexpr unsigned int n_steps     = 4;

      // the slip d_k of each node in its free tangential components (each
      // from the rank owning the dof), g_k's first part, and d^T K_kk d
      const LA::Vector residual = problem.residual(admissible);
      Vector<double>   slip(n_nodes * dim), g(n_nodes * dim);
      for (unsigned int k = 0; k < n_nodes; ++k)
        for (unsigned int c = 0; c < dim; ++c)
          {
            const types::global_dof_index dof = boundary.node(k).dofs[c];
            if (c != c_star && owned.is_element(dof) &&
                !constraints.is_constrained(dof))
              {
                slip[dim * k + c] = admissible[dof] - origin[k][c];
                g[dim * k + c]    = residual[dof];
              }
          }
      Utilities::MPI::sum(slip, communicator, slip);
      // (c_star's slip is zero)
      std::vector<double> curvature(n_nodes, 0.);
      for (unsigned int k = 0; k < n_nodes; ++k)
        for (unsigned int c = 0; c < dim; ++c)
          for (unsigned int b = 0; b < dim; ++b)
            curvature[k] += slip[dim * k + c] *
                            coupling.diagonal_blocks[k][c][b] *
                            slip[dim * k + b];

      // the contact term's changes, and int_GC R^_t psi_k into g
      std::vector<double> contact_change(n_nodes * n_steps, 0.);
      const LA::Vector    ghosted =
        with_ghosts(admissible,
                    DoFTools::extract_locally_relevant_dofs(dof_handler));
      for_each_contact_point(
        mapping,
        dof_handler,
        boundary,
        fields,
        &origin,
        ghosted,
        [&](const unsigned int,
            const ContactPoint<dim> &point,
            const Tensor<1, dim>    &w) {
          const double base = contact_integrand(point, w, boundary, true);
          for (const auto &[k, hat] : point.hats)
            {
              Tensor<1, dim> d;
              for (unsigned int c = 0; c < dim; ++c)
                {
                  d[c] = slip[dim * k + c];
                  g[dim * k + c] += hat * point.tangential_reaction[c] *
                                    point.JxW * (c != c_star ? 1. : 0.);
                }
              if (d.norm() == 0. || hat == 0.)
                continue;
              for (unsigned int step = 1; step <= n_steps; ++step)
                contact_change[n_steps * k + step - 1] +=
                  2. *
                  (contact_integrand(point,
                                     w - (static_cast<double>(step) / n_steps) *
                                           hat * d,
                                     boundary,
                                     true) -
                   base) *
                  point.JxW;
            }
        });
      Utilities::MPI::sum(g, communicator, g);
      Utilities::MPI::sum(contact_change, communicator, contact_change);

      // the changes, in increasing order of the nodes
      std::vector<bool> blocked(n_nodes, false);
      unsigned int      n_changed = 0;
      for (unsigned int k = 0; k < n_nodes; ++k)
        {
          if (blocked[k])
            continue;
          double d_dot_g = 0.;
          for (unsigned int c = 0; c < dim; ++c)
            d_dot_g += slip[dim * k + c] * g[dim * k + c];
          double best = 0., best_t = 0.;
          for (unsigned int step = 1; step <= n_steps; ++step)
            {
              const double t      = static_cast<double>(step) / n_steps;
              const double energy = t * t * curvature[k] + 2. * t * d_dot_g;
              const double change =
                energy + contact_change[n_steps * k + step - 1];
              // (well below round-off of the terms: the same decision on
              // every rank)
              const double scale =
                std::abs(energy) +
                std::abs(contact_change[n_steps * k + step - 1]);
              if (change < best && change < -1e-8 * scale)
                {
                  best   = change;
                  best_t = t;
                }
            }
          if (best_t == 0.)
            continue;
          for (const unsigned int j : coupling.neighbours[k])
            blocked[j] = true;
          // (from where the node slides: t = 1 leaves no slip at all,
          // where U^ - d would leave the round-off of the difference)
          for (unsigned int c = 0; c < dim; ++c)
            {
              const types::global_dof_index dof = boundary.node(k).dofs[c];
              if (slip[dim * k + c] != 0. && owned.is_element(dof))
                admissible[dof] =
                  origin[k][c] + (1. - best_t) * slip[dim * k + c];
            }
          ++n_changed;
          predicted_change += best;
        }
      admissible.compress(VectorOperation::insert);
      return n_changed;
    }



    /**
     * U^ without slip at the nodes whose rows stick: their free tangential
     * components at the origin. The integral condition holds the weighted
     * slips of the sticking rows, (M (t - origin))_i = 0, not the nodal
     * ones, which a sliding or separated neighbour makes nonzero; the
     * friction term multiplies them by s = mu |R^_n| (the 3D cube, every
     * row in contact sticking: eps 39 % at mu = 1e3, 100 % at 1e10). A
     * tangential change keeps U^ admissible (the contact direction is an
     * axis), and e a bound. (The pointwise condition holds the nodal slips
     * of its sticking rows: there it changes round-off.)
     */
    template <int dim>
    void
    hold_sticking_nodes(const DiscreteContactProblem<dim> &problem,
                        const FrictionState<dim>          &state,
                        LA::Vector                        &admissible)
    {
      using Status                = typename FrictionState<dim>::Status;
      const auto        &boundary = problem.boundary();
      const auto        &rows     = boundary.multiplier_nodes();
      const unsigned int c_star   = boundary.constrained_component();
      const IndexSet     owned    = admissible.locally_owned_elements();
      for (unsigned int i = 0; i < state.status.size(); ++i)
        if (state.status[i] == Status::stick)
          for (unsigned int c = 0; c < dim; ++c)
            {
              const types::global_dof_index dof =
                boundary.node(rows[i]).dofs[c];
              if (c != c_star && owned.is_element(dof) &&
                  !problem.constraints().is_constrained(dof))
                admissible[dof] = state.origin[rows[i]][c];
            }
      admissible.compress(VectorOperation::insert);
    }



    /**
     * The warning that the contact term of e uses the gap interpolated
     * between the nodes of GC, if g differs from it by @p gap_deviation
     * (the largest over the ranks) beyond round-off.
     */
    template <int dim>
    void
    warn_if_gap_not_linear(const ContactBoundary<dim> &boundary,
                           const double                gap_deviation,
                           const MPI_Comm              communicator)
    {
      if (boundary.n_nodes() == 0 ||
          !(gap_deviation >
            1e-10 * (boundary.size() + boundary.nodal_gap().linfty_norm())))
        return;
      std::ostringstream text;
      text.precision(3);
      text << "Contact/Gap is not linear along the faces of GC: it differs "
              "from its interpolation between the nodes by up to "
           << gap_deviation
           << "; the error estimate is that of the foundation so "
              "interpolated (doc/estimator.md, \"The guaranteed bound\")";
      warn_once("gap not linear", text.str(), communicator);
    }



    /**
     * The denominator of eps that the round-off of the strains of @p u_h
     * alone would give: the volume times E times the square of a machine
     * epsilon times max |u_h| / h_min, the round-off of a strain.
     */
    template <int dim>
    double
    denominator_of_round_off(const DoFHandler<dim>            &dof_handler,
                             const LinearElasticMaterial<dim> &material,
                             const LA::Vector                 &u_h)
    {
      const MPI_Comm communicator =
        dof_handler.get_triangulation().get_communicator();
      double h_min = std::numeric_limits<double>::max(), volume = 0.;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            h_min = std::min(h_min, cell->minimum_vertex_distance());
            volume += cell->measure();
          }
      h_min  = Utilities::MPI::min(h_min, communicator);
      volume = Utilities::MPI::sum(volume, communicator);
      const double round_off_strain =
        std::numeric_limits<double>::epsilon() * u_h.linfty_norm() / h_min;
      return volume * std::abs(material.young_modulus) * round_off_strain *
             round_off_strain;
    }
  } // namespace



  template <int dim>
  void
  ConstitutiveRelationError<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    prm.declare_entry(
      "Enable",
      "true",
      Patterns::Bool(),
      "Compute the error in constitutive relation (eps, eps_E).");
    prm.leave_subsection();
    StressReconstruction<dim>::registry().declare_parameters(prm);
  }



  template <int dim>
  void
  ConstitutiveRelationError<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    is_enabled = prm.get_bool("Enable");
    prm.leave_subsection();
    // only when it is used: a reconstruction may refuse the dimension or a
    // choice of its parameters
    reconstruction.reset();
    if (is_enabled)
      reconstruction = StressReconstruction<dim>::registry().create(prm);
  }



  template <int dim>
  bool
  ConstitutiveRelationError<dim>::enabled() const
  {
    return is_enabled;
  }



  template <int dim>
  typename ConstitutiveRelationError<dim>::Result
  ConstitutiveRelationError<dim>::estimate(
    const DiscreteContactProblem<dim> &problem,
    const Mapping<dim>                &mapping,
    const DoFHandler<dim>             &dof_handler,
    const LinearElasticMaterial<dim>  &material,
    const BoundaryConditions<dim>     &boundary_conditions,
    const LA::Vector                  &u_h,
    const Vector<double>              &y,
    LA::Vector                        &admissible_displacement,
    const FrictionLaw<dim>            *friction_law,
    const FrictionState<dim>          *friction_state)
  {
    check_discretisation(dof_handler, "ConstitutiveRelationError::estimate()");
    if (reconstruction == nullptr)
      throw std::logic_error(
        "ConstitutiveRelationError::estimate(): no stress reconstruction "
        "(call parse_parameters() first, with Error estimator/Enable = "
        "true)");
    check_dirichlet_data(problem.constraints(),
                         dof_handler,
                         boundary_conditions);
    Result      result;
    const auto &boundary = problem.boundary();

    // R^, U^ and the displacement whose stress is in FE equilibrium with R^
    const bool with_friction =
      friction_law != nullptr && friction_law->enabled();
    AssertThrow(!with_friction || friction_state != nullptr,
                ExcMessage("the error estimate with friction needs the "
                           "friction state of the solution"));
    const std::unique_ptr<const FrictionData<dim>> friction(
      with_friction ?
        new FrictionData<dim>{*friction_law, friction_state->force} :
        nullptr);
    const AdmissibleContactFields<dim> fields =
      problem.condition().admissible_fields(problem, u_h, y, friction.get());
    const Vector<double> &normal_reaction = fields.normal_reaction;
    result.positive_multipliers           = fields.positive_multipliers;
    admissible_displacement               = fields.displacement;
    if (with_friction)
      hold_sticking_nodes(problem, *friction_state, admissible_displacement);
    const std::vector<Tensor<1, dim>> &tangential_reaction =
      fields.tangential_reaction;

    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    const LA::Vector ghosted_equilibrated =
      with_ghosts(fields.equilibrated_displacement, relevant);
    const EquilibrationInput<dim> input{mapping,
                                        dof_handler,
                                        material,
                                        boundary_conditions,
                                        boundary,
                                        normal_reaction,
                                        ghosted_equilibrated,
                                        tangential_reaction};
    const MPI_Comm                communicator =
      dof_handler.get_triangulation().get_communicator();
    // sigma^ and the terms of e^2 per cell for the admissible displacement
    // @p admissible
    struct Terms
    {
      Vector<double> error_squared, sum_squared, contact_local;
      double         volume_error = 0., volume_sum = 0., contact_term = 0.,
             equilibrium_defect = 0., condition_defect = 0.;
      std::vector<std::pair<std::string, double>> step_seconds;
    };
    // how far g is from its interpolation between the nodes of GC, the
    // gap of the contact term
    double     gap_deviation = 0.;
    const auto terms_for     = [&](const LA::Vector &admissible) {
      Terms terms;
      // sigma^ and the volume terms, on the cells of this rank (which read
      // the dofs of the cells around them)
      const LA::Vector ghosted_admissible = with_ghosts(admissible, relevant);
      reconstruction->compute(input,
                              ghosted_admissible,
                              terms.error_squared,
                              terms.sum_squared);
      terms.equilibrium_defect = reconstruction->equilibrium_defect();
      terms.condition_defect   = reconstruction->condition_defect();
      terms.step_seconds       = reconstruction->step_seconds();

      // the contact term 2 int_GC R^_n (W^_n - g), per cell, with friction
      // plus 2 int_GC s |W^_t| + R^_t . W^_t
      terms.contact_local.reinit(terms.error_squared.size());
      if (boundary.n_nodes() > 0)
        for_each_contact_point(
          mapping,
          dof_handler,
          boundary,
          fields,
          with_friction ? &friction_state->origin : nullptr,
          ghosted_admissible,
          [&](const unsigned int       cell,
              const ContactPoint<dim> &point,
              const Tensor<1, dim>    &w) {
            terms.contact_local[cell] +=
              2. * contact_integrand(point, w, boundary, with_friction) *
              point.JxW;
            gap_deviation =
              std::max(gap_deviation,
                       std::abs(boundary.gap(point.position) - point.gap));
          });

      // every rank filled the entries of its cells: complete them
      if (Utilities::MPI::n_mpi_processes(communicator) > 1)
        for (Vector<double> *local :
             {&terms.error_squared, &terms.sum_squared, &terms.contact_local})
          Utilities::MPI::sum(*local, communicator, *local);
      terms.contact_term = std::accumulate(terms.contact_local.begin(),
                                           terms.contact_local.end(),
                                           0.);
      terms.volume_error = std::accumulate(terms.error_squared.begin(),
                                           terms.error_squared.end(),
                                           0.);
      terms.volume_sum =
        std::accumulate(terms.sum_squared.begin(), terms.sum_squared.end(), 0.);
      // (a contact term of round-off size may come out negative: -4e-18 of
      // e^2 on a mesh of two triangles; it is zero, not a negative share)
      if (terms.contact_term < 0. &&
          -terms.contact_term <= 1e-12 * terms.volume_error)
        terms.contact_term = 0.;
      return terms;
    };
    Terms terms = terms_for(admissible_displacement);
    warn_if_gap_not_linear(boundary,
                           Utilities::MPI::max(gap_deviation, communicator),
                           communicator);

    // with friction, a second U^ with less slip where it lowers e^2 for
    // this sigma^ (lower_friction_term()), if by at least 1 %: the sharper
    // of the two bounds, since the enhancement for the new U^ stops short
    // of its minimum too (on the Coulomb block at mu = 0.3 a change
    // predicted below 1e-3 of e^2 gave an e^2 larger by 5e-4)
    if (with_friction && boundary.n_nodes() > 0)
      {
        LA::Vector                     less_slip(admissible_displacement);
        double                         predicted_change = 0.;
        const ContactNodeCoupling<dim> coupling =
          contact_node_coupling(problem,
                                less_slip.locally_owned_elements(),
                                communicator);
        // (the nodes next to a changed one, in further sweeps)
        for (unsigned int sweep = 0; sweep < 8; ++sweep)
          if (lower_friction_term(predicted_change,
                                  problem,
                                  coupling,
                                  mapping,
                                  dof_handler,
                                  fields,
                                  friction_state->origin,
                                  less_slip) == 0)
            break;
        const double e_squared = terms.volume_error + terms.contact_term;
        if (predicted_change < -0.01 * e_squared)
          {
            Terms other = terms_for(less_slip);
            if (other.volume_error + other.contact_term < e_squared)
              {
                terms                   = std::move(other);
                admissible_displacement = less_slip;
              }
          }
      }
    Vector<double> &error_squared = terms.error_squared;
    result.contact_local          = terms.contact_local;
    result.contact_term           = terms.contact_term;
    result.equilibrium_defect     = terms.equilibrium_defect;
    result.condition_defect       = terms.condition_defect;
    result.step_seconds           = terms.step_seconds;
    const double volume_error     = terms.volume_error;
    const double volume_sum       = terms.volume_sum;
    result.e_squared              = volume_error + result.contact_term;
    result.denominator            = volume_sum + result.contact_term;
    result.local.reinit(error_squared.size());
    // no stress and no contact work (no load, or a rigid motion imposed by
    // the Dirichlet data): the admissible fields are exact, eps = 0, not
    // 0 / 0 or the ratio of two round-off errors. D of strains below 100
    // round-offs is round-off (a translation imposed on the 3D block
    // reaches tens); below 1e5 of them eps is polluted by it (the block
    // translated by (1, 1), no contact: 7 % at 24 round-offs, 0.8 % at 80,
    // 0.06 % at 240). An iterative solve leaves its own tolerance instead,
    // which this floor does not see.
    const double round_off_denominator =
      denominator_of_round_off(dof_handler, material, u_h);
    result.stress_free = !(result.denominator > 1e4 * round_off_denominator);
    result.polluted_by_round_off =
      !(result.denominator > 1e10 * round_off_denominator);
    if (result.stress_free)
      {
        result.e_squared = result.denominator = result.contact_term = 0.;
        result.contact_local                                        = 0.;
        return result;
      }
    result.eps = std::sqrt(result.e_squared / result.denominator);
    result.eps_contact =
      result.e_squared > 0. ? result.contact_term / result.e_squared : 0.;
    for (unsigned int E = 0; E < error_squared.size(); ++E)
      result.local[E] =
        std::sqrt(std::max(error_squared[E] + result.contact_local[E], 0.) /
                  result.denominator);
    return result;
  }

  template class ConstitutiveRelationError<2>;
  template class ConstitutiveRelationError<3>;
} // namespace Signorini
