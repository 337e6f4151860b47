#include <signorini/estimator/element_equilibration.h>
#include <signorini/estimator/star_patch_equilibration.h>
#include <signorini/estimator/stress_reconstruction.h>

#include <type_traits>

namespace Signorini
{
  namespace
  {
    /// Enter Error estimator/@p subsection.
    void
    enter(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection("Error estimator");
      prm.enter_subsection(subsection);
    }

    /// Leave it.
    void
    leave(ParameterHandler &prm)
    {
      prm.leave_subsection();
      prm.leave_subsection();
    }

    /**
     * Register @p T, whose parameters are in Error estimator/@p subsection.
     * A reconstruction constructed from the ParameterHandler reads them in
     * the subsection its caller entered (and declares them there): enter it
     * for it. Any other is registered as the registry expects (it enters
     * its own section).
     */
    template <int dim, typename T>
    void
    add_reconstruction(Registry<StressReconstruction<dim>> &family,
                       const std::string                   &name,
                       const std::string                   &description,
                       const std::string                   &subsection)
    {
      if constexpr (std::is_constructible_v<T, ParameterHandler &>)
        family.add(
          name,
          description,
          typeid(T),
          [subsection](ParameterHandler &prm)
            -> std::unique_ptr<StressReconstruction<dim>> {
            enter(prm, subsection);
            auto member = std::make_unique<T>(prm);
            leave(prm);
            return member;
          },
          [subsection](ParameterHandler &prm) {
            enter(prm, subsection);
            T::declare_parameters(prm);
            leave(prm);
          });
      else
        family.template add<T>(name, description);
    }
  } // namespace



  template <int dim>
  const Registry<StressReconstruction<dim>> &
  StressReconstruction<dim>::registry()
  {
    static const Registry<StressReconstruction<dim>> reconstructions = [] {
      Registry<StressReconstruction<dim>> family(
        "Error estimator",
        "Stress reconstruction",
        "Construction of sigma^ (doc/estimator.md)");
      add_reconstruction<dim, StarPatchEquilibration<dim>>(
        family, "star patch", "flux-free vertex-patch problems", "Star patch");
      add_reconstruction<dim, ElementEquilibration<dim>>(
        family,
        "element equilibration",
        "the paper's element equilibration technique, [LAD 91]",
        "Element equilibration");
      return family;
    }();
    return reconstructions;
  }



  template <int dim>
  const std::string &
  StressReconstruction<dim>::name() const
  {
    return registry().name_of(*this);
  }



  template class StressReconstruction<2>;
} // namespace Signorini
