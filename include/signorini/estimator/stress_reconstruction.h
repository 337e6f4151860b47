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
#include <signorini/registry.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * What a stress reconstruction needs: the mesh and element, the material,
   * the loads (body force, tractions, the admissible contact reaction R^ =
   * R^_n nu_c given by its values at the nodes of GC) and a finite element
   * displacement whose stress sigma_h is in finite element equilibrium with
   * these loads (U_h, or U~_h for the pointwise condition when some
   * Lambda_i > 0: paper section 5.2, ContactCondition::admissible_fields()).
   */
  template <int dim>
  struct EquilibrationInput
  {
    /// The mapping of the cells.
    const Mapping<dim> &mapping;
    /// The P1 vector element on the current mesh.
    const DoFHandler<dim> &dof_handler;
    /// K
    const LinearElasticMaterial<dim> &material;
    /// f_d, F_d and the Dirichlet part.
    const BoundaryConditions<dim> &boundary_conditions;
    /// GC and nu_c.
    const ContactBoundary<dim> &contact_boundary;
    /// R^_n at the nodes of GC.
    const Vector<double> &normal_reaction;
    /// The displacement whose stress is in FE equilibrium with the loads.
    const LA::Vector &equilibrated_displacement;
    /// R^_t at the nodes of GC (friction), or empty.
    const std::vector<Tensor<1, dim>> &tangential_reaction;

    /// R^ = R^_n nu_c + R^_t at node @p k of GC (a P1 field on GC).
    Tensor<1, dim>
    contact_reaction(const unsigned int k) const
    {
      Tensor<1, dim> reaction =
        normal_reaction[k] * contact_boundary.direction();
      if (!tangential_reaction.empty())
        reaction += tangential_reaction[k];
      return reaction;
    }
  };

  /**
   * Construction of a statically admissible stress field sigma^ from a finite
   * element solution (paper section 5, [LAD 91]; doc/theory.md section 7).
   * The interface the error estimator uses, implemented by the star-patch
   * construction and by the element equilibration technique; a strictly
   * admissible variant can be another. The reconstructions form a family
   * chosen by Error estimator/Stress reconstruction (registry()).
   */
  template <int dim>
  class StressReconstruction
  {
  public:
    virtual ~StressReconstruction() = default;

    /// The reconstructions, chosen by Error estimator/Stress reconstruction;
    /// each registers itself (SIGNORINI_REGISTER_TEMPLATE()).
    static Registry<StressReconstruction<dim>> &
    registry();

    /// The name the reconstruction is chosen by.
    const std::string &
    name() const;

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

    /**
     * Largest relative defect of condition() in the last compute(), over
     * all ranks: round-off if correct. It is a different check for each
     * reconstruction: the element equilibration's prolongation condition
     * (which its traction densities are built to satisfy), the star
     * patch's finite element equilibrium R(phi_i) = 0 of its input (on
     * which the equilibrium of the sum of the patch corrections rests).
     */
    double
    condition_defect() const
    {
      return max_condition_defect;
    }

    /// The condition whose defect condition_defect() measures, in words.
    virtual std::string
    condition() const = 0;

    /// The wall seconds of the steps of the last compute() on this rank, in
    /// order (empty where a reconstruction does not time its steps).
    const std::vector<std::pair<std::string, double>> &
    step_seconds() const
    {
      return steps;
    }

  protected:
    /// See step_seconds().
    std::vector<std::pair<std::string, double>> steps;
    /// See equilibrium_defect().
    double max_equilibrium_defect = 0.;
    /// See condition_defect().
    double max_condition_defect = 0.;
  };

  /// The message with which the reconstruction chosen as @p name refuses a
  /// dimension it is not written for.
  inline std::string
  reconstruction_is_2d_only(const std::string &name)
  {
    return "Error estimator/Stress reconstruction = " + name +
           " is implemented in 2D only (triangles); on tetrahedra choose "
           "star patch, or set Error estimator/Enable = false to compute "
           "without the estimator";
  }
} // namespace Signorini

#endif
