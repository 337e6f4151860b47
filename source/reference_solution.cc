#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <signorini/cell_locator.h>
#include <signorini/nodal_interpolation.h>
#include <signorini/reference_solution.h>
#include <signorini/registry.h>

#include <cmath>
#include <iostream>
#include <limits>

namespace Signorini
{
  namespace
  {
    template <typename Mesh>
    const NamedValues<Mesh> &
    mesh_names()
    {
      static const NamedValues<Mesh> names(
        {{"initial mesh",
          Mesh::initial_mesh,
          "refined uniformly and solved first; nested in uniform cycles"},
         {"final mesh",
          Mesh::final_mesh,
          "the last mesh of the computations refined uniformly and solved "
          "last; for adapted meshes, which are locally finer than any "
          "affordable uniform mesh"}});
      return names;
    }
  } // namespace



  template <int dim>
  void
  ReferenceSolution<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Reference solution");
    prm.declare_entry("Extra refinements",
                      "0",
                      Patterns::Integer(0, 6),
                      "If > 0, solve once on a finer mesh with the same "
                      "condition (see Mesh: the initial mesh refined this many "
                      "levels beyond Number of cycles - 1, or the last mesh "
                      "refined this many times) and report eps_ex, the "
                      "effectivity and the Prager-Synge check against it.");
    prm.declare_entry("Mesh",
                      mesh_names<Mesh>().default_name(),
                      Patterns::Selection(mesh_names<Mesh>().selection()),
                      mesh_names<Mesh>().help(
                        "The mesh the reference refines"));
    prm.leave_subsection();
  }



  template <int dim>
  ReferenceSolution<dim>::ReferenceSolution()
    : timer(ConditionalOStream(std::cout, false))
    , triangulation(MPI_COMM_WORLD,
                    Triangulation<dim>::none,
                    /*allow_artificial_cells=*/false,
                    parallel::shared::Triangulation<dim>::partition_metis)
  {}



  template <int dim>
  void
  ReferenceSolution<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Reference solution");
    extra_levels = prm.get_integer("Extra refinements");
    mesh_choice  = mesh_names<Mesh>().value(prm.get("Mesh"));
    prm.leave_subsection();
    if (enabled())
      reference = std::make_unique<ContactComputation<dim>>(prm, timer);
  }



  template <int dim>
  bool
  ReferenceSolution<dim>::enabled() const
  {
    return extra_levels > 0;
  }



  template <int dim>
  typename ReferenceSolution<dim>::Mesh
  ReferenceSolution<dim>::mesh() const
  {
    return mesh_choice;
  }



  template <int dim>
  unsigned int
  ReferenceSolution<dim>::extra_refinements() const
  {
    return extra_levels;
  }



  template <int dim>
  void
  ReferenceSolution<dim>::solve_on_initial_mesh(const MeshInput<dim> &input,
                                                const unsigned int    levels)
  {
    MeshInput<dim> fine_input      = input;
    fine_input.initial_refinements = levels;
    adaptive_mesh.initialize(fine_input, triangulation);
    adaptive_mesh.release_hierarchy();
    reference->setup(triangulation);
    reference->enable_nested_start(fine_input);
    reference->assemble();
    reference->solve();
    is_solved = true;
  }



  template <int dim>
  void
  ReferenceSolution<dim>::solve_on(
    const Triangulation<dim>                             &fine_mesh,
    const typename ContactComputation<dim>::ContactState &state)
  {
    triangulation.clear();
    triangulation.copy_triangulation(fine_mesh);
    reference->setup(triangulation);
    reference->assemble();
    reference->set_initial_contact_state(state);
    reference->solve();
    is_solved = true;
  }



  template <int dim>
  bool
  ReferenceSolution<dim>::solved() const
  {
    return is_solved;
  }



  template <int dim>
  const ContactComputation<dim> &
  ReferenceSolution<dim>::computation() const
  {
    return *reference;
  }



  template <int dim>
  unsigned int
  ReferenceSolution<dim>::level() const
  {
    Assert(is_solved && mesh_choice == Mesh::initial_mesh,
           ExcMessage("level(): only for a solved initial-mesh reference"));
    return adaptive_mesh.levels()[0];
  }



  template <int dim>
  typename ReferenceSolution<dim>::Comparison
  ReferenceSolution<dim>::compare(const DoFHandler<dim> &dof_handler,
                                  const Vector<double>  &u_h,
                                  const Vector<double>  &u_hat,
                                  const double           eps,
                                  const double           e) const
  {
    return comparison(dof_handler, u_h, u_hat, eps, e, /*with_local=*/true);
  }



  template <int dim>
  typename ReferenceSolution<dim>::Comparison
  ReferenceSolution<dim>::comparison(const DoFHandler<dim> &dof_handler,
                                     const Vector<double>  &u_h,
                                     const Vector<double>  &u_hat,
                                     const double           eps,
                                     const double           e,
                                     const bool             with_local) const
  {
    // the fields on the reference mesh: exact where it refines the mesh of
    // the computation (uniform cycles, the last mesh of a final-mesh
    // reference), nodal interpolation elsewhere (across the green edges of
    // red refinement; a bisected mesh is never nested in a red-refined
    // initial mesh)
    const LA::Vector &u_ref        = reference->displacement();
    const auto        on_reference = [&](const Vector<double> &u) {
      const Vector<double> fine =
        interpolate_at_vertices(dof_handler, u, reference->dof_handler());
      LA::Vector result(u_ref);
      for (const auto i : result.locally_owned_elements())
        result[i] = fine[i];
      result.compress(VectorOperation::insert);
      return result;
    };
    const auto norm = [&](const LA::Vector &v) {
      return std::sqrt(reference->stiffness_matrix().matrix_norm_square(v));
    };
    const LA::Vector u_h_fine = on_reference(u_h);
    LA::Vector       difference(u_ref), sum(u_ref);
    difference -= u_h_fine;
    sum += u_h_fine;
    Comparison   result;
    const double denominator = norm(sum);
    // a problem without stress (no load, or a rigid motion imposed): both
    // errors vanish, and eps_ex is not the ratio of two round-offs. The
    // round-off of the energy norm: a machine epsilon of every nodal value,
    // sqrt(sum_i K_ii v_i^2) for v = u_ref + u_h
    double nodal_energy = 0.;
    for (const auto i : sum.locally_owned_elements())
      nodal_energy +=
        reference->stiffness_matrix().diag_element(i) * sum[i] * sum[i];
    nodal_energy =
      Utilities::MPI::sum(nodal_energy, sum.get_mpi_communicator());
    if (!(denominator > 1e2 * std::numeric_limits<double>::epsilon() *
                          std::sqrt(nodal_energy)))
      {
        if (with_local)
          result.local.reinit(dof_handler.get_triangulation().n_active_cells());
        // (the estimate of such a problem is zero too: exact, ratio 1)
        if (u_hat.size() > 0)
          result.effectivity = result.prager_synge_ratio =
            (e == 0. ? 1. : std::numeric_limits<double>::infinity());
        return result;
      }
    result.eps_ex = norm(difference) / denominator;
    if (with_local)
      {
        result.local = local_energies(dof_handler, difference);
        for (double &value : result.local)
          value = std::sqrt(value) / denominator;
      }
    if (u_hat.size() > 0)
      {
        LA::Vector error_hat(u_ref);
        error_hat -= on_reference(u_hat);
        result.effectivity        = eps / result.eps_ex;
        result.prager_synge_ratio = norm(error_hat) / e;
      }
    return result;
  }



  template <int dim>
  Vector<double>
  ReferenceSolution<dim>::local_energies(const DoFHandler<dim> &dof_handler,
                                         const LA::Vector &difference) const
  {
    // P1 on straight cells: a constant strain per reference cell, so one
    // point integrates a(e, e) = int sigma(e) : eps(e) exactly, as the
    // stiffness matrix of the global norm does
    const Vector<double>             e = replicate(difference);
    const CellLocator<dim>           locator(dof_handler.get_triangulation());
    const QGaussSimplex<dim>         quadrature(1);
    FEValues<dim>                    fe_values(reference->mapping(),
                            reference->finite_element(),
                            quadrature,
                            update_gradients | update_JxW_values);
    const FEValuesExtractors::Vector displacement(0);
    std::vector<SymmetricTensor<2, dim>> strain(quadrature.size());
    const LinearElasticMaterial<dim>    &material = reference->material();
    Vector<double> energies(dof_handler.get_triangulation().n_active_cells());
    // every cell on every rank (the whole mesh is on each), in one order
    for (const auto &cell : reference->dof_handler().active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values[displacement].get_function_symmetric_gradients(e, strain);
        double energy = 0.;
        for (const unsigned int q : fe_values.quadrature_point_indices())
          energy += (material.stress(strain[q]) * strain[q]) * fe_values.JxW(q);
        const auto location = locator.locate(cell->center());
        AssertThrow(location.found,
                    ExcMessage("the computational mesh has no cells"));
        energies[location.cell] += energy;
      }
    return energies;
  }



  template <int dim>
  void
  ReferenceSolution<dim>::keep(const ContactComputation<dim> &computation,
                               const Vector<double>          &u_hat,
                               const double                   eps,
                               const double                   e)
  {
    const DoFHandler<dim> &dof_handler = computation.dof_handler();
    auto                   kept        = std::make_unique<Computation>();
    kept->mesh.copy_triangulation(dof_handler.get_triangulation());
    kept->dof_handler.reinit(kept->mesh);
    kept->dof_handler.distribute_dofs(computation.finite_element());
    kept->displacement.reinit(dof_handler.n_dofs());
    kept->admissible_displacement.reinit(
      u_hat.size() > 0 ? dof_handler.n_dofs() : 0);
    // the copy has the same cells in the same order: match them by vertex
    const Vector<double> u_h  = replicate(computation.displacement());
    auto                 copy = kept->dof_handler.begin_active();
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int c = 0; c < dim; ++c)
            {
              const auto from        = cell->vertex_dof_index(v, c);
              const auto to          = copy->vertex_dof_index(v, c);
              kept->displacement[to] = u_h[from];
              if (u_hat.size() > 0)
                kept->admissible_displacement[to] = u_hat[from];
            }
        ++copy;
      }
    kept->eps = eps;
    kept->e   = e;
    computations.push_back(std::move(kept));
  }



  template <int dim>
  std::vector<typename ReferenceSolution<dim>::Comparison>
  ReferenceSolution<dim>::compare_kept() const
  {
    std::vector<Comparison> comparisons;
    for (const auto &computation : computations)
      comparisons.push_back(comparison(computation->dof_handler,
                                       computation->displacement,
                                       computation->admissible_displacement,
                                       computation->eps,
                                       computation->e,
                                       /*with_local=*/false));
    return comparisons;
  }

  template class ReferenceSolution<2>;
  template class ReferenceSolution<3>;
} // namespace Signorini
