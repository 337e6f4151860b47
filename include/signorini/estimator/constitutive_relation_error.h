#ifndef signorini_estimator_constitutive_relation_error_h
#define signorini_estimator_constitutive_relation_error_h

#include <deal.II/base/parameter_handler.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/vector.h>

#include <signorini/boundary_conditions.h>
#include <signorini/contact/discrete_problem.h>
#include <signorini/contact/friction_law.h>
#include <signorini/contact/frictional_active_set_solver.h>
#include <signorini/estimator/stress_reconstruction.h>
#include <signorini/linear_algebra.h>
#include <signorini/material.h>

#include <memory>

namespace Signorini
{
  using namespace dealii;

  /**
   * The error in constitutive relation for unilateral contact (paper
   * sections 3 and 5; doc/theory.md section 7, doc/estimator.md).
   *
   * Admissible fields from the finite element solution (U_h, Lambda):
   * - R^, U^ and the displacement whose stress is in finite element
   *   equilibrium with R^ from the contact condition
   *   (ContactCondition::admissible_fields(): paper sections 5.1 and 5.2);
   * - sigma^ from a StressReconstruction (by default element equilibration
   *   with enhanced densities and Johnson-Mercier fields, a guaranteed
   *   bound; or the paper's element equilibration, or the star patch).
   *
   * Then, per element E and with D = ||sigma^ + K eps(U^)||^2 + 2 int R^_n
   * (W^_n - g):
   *   eps_E^2 = (||sigma^ - K eps(U^)||^2_E + 2 int_{GC cap dE} R^_n (W^_n -
   * g)) / D  [10] and eps^2 = sum_E eps_E^2 [11].
   *
   * With friction the contact term has the bipotential's friction part
   * (de Saxce; Coorevits, Hild and Hjiaj 2001), 2 int s |W^_t| + R^_t .
   * W^_t >= 0, s = mu |R^_n| (Coulomb) or the threshold (Tresca), in D as
   * well.
   */
  template <int dim>
  class ConstitutiveRelationError
  {
  public:
    /// The estimate and its checks.
    struct Result
    {
      double         eps          = 0.; ///< [9]
      double         eps_contact  = 0.; ///< share of the contact term in eps^2
      double         e_squared    = 0.; ///< e^2 [8], [14]
      double         denominator  = 0.; ///< D
      double         contact_term = 0.; ///< 2 int R^_n (W^_n - g) >= 0
      Vector<double> local;             ///< eps_E per active cell
      Vector<double> contact_local;     ///< contact term per active cell
      /// StressReconstruction::equilibrium_defect()
      double equilibrium_defect = 0.;
      /// StressReconstruction::condition_defect(): the prolongation
      /// condition (element equilibration) or the FE equilibrium (star
      /// patch)
      double       condition_defect     = 0.;
      unsigned int positive_multipliers = 0; ///< pointwise: Lambda_i > 0
      /// StressReconstruction::step_seconds()
      std::vector<std::pair<std::string, double>> step_seconds;
      /// No stress and no contact work, to round-off (no load, or a rigid
      /// motion imposed): the solution is exact and eps = 0.
      bool stress_free = false;
      /// Strains within 1e5 round-offs of max |u_h| / h_min (a rigid motion
      /// much larger than the deformation): eps is not reliable.
      bool polluted_by_round_off = false;
    };

    /// Section Error estimator: Enable, and the stress reconstructions.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Read it and, if enabled, create the chosen stress reconstruction
    /// (which throws an InputError if it is not implemented in dimension
    /// dim).
    void
    parse_parameters(ParameterHandler &prm);

    /// Error estimator/Enable
    bool
    enabled() const;

    /**
     * Estimate the error of (u_h, y) on the problem's mesh; @p
     * admissible_displacement receives U^. With friction (@p friction_law
     * enabled), @p friction_state is the solution's: from its tangential
     * multipliers the condition builds R^_t in the Coulomb cone or the
     * Tresca disc, and e^2 has the bipotential's friction term on the
     * slip since the previous load step.
     */
    Result
    estimate(const DiscreteContactProblem<dim> &problem,
             const Mapping<dim>                &mapping,
             const DoFHandler<dim>             &dof_handler,
             const LinearElasticMaterial<dim>  &material,
             const BoundaryConditions<dim>     &boundary_conditions,
             const LA::Vector                  &u_h,
             const Vector<double>              &y,
             LA::Vector                        &admissible_displacement,
             const FrictionLaw<dim>            *friction_law   = nullptr,
             const FrictionState<dim>          *friction_state = nullptr);

  private:
    /// Error estimator/Enable
    bool is_enabled = false;
    /// sigma^ (null unless enabled)
    std::unique_ptr<StressReconstruction<dim>> reconstruction;
  };
} // namespace Signorini

#endif
