// The self-registering families (include/signorini/registry.h):
// - every member registered itself from its own file, and the choices are
//   in the order of the ranks, whatever the order of static initialisation;
// - members added out of order are listed by rank, the lowest the default,
//   and a rank taken twice is refused;
// - a reconstruction not implemented in a dimension keeps its name and
//   parameters there, and choosing it is an InputError naming the entry.

#include <signorini/adaptation/fixed_fraction.h>
#include <signorini/adaptation/optimal_size.h>
#include <signorini/adaptation/uniform_refinement.h>
#include <signorini/contact/condition.h>
#include <signorini/contact/solver.h>
#include <signorini/estimator/stress_reconstruction.h>

#include "tests.h"

using namespace SignoriniTests;

namespace
{
  /// A reconstruction written for triangles only, with a parameter.
  struct TrianglesOnly : public StressReconstruction<3>
  {
    static constexpr bool is_implemented = false;

    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Triangles only");
      prm.declare_entry("Degree", "1", Patterns::Integer(1));
      prm.leave_subsection();
    }

    void
    parse_parameters(ParameterHandler &)
    {}
  };
} // namespace



int
main()
{
  initlog();
  deallog << "reconstructions 2D: "
          << StressReconstruction<2>::registry().selection() << std::endl;
  deallog << "reconstructions 3D: "
          << StressReconstruction<3>::registry().selection() << std::endl;
  deallog << "conditions 2D: " << ContactCondition<2>::registry().selection()
          << std::endl;
  deallog << "conditions 3D: " << ContactCondition<3>::registry().selection()
          << std::endl;
  deallog << "solvers 2D: " << ContactSolver<2>::registry().selection()
          << std::endl;
  deallog << "solvers 3D: " << ContactSolver<3>::registry().selection()
          << std::endl;
  deallog << "size predictors: " << SizePredictor::registry().selection()
          << std::endl;

  {
    Registry<SizePredictor, unsigned int> family("Test", "Choice", "Help");
    family.add<FixedFractionPredictor>(7, "fixed fraction", "c");
    family.add<UniformRefinement>(2, "uniform", "a");
    family.add<OptimalSizePredictor>(5, "optimal size", "b");
    ParameterHandler prm;
    family.declare_parameters(prm);
    prm.enter_subsection("Test");
    deallog << "by rank: " << family.selection()
            << ", default: " << prm.get("Choice") << std::endl;
    prm.leave_subsection();
    try
      {
        Registry<SizePredictor, unsigned int> clash("Test", "Choice", "Help");
        clash.add<UniformRefinement>(0, "uniform", "a");
        clash.add<OptimalSizePredictor>(0, "optimal size", "b");
        deallog << "same rank: accepted" << std::endl;
      }
    catch (const ExceptionBase &)
      {
        deallog << "same rank: refused" << std::endl;
      }
  }

  {
    StressReconstruction<3>::registry().add<TrianglesOnly>(9,
                                                           "triangles only",
                                                           "a test");
    ParameterHandler prm;
    StressReconstruction<3>::registry().declare_parameters(prm);
    set_entry(prm, "Error estimator/Stress reconstruction", "triangles only");
    set_entry(prm, "Triangles only/Degree", "2");
    try
      {
        StressReconstruction<3>::registry().create(prm);
        deallog << "triangles only in 3D: created" << std::endl;
      }
    catch (const InputError &error)
      {
        deallog << "triangles only in 3D: " << error.what() << std::endl;
      }
  }
}
