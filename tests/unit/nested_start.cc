// The nested start of the active set method (Contact/Nested start): on one
// mesh with no previous mesh to start from, the block with 3 refinements is
// solved from scratch and with the nested start from the block with 0, 1
// and 2 refinements (Nested start cells = 100), for both conditions and for
// the paper's block, a gap case on the right edge (part of GC stays open) and
// a body held by the contact alone (the left edge a roller: the coarser
// meshes have a free rigid motion too). Checked for each: both runs converge
// to the same discrete solution (same active set, energies and contact
// forces to 1e-10 relative), the nested run did compute on the three coarser
// meshes, and it needs fewer active-set iterations on the mesh itself.

#include "tests.h"

int
main(int argc, char **argv)
{
  using namespace SignoriniTests;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  const std::map<std::string, std::string> mesh = {
    {"Mesh/Initial refinements", "3"},
    {"Number of cycles", "1"},
    {"Contact/Nested start cells", "100"}};
  std::map<std::string, std::map<std::string, std::string>> cases = {
    {"block", mesh},
    {"gap on the right edge", gap_on_right_edge()},
    {"held by the contact alone",
     {{"Boundary conditions/Dirichlet 1/Components", "x"}}}};
  for (auto &[name, overrides] : cases)
    overrides.insert(mesh.begin(), mesh.end());

  unsigned int failures = 0;
  for (const auto &[name, overrides] : cases)
    for (const std::string condition : {"integral", "pointwise"})
      {
        deallog << "--- " << name << ", " << condition << " condition"
                << std::endl;
        auto o                 = overrides;
        o["Contact/Condition"] = condition;
        const Result nested = compare_starts("block.prm", o, failures).second;
        expect_below("three coarser meshes",
                     std::abs(value(nested, "nested_meshes") - 3.),
                     0.,
                     failures);
      }
  return failures == 0 ? 0 : 1;
}
