#ifndef signorini_estimator_stress_reconstruction_h
#define signorini_estimator_stress_reconstruction_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/vector.h>

#include <signorini/boundary_conditions.h>
#include <signorini/contact/contact_boundary.h>
#include <signorini/linear_algebra.h>
#include <signorini/material.h>

#include <memory>
#include <string>

namespace Signorini
{
  using namespace dealii;

  /**
   * What a stress reconstruction needs: the mesh and element, the material,
   * the loads (body force, tractions, the admissible contact reaction R^ =
   * R^_n nu_c given by its values at the nodes of GC) and a finite element
   * displacement whose stress sigma_h is in finite element equilibrium with
   * these loads (U_h, or U~_h for the pointwise condition when some
   * Lambda_i > 0, spec section 4).
   */
  template <int dim>
  struct EquilibrationInput
  {
    const Mapping<dim>               &mapping;
    const DoFHandler<dim>            &dof_handler;
    const LinearElasticMaterial<dim> &material;
    const BoundaryConditions<dim>    &boundary_conditions;
    const ContactBoundary<dim>       &contact_boundary;
    const Vector<double>             &normal_reaction;
    const LA::Vector                 &equilibrated_displacement;
  };

  /**
   * Construction of a statically admissible stress field sigma^ from a finite
   * element solution (spec section 4). The interface the error estimator
   * uses, implemented by the star-patch construction and by the element
   * equilibration technique; a strictly admissible variant can be another.
   */
  template <int dim>
  class StressReconstruction
  {
  public:
    virtual ~StressReconstruction() = default;

    virtual std::string
    name() const = 0;

    /**
     * Build sigma^ and return, for every active cell this rank owns (by
     * active cell index; zero for the others),
     * ||sigma^ - K eps(U^)||^2_{sigma,E} in @p error_squared and
     * ||sigma^ + K eps(U^)||^2_{sigma,E} in @p sum_squared, U^ being
     * @p admissible_displacement. Under MPI the displacements carry the
     * ghost entries of the locally relevant dofs.
     */
    virtual void
    compute(const EquilibrationInput<dim> &input,
            const LA::Vector              &admissible_displacement,
            Vector<double>                &error_squared,
            Vector<double>                &sum_squared) = 0;

    /// Largest relative defect of the equilibrium of the data of the local
    /// problems (EET: resultant and moment of the element data; star patch:
    /// residual of the patch problems) in the last compute(), over all
    /// ranks: round-off if correct.
    double
    equilibrium_defect() const
    {
      return max_equilibrium_defect;
    }

    /// Largest relative defect of the condition the construction rests on
    /// (EET: the prolongation condition; star patch: the FE equilibrium
    /// R(phi_i) = 0) in the last compute(), over all ranks. Reported as
    /// `prolongation_defect`.
    double
    prolongation_defect() const
    {
      return max_prolongation_defect;
    }

  protected:
    double max_equilibrium_defect  = 0.;
    double max_prolongation_defect = 0.;
  };
} // namespace Signorini

#endif
