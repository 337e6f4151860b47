#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <signorini/exact_solution.h>
#include <signorini/input_error.h>

#include <cmath>

namespace Signorini
{
  template <int dim>
  void
  ExactSolution<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Exact solution");
    {
      prm.declare_entry("Enable",
                        "false",
                        Patterns::Bool(),
                        "Compare with a known displacement (manufactured "
                        "solution): adds energy_error to the statistics.");
      Functions::ParsedFunction<dim>::declare_parameters(prm, dim);
    }
    prm.leave_subsection();
  }



  template <int dim>
  void
  ExactSolution<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Exact solution");
    if (prm.get_bool("Enable"))
      {
        displacement = parse_function<dim>(prm, dim, "Exact solution");
        // (compared with the end of the load path, t = 1)
        displacement->set_time(1.);
      }
    prm.leave_subsection();
  }



  template <int dim>
  bool
  ExactSolution<dim>::enabled() const
  {
    return displacement != nullptr;
  }



  template <int dim>
  const Function<dim> *
  ExactSolution<dim>::function() const
  {
    return displacement.get();
  }



  template <int dim>
  typename ExactSolution<dim>::Error
  ExactSolution<dim>::error(const ContactComputation<dim> &computation) const
  {
    // ||u - u_h||_u^2 = int eps(u - u_h) : K : eps(u - u_h)
    const QGaussSimplex<dim>         quadrature(4);
    FEValues<dim>                    fe_values(computation.mapping(),
                            computation.finite_element(),
                            quadrature,
                            update_gradients | update_quadrature_points |
                              update_JxW_values);
    const FEValuesExtractors::Vector u(0);
    const LA::Vector ghosted = with_ghosts(computation.displacement(),
                                           computation.locally_relevant_dofs());
    const LinearElasticMaterial<dim>        &material = computation.material();
    std::vector<Tensor<2, dim>>              grad_h(quadrature.size());
    std::vector<std::vector<Tensor<1, dim>>> grad(
      quadrature.size(), std::vector<Tensor<1, dim>>(dim));
    double error_sq = 0., norm_sq = 0.;
    for (const auto &cell : computation.dof_handler().active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        fe_values[u].get_function_gradients(ghosted, grad_h);
        displacement->vector_gradient_list(fe_values.get_quadrature_points(),
                                           grad);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            Tensor<2, dim> g;
            for (unsigned int c = 0; c < dim; ++c)
              g[c] = grad[q][c];
            const SymmetricTensor<2, dim> e  = symmetrize(g - grad_h[q]);
            const SymmetricTensor<2, dim> ex = symmetrize(g);
            error_sq += (material.stress(e) * e) * fe_values.JxW(q);
            norm_sq += (material.stress(ex) * ex) * fe_values.JxW(q);
          }
      }
    const MPI_Comm communicator = MPI_COMM_WORLD;
    error_sq                    = Utilities::MPI::sum(error_sq, communicator);
    norm_sq                     = Utilities::MPI::sum(norm_sq, communicator);
    Error result;
    result.energy_error = std::sqrt(error_sq);
    // (undefined for a zero exact solution)
    if (norm_sq > 0.)
      result.relative_energy_error = std::sqrt(error_sq / norm_sq);
    return result;
  }

  template class ExactSolution<2>;
  template class ExactSolution<3>;
} // namespace Signorini
