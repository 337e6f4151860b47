// Hertz contact of a cylinder on a rigid plane (tests/inputs/hertz.prm), both
// discrete conditions: the computed contact half-width must be within one
// contact element of a = sqrt(4 P R / (pi E*)), and the contact pressure
// -Lambda within 5 % of p(x) = 2P/(pi a^2) sqrt(a^2 - x^2) in relative L2 norm
// over the contact zone, P being the computed load per unit length.
//
// Second, the same cylinder held by the contact alone: the top edge carries
// a prescribed load q per unit length of the quarter instead of an imposed
// displacement, so the vertical translation is stopped only by the plane.
// Then P = 2 q is known beforehand: the contact force must equal -q and the
// half-width and pressure meet the same bounds.

#include "tests.h"

namespace
{
  struct ContactNode
  {
    double x, pressure;
    bool   active;
  };

  std::vector<ContactNode>
  read_contact_table(const std::string &filename)
  {
    std::vector<ContactNode> nodes;
    for (auto &row : SignoriniTests::read_table(filename))
      nodes.push_back(
        {std::stod(row["x"]), -std::stod(row["Lambda"]), row["active"] == "1"});
    return nodes;
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace SignoriniTests;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  const double R = 1., E = 1., nu = 0.3, E_star = E / (1. - nu * nu);
  unsigned int failures = 0;
  const double q        = 0.003; // load of the force-controlled quarter
  for (const std::string loading : {"displacement", "force"})
    for (const std::string condition : {"integral", "pointwise"})
      {
        std::map<std::string, std::string> overrides{
          {"Contact/Condition", condition},
          {"Output directory", "output-" + loading + "-" + condition}};
        if (loading == "force")
          {
            overrides["Boundary conditions/Dirichlet 2/Boundary ids"] = "";
            overrides["Boundary conditions/Traction 1/Boundary ids"]  = "3";
            overrides["Boundary conditions/Traction 1/Function expression"] =
              "0; " + std::to_string(-q);
          }
        const Result      r    = run("hertz.prm", overrides);
        const double      P    = 2. * std::abs(value(r, "contact_force"));
        const std::string name = loading + " controlled, " + condition;
        if (loading == "force")
          expect_below(name + ": contact force = -q",
                       std::abs(value(r, "contact_force") + q),
                       1e-10 * q,
                       failures);
        const double a     = std::sqrt(4. * P * R / (numbers::PI * E_star));
        const auto   nodes = read_contact_table("output-" + loading + "-" +
                                              condition + "/contact-00.csv");

        // half-width: between the last active node and the next one
        unsigned int last = 0;
        for (unsigned int k = 0; k < nodes.size(); ++k)
          if (nodes[k].active)
            last = k;
        const double element = nodes[last + 1].x - nodes[last].x;

        // relative L2 error of the P1 pressure on (0, a)
        const auto exact = [&](const double x) {
          return x < a ?
                   2. * P / (numbers::PI * a * a) * std::sqrt(a * a - x * x) :
                   0.;
        };
        double error_sq = 0., norm_sq = 0.;
        for (unsigned int k = 0; k + 1 < nodes.size() && nodes[k].x < a; ++k)
          for (unsigned int s = 0; s < 200; ++s)
            {
              const double t = (s + 0.5) / 200.;
              const double x = nodes[k].x + t * (nodes[k + 1].x - nodes[k].x);
              if (x > a)
                break;
              const double dx = (nodes[k + 1].x - nodes[k].x) / 200.;
              const double ph =
                (1 - t) * nodes[k].pressure + t * nodes[k + 1].pressure;
              error_sq += (ph - exact(x)) * (ph - exact(x)) * dx;
              norm_sq += exact(x) * exact(x) * dx;
            }
        const double relative_error = std::sqrt(error_sq / norm_sq);

        deallog << name << ": P = " << std::setprecision(3) << P
                << ", a/R = " << a / R << ", computed half-width in ["
                << nodes[last].x << ", " << nodes[last + 1].x
                << "], pressure error " << std::fixed << std::setprecision(1)
                << 100. * relative_error << " %" << std::defaultfloat
                << std::endl;
        expect_below(name + ": a/R <= 0.1", a / R, 0.1, failures);
        expect_below(name + ": |a_h - a| within one contact element",
                     std::abs(nodes[last].x - a),
                     element,
                     failures);
        expect_below(name + ": relative L2 pressure error <= 5%",
                     relative_error,
                     0.05,
                     failures);
      }
  return failures == 0 ? 0 : 1;
}
