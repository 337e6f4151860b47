// The nested start on a mesh without coarser levels (Contact/Nested start
// with Initial refinements = 0): the domain is meshed again by Gmsh at
// coarser sizes (CoarseDomainMesher) from the mesh's boundary, and the
// chain of those meshes gives the first active set and displacement. The
// meshes here are Gmsh meshes of the block (tests/meshes/square.geo at
// lc = 1/32, tests/meshes/block-3d.geo at lc = 1/8), with Nested start
// cells = 100; the cases: the paper's block with both conditions, the body
// held by the contact alone (the left edge a roller) and the 3D block.
// Checked for each: the runs from scratch and with the nested start
// converge to the same discrete solution (same active set, energies and
// contact forces to 1e-10 relative), the nested run did compute on coarser
// meshes, and it needs fewer active-set iterations on the mesh itself.

#include "tests.h"

#include <filesystem>

using namespace SignoriniTests;

namespace
{
  /// tests/meshes/@p name with its mesh size lc replaced by @p size, written
  /// to the working directory; its absolute path.
  std::string
  geometry_with_size(const std::string &name, const std::string &size)
  {
    std::ifstream     in(std::string(SOURCE_DIR) + "/../meshes/" + name);
    std::stringstream text;
    text << in.rdbuf();
    std::string       geometry = text.str();
    const std::string line     = "lc = 0.5;";
    AssertThrow(geometry.find(line) != std::string::npos,
                ExcMessage(name + " has no line " + line));
    geometry.replace(geometry.find(line), line.size(), "lc = " + size + ";");
    std::ofstream(name) << geometry;
    return std::filesystem::absolute(name).string();
  }



  /// compare_starts(), and the nested start did use coarser meshes.
  template <int dim>
  void
  compare_starts_from_gmsh(const std::string                        &prm_file,
                           const std::map<std::string, std::string> &overrides,
                           unsigned int                             &failures)
  {
    const Result nested =
      compare_starts<dim>(prm_file, overrides, failures).second;
    expect_below("coarser meshes computed (minus 1)",
                 -value(nested, "nested_meshes") + 1.,
                 0.,
                 failures);
  }
} // namespace



int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  unsigned int failures = 0;

  const std::map<std::string, std::string> square = {
    {"Mesh/Source", "file"},
    {"Mesh/File name", geometry_with_size("square.geo", "1/32")},
    {"Number of cycles", "1"},
    {"Contact/Nested start cells", "100"}};
  for (const std::string condition : {"integral", "pointwise"})
    {
      deallog << "--- Gmsh block, " << condition << " condition" << std::endl;
      auto overrides                 = square;
      overrides["Contact/Condition"] = condition;
      compare_starts_from_gmsh<2>("block.prm", overrides, failures);
    }
  {
    deallog << "--- Gmsh block held by the contact alone" << std::endl;
    auto overrides                                          = square;
    overrides["Boundary conditions/Dirichlet 1/Components"] = "x";
    compare_starts_from_gmsh<2>("block.prm", overrides, failures);
  }
  {
    deallog << "--- Gmsh 3D block, integral condition" << std::endl;
    compare_starts_from_gmsh<3>("../runs/block_3d_frank_wolfe.prm",
                                {{"Mesh/Source", "file"},
                                 {"Mesh/File name",
                                  geometry_with_size("block-3d.geo", "1/8")},
                                 {"Mesh/Initial refinements", "0"},
                                 {"Number of cycles", "1"},
                                 {"Contact/Condition", "integral"},
                                 {"Contact/Solver", "active set"},
                                 {"Contact/Nested start cells", "100"}},
                                failures);
  }

  deallog << (failures == 0 ? "all checks passed" : "FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
