#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_values.h>

#include <signorini/estimator/constitutive_relation_error.h>

#include <limits>
#include <numeric>

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

    const std::vector<Tensor<1, dim>> &tangential_reaction =
      fields.tangential_reaction;

    // sigma^ and the volume terms, on the cells of this rank (which read
    // the dofs of the cells around them)
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    const LA::Vector ghosted_equilibrated =
      with_ghosts(fields.equilibrated_displacement, relevant);
    const LA::Vector ghosted_admissible =
      with_ghosts(admissible_displacement, relevant);
    Vector<double>                error_squared, sum_squared;
    const EquilibrationInput<dim> input{mapping,
                                        dof_handler,
                                        material,
                                        boundary_conditions,
                                        boundary,
                                        normal_reaction,
                                        ghosted_equilibrated,
                                        tangential_reaction};
    reconstruction->compute(input,
                            ghosted_admissible,
                            error_squared,
                            sum_squared);
    result.equilibrium_defect = reconstruction->equilibrium_defect();
    result.condition_defect   = reconstruction->condition_defect();
    result.step_seconds       = reconstruction->step_seconds();

    // the contact term 2 int_GC R^_n (W^_n - g), per cell, with friction
    // plus 2 int_GC s |W^_t| + R^_t . W^_t
    result.contact_local.reinit(error_squared.size());
    if (boundary.n_nodes() > 0)
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
        std::vector<Tensor<1, dim>>      w_hat(face_quadrature.size());
        for (const auto &cell : dof_handler.active_cell_iterators())
          for (const unsigned int f : cell->face_indices())
            if (cell->is_locally_owned() && cell->face(f)->at_boundary() &&
                boundary.boundary_ids().count(cell->face(f)->boundary_id()) !=
                  0)
              {
                fe_face_values.reinit(cell, f);
                fe_face_values[displacement].get_function_values(
                  ghosted_admissible, w_hat);
                // R^ is P1 on the face: in 2D linear along the edge
                // between its two vertices, otherwise the sum of its nodal
                // values times the hat functions of the face's vertices
                // (the component-0 shape functions of the cell's vertices)
                const auto face = cell->face(f);
                // (node of GC, shape function index or -1 in 2D)
                std::vector<std::pair<unsigned int, unsigned int>> face_nodes;
                for (const unsigned int w : cell->vertex_indices())
                  for (const unsigned int v : face->vertex_indices())
                    if (cell->vertex_index(w) == face->vertex_index(v))
                      face_nodes.emplace_back(
                        boundary.node_index(cell->vertex_index(w)),
                        fe.component_to_system_index(0, w));
                const Point<dim>   a      = face->vertex(0);
                const double       length = face->measure();
                const unsigned int first =
                  boundary.node_index(face->vertex_index(0));
                for (const unsigned int q :
                     fe_face_values.quadrature_point_indices())
                  {
                    const Point<dim> &x = fe_face_values.quadrature_point(q);
                    double            r = 0., bound = 0.;
                    Tensor<1, dim>    r_t, origin;
                    for (const auto &[k, i] : face_nodes)
                      {
                        double hat = 0.;
                        if (dim == 2)
                          {
                            const double s = x.distance(a) / length;
                            hat            = (k == first) ? 1. - s : s;
                          }
                        else
                          hat = fe_face_values.shape_value_component(i, q, 0);
                        r += hat * normal_reaction[k];
                        if (with_friction)
                          {
                            r_t += hat * tangential_reaction[k];
                            bound += hat * fields.friction_bound[k];
                            origin += hat * friction_state->origin[k];
                          }
                      }
                    const double w_n  = w_hat[q] * boundary.direction();
                    double       term = r * (w_n - boundary.gap(x));
                    if (with_friction)
                      {
                        // the bipotential's friction part, s |W^_t| + R^_t .
                        // W^_t >= 0 with |R^_t| <= s, both P1 (s = mu |R^_n|
                        // for Coulomb); W^_t the slip since the previous
                        // load step (origin: tangential components only)
                        const Tensor<1, dim> w_t =
                          w_hat[q] - w_n * boundary.direction() - origin;
                        term += bound * w_t.norm() + r_t * w_t;
                      }
                    result.contact_local[cell->active_cell_index()] +=
                      2. * term * fe_face_values.JxW(q);
                  }
              }
      }

    // every rank filled the entries of its cells: complete them
    const MPI_Comm communicator =
      dof_handler.get_triangulation().get_communicator();
    if (Utilities::MPI::n_mpi_processes(communicator) > 1)
      for (Vector<double> *local :
           {&error_squared, &sum_squared, &result.contact_local})
        Utilities::MPI::sum(*local, communicator, *local);
    result.contact_term = std::accumulate(result.contact_local.begin(),
                                          result.contact_local.end(),
                                          0.);
    const double volume_error =
      std::accumulate(error_squared.begin(), error_squared.end(), 0.);
    const double volume_sum =
      std::accumulate(sum_squared.begin(), sum_squared.end(), 0.);
    // (a contact term of round-off size may come out negative: -4e-18 of
    // e^2 on a mesh of two triangles; it is zero, not a negative share)
    if (result.contact_term < 0. &&
        -result.contact_term <= 1e-12 * volume_error)
      result.contact_term = 0.;
    result.e_squared   = volume_error + result.contact_term;
    result.denominator = volume_sum + result.contact_term;
    result.local.reinit(error_squared.size());
    // no stress and no contact work (no load, or a rigid motion imposed by
    // the Dirichlet data): the admissible fields are exact, eps = 0, not
    // 0 / 0 or the ratio of two round-off errors. The round-off of the
    // strains is about a machine epsilon times max |u_h| / h_min: D of
    // strains below 100 of them is round-off (a translation imposed on the
    // 3D block reaches tens); below 1e5 of them eps is polluted by it (the
    // block translated by (1, 1), no contact: 7 % at 24 round-offs, 0.8 %
    // at 80, 0.06 % at 240). An iterative solve leaves its own tolerance
    // instead, which this floor does not see.
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
    const double round_off_denominator = volume *
                                         std::abs(material.young_modulus) *
                                         round_off_strain * round_off_strain;
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
