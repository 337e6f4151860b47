#include <signorini/estimator/stress_reconstruction.h>

namespace Signorini
{
  template <int dim>
  Registry<StressReconstruction<dim>> &
  StressReconstruction<dim>::registry()
  {
    // the reconstructions register themselves in their own files
    static Registry<StressReconstruction<dim>> reconstructions(
      "Error estimator",
      "Stress reconstruction",
      "Construction of sigma^ (doc/estimator.md)",
      reconstruction_is_2d_only);
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
