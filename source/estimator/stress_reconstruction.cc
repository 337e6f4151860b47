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
     *
     * A reconstruction not implemented in dimension dim (T::is_implemented
     * false) keeps its name and parameters, so that a parameter file reads
     * the same, but choosing it is an InputError naming the entry.
     */
    template <int dim, typename T>
    void
    add_reconstruction(Registry<StressReconstruction<dim>> &family,
                       const std::string                   &name,
                       const std::string                   &description,
                       const std::string                   &subsection)
    {
      if constexpr (!T::is_implemented)
        {
          using Declarer =
            typename Registry<StressReconstruction<dim>>::Declarer;
          Declarer declare;
          if constexpr (std::is_constructible_v<T, ParameterHandler &>)
            declare = [subsection](ParameterHandler &prm) {
              enter(prm, subsection);
              T::declare_parameters(prm);
              leave(prm);
            };
          else if constexpr (internal::HasParameters<T>::value)
            declare = [](ParameterHandler &prm) { T::declare_parameters(prm); };
          family.add(
            name,
            description,
            typeid(T),
            [name](ParameterHandler &)
              -> std::unique_ptr<StressReconstruction<dim>> {
              throw InputError(reconstruction_is_2d_only(name));
            },
            declare);
        }
      else if constexpr (std::is_constructible_v<T, ParameterHandler &>)
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
      add_reconstruction<dim, ElementEquilibration<dim>>(
        family,
        "element equilibration",
        "traction densities and element fields: by default enhanced "
        "densities and exactly equilibrated fields, a guaranteed bound; "
        "the paper's technique [LAD 91] with least squares densities and "
        "displacement fields",
        "Element equilibration");
      add_reconstruction<dim, StarPatchEquilibration<dim>>(
        family, "star patch", "flux-free vertex-patch problems", "Star patch");
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
  template class StressReconstruction<3>;
} // namespace Signorini
