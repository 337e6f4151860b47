// Hertz contact of a ball on a rigid plane in 3D
// (tests/inputs/hertz-sphere.prm: an eighth of the ball in tetrahedra graded
// towards the contact point, edge h = 0.005 there). With the load
// P = 4 |contact force| on the whole ball, Hertz gives the contact radius
// a = (3 P R / (4 E*))^(1/3) and the pressure p(r) = p0 (1 - r^2/a^2)^(1/2),
// p0 = 3 P / (2 pi a^2). Checked: every node closer to the axis than a - h
// is in contact and every node farther than a + h is not (the radius within
// one contact element); the nodal pressure (nodal force over the node's
// area) at the contact point and its largest value within 3 % of p0.
//
// The integral condition with the top face z = 0 moved down; the pointwise
// condition with the ball held by the contact alone: a pressure q on the top
// face instead of an imposed displacement, so that the vertical translation
// is stopped only by the plane. There the contact force must balance the
// load, and the same bounds hold.

#include "tests.h"

#include <cmath>

namespace
{
  struct ContactNode
  {
    double r, pressure;
    bool   multiplier, active;
  };

  std::vector<ContactNode>
  read_contact_table(const std::string &filename)
  {
    std::vector<ContactNode> nodes;
    for (auto &row : SignoriniTests::read_table(filename))
      nodes.push_back({std::hypot(std::stod(row["x"]), std::stod(row["y"])),
                       std::stod(row["nodal_pressure"]),
                       row["multiplier_node"] == "1",
                       row["active"] == "1"});
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
  const double h        = 0.005;  // the mesh size at the contact point
  const double q        = 0.0005; // pressure on the top face z = 0
  unsigned int failures = 0;
  const std::vector<std::pair<std::string, std::string>> cases = {
    {"displacement", "integral"}, {"force", "pointwise"}};
  for (const auto &[loading, condition] : cases)
    {
      const std::string output = "output-" + loading + "-" + condition;
      std::map<std::string, std::string> overrides{
        {"Contact/Condition", condition}, {"Output directory", output}};
      if (loading == "force")
        {
          overrides["Boundary conditions/Dirichlet 3/Boundary ids"] = "";
          overrides["Boundary conditions/Traction 1/Boundary ids"]  = "3";
          overrides["Boundary conditions/Traction 1/Function expression"] =
            "0; 0; " + std::to_string(-q);
        }
      const Result      r     = run<3>("hertz-sphere.prm", overrides);
      const std::string name  = loading + " controlled, " + condition;
      const double      force = std::abs(value(r, "contact_force"));
      expect_below(name + ": converged",
                   1. - value(r, "converged"),
                   0.,
                   failures);
      if (loading == "force")
        {
          // the top face is a polygonal quarter disc: its area is pi/4 to
          // about 1 %
          deallog << name << ": contact force / (q pi R^2 / 4) = "
                  << std::setprecision(4)
                  << force / (q * numbers::PI * R * R / 4.) << std::endl;
          expect_below(name + ": contact force = load",
                       std::abs(force / (q * numbers::PI * R * R / 4.) - 1.),
                       0.01,
                       failures);
        }
      const double P     = 4. * force;
      const double a     = std::cbrt(3. * P * R / (4. * E_star));
      const double p0    = 3. * P / (2. * numbers::PI * a * a);
      const auto   nodes = read_contact_table(output + "/contact-00.csv");

      double inner_open = 0., outer_active = 0., centre = 0., largest = 0.,
             last_active    = 0.;
      unsigned int n_active = 0;
      for (const ContactNode &node : nodes)
        {
          if (!node.multiplier)
            continue;
          if (node.r == 0.)
            centre = node.pressure;
          largest = std::max(largest, node.pressure);
          if (node.active)
            {
              ++n_active;
              last_active = std::max(last_active, node.r);
            }
          if (!node.active && node.r < a - h)
            inner_open = std::max(inner_open, a - h - node.r);
          if (node.active && node.r > a + h)
            outer_active = std::max(outer_active, node.r - a - h);
        }
      deallog << name << ": P = " << std::setprecision(4) << P << ", a = " << a
              << ", active nodes " << n_active
              << ", farthest at r = " << last_active
              << "; nodal pressure / p0: at the contact point " << centre / p0
              << ", largest " << largest / p0 << std::endl;
      expect_below(name + ": a/R <= 0.11", a / R, 0.11, failures);
      expect_below(name + ": nodes with r < a - h all in contact",
                   inner_open,
                   0.,
                   failures);
      expect_below(name + ": nodes with r > a + h all open",
                   outer_active,
                   0.,
                   failures);
      expect_below(name + ": pressure at the contact point within 3 % of p0",
                   std::abs(centre / p0 - 1.),
                   0.03,
                   failures);
      expect_below(name + ": largest pressure within 3 % of p0",
                   std::abs(largest / p0 - 1.),
                   0.03,
                   failures);
    }
  return failures == 0 ? 0 : 1;
}
