#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_values.h>

#include <signorini/estimator/constitutive_relation_error.h>
#include <signorini/estimator/element_equilibration.h>
#include <signorini/estimator/star_patch_equilibration.h>

#include <numeric>

namespace Signorini
{
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
    prm.declare_entry("Stress reconstruction",
                      "star patch",
                      Patterns::Selection("star patch|element equilibration"),
                      "Construction of sigma^: 'star patch' (flux-free "
                      "vertex-patch problems; effectivity 1.25-1.7 on the "
                      "block) or 'element equilibration' (the paper's EET; "
                      "2.6-3.5), see doc/estimator.md.");
    prm.enter_subsection("Star patch");
    StarPatchEquilibration<dim>::declare_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("Element equilibration");
    ElementEquilibration<dim>::declare_parameters(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  void
  ConstitutiveRelationError<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Error estimator");
    is_enabled               = prm.get_bool("Enable");
    const std::string choice = prm.get("Stress reconstruction");
    prm.enter_subsection(choice == "star patch" ? "Star patch" :
                                                  "Element equilibration");
    if (choice == "star patch")
      reconstruction = std::make_unique<StarPatchEquilibration<dim>>(prm);
    else
      reconstruction = std::make_unique<ElementEquilibration<dim>>(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }



  template <int dim>
  bool
  ConstitutiveRelationError<dim>::enabled() const
  {
    return is_enabled;
  }



  namespace
  {
    /**
     * A body held only by the contact: the clipped reaction
     * R^ = min(Lambda, 0) no longer balances the load on the free rigid
     * motions N_j, and no stress is in equilibrium with it. Rescale it node
     * by node by 1 + sum_j beta_j (nu_c . N_j)(x_k), beta such that
     * N_j^T (F + forces) = 0; it stays compressive while the factors stay
     * positive (the clipped part is small next to the compressive one).
     * Updates @p normal_reaction and its nodal @p forces = M R^.
     */
    template <int dim>
    void
    balance_on_rigid_motions(const DiscreteContactProblem<dim> &problem,
                             Vector<double>                    &normal_reaction,
                             Vector<double>                    &forces)
    {
      const FullMatrix<double> normals = problem.rigid_normal_components();
      const unsigned int       r = normals.n(), n = normals.m();
      const auto              &mass = problem.boundary().mass_matrix();
      // work of the forces on the free motions, and its change per beta_l
      Vector<double> imbalance(problem.rigid_load());
      normals.Tvmult_add(imbalance, forces);
      FullMatrix<double> change(r, r);
      Vector<double>     scaled(n), scaled_forces(n);
      for (unsigned int l = 0; l < r; ++l)
        {
          for (unsigned int k = 0; k < n; ++k)
            scaled[k] = normal_reaction[k] * normals(k, l);
          mass.vmult(scaled_forces, scaled);
          for (unsigned int j = 0; j < r; ++j)
            for (unsigned int k = 0; k < n; ++k)
              change(j, l) += normals(k, j) * scaled_forces[k];
        }
      change.gauss_jordan();
      Vector<double> beta(r);
      change.vmult(beta, imbalance);
      beta *= -1.;
      for (unsigned int k = 0; k < n; ++k)
        {
          double factor = 1.;
          for (unsigned int j = 0; j < r; ++j)
            factor += beta[j] * normals(k, j);
          AssertThrow(factor >= 0.,
                      ExcMessage("the contact reaction of a body held only "
                                 "by the contact cannot be made admissible "
                                 "(Contact/Condition = pointwise: try "
                                 "integral)"));
          normal_reaction[k] *= factor;
        }
      mass.vmult(forces, normal_reaction);
    }
  } // namespace



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
    LA::Vector                        &admissible_displacement)
  {
    Result      result;
    const auto &boundary  = problem.boundary();
    const auto &condition = problem.condition();
    const bool  integral  = (condition.name() == "integral");

    // R^_n at every node of GC (zero where there is no multiplier)
    const Vector<double> lambda = condition.multiplier(y);
    Vector<double>       normal_reaction(boundary.n_nodes());
    const auto          &multiplier_nodes = boundary.multiplier_nodes();
    for (unsigned int i = 0; i < multiplier_nodes.size(); ++i)
      {
        normal_reaction[multiplier_nodes[i]] =
          integral ? lambda[i] : std::min(lambda[i], 0.);
        result.positive_multipliers += (!integral && lambda[i] > 0.) ? 1 : 0;
      }

    // U^
    admissible_displacement = u_h;
    if (integral)
      {
        const Vector<double> q_n   = boundary.normal_components(u_h);
        const IndexSet       owned = u_h.locally_owned_elements();
        for (const unsigned int k : multiplier_nodes)
          {
            const double excess = q_n[k] - boundary.nodal_gap()[k];
            if (excess > 0.)
              for (unsigned int c = 0; c < dim; ++c)
                if (owned.is_element(boundary.node(k).dofs[c]))
                  admissible_displacement[boundary.node(k).dofs[c]] -=
                    excess * boundary.direction()[c];
          }
        admissible_displacement.compress(VectorOperation::add);
      }

    // The displacement whose stress is in FE equilibrium with R^
    LA::Vector equilibrated(u_h);
    if (result.positive_multipliers > 0)
      {
        // nodal forces of R^: (M R^_n)_k nu_c
        Vector<double> forces(boundary.n_nodes());
        boundary.mass_matrix().vmult(forces, normal_reaction);
        if (problem.n_rigid_motions() > 0)
          balance_on_rigid_motions(problem, normal_reaction, forces);
        // the preconditioner is that of the last active set: rebuild it for
        // the operator without contact constraints (a third of the CG
        // iterations at 4e5 DoFs)
        problem.update_preconditioner(
          std::vector<bool>(problem.n_constraints(), false));
        problem.solve_with_normal_forces(forces, equilibrated);
      }

    // sigma^ and the volume terms, on the cells of this rank (which read
    // the dofs of the cells around them)
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    const LA::Vector ghosted_equilibrated = with_ghosts(equilibrated, relevant);
    const LA::Vector ghosted_admissible =
      with_ghosts(admissible_displacement, relevant);
    Vector<double>                error_squared, sum_squared;
    const EquilibrationInput<dim> input{mapping,
                                        dof_handler,
                                        material,
                                        boundary_conditions,
                                        boundary,
                                        normal_reaction,
                                        ghosted_equilibrated};
    reconstruction->compute(input,
                            ghosted_admissible,
                            error_squared,
                            sum_squared);
    result.equilibrium_defect  = reconstruction->equilibrium_defect();
    result.prolongation_defect = reconstruction->prolongation_defect();

    // the contact term 2 int_GC R^_n (W^_n - g), per cell
    result.contact_local.reinit(error_squared.size());
    if (boundary.n_nodes() > 0)
      {
        const QGauss<dim - 1>            face_quadrature(4);
        FEFaceValues<dim>                fe_face_values(mapping,
                                         dof_handler.get_fe(),
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
                const Point<dim> a      = cell->face(f)->vertex(0);
                const double     r0     = normal_reaction[boundary.node_index(
                  cell->face(f)->vertex_index(0))];
                const double     r1     = normal_reaction[boundary.node_index(
                  cell->face(f)->vertex_index(1))];
                const double     length = cell->face(f)->measure();
                for (const unsigned int q :
                     fe_face_values.quadrature_point_indices())
                  {
                    const Point<dim> &x = fe_face_values.quadrature_point(q);
                    const double      s = x.distance(a) / length;
                    const double      r = (1. - s) * r0 + s * r1;
                    result.contact_local[cell->active_cell_index()] +=
                      2. * r *
                      (w_hat[q] * boundary.direction() - boundary.gap(x)) *
                      fe_face_values.JxW(q);
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
    result.e_squared   = volume_error + result.contact_term;
    result.denominator = volume_sum + result.contact_term;
    result.eps         = std::sqrt(result.e_squared / result.denominator);
    result.eps_contact = result.contact_term / result.e_squared;
    result.local.reinit(error_squared.size());
    for (unsigned int E = 0; E < error_squared.size(); ++E)
      result.local[E] =
        std::sqrt(std::max(error_squared[E] + result.contact_local[E], 0.) /
                  result.denominator);
    return result;
  }

  template class ConstitutiveRelationError<2>;
} // namespace Signorini
