// The meshes of the adaptive computation (AdaptiveMesh): from the paper's
// 96-triangle block, refine three levels around the contact/separation
// point, build the conforming mesh by green closure and check that
// - it is conforming: no hanging-node constraints, the boundary has the
//   length of the square's perimeter (an interior hanging edge would count)
//   and the areas add up to one;
// - every boundary id keeps its length;
// - the requested levels are met (and not exceeded), no cell is inverted and
//   the minimum angle is reported;
// - sizes can grow again: a rebuild with negative level changes gives the
//   initial mesh back, since each mesh is rebuilt from the initial one.

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_simplex_p.h>

#include <signorini/adaptation/adaptive_mesh.h>
#include <signorini/adaptation/mesh_quality.h>

#include "tests.h"

using namespace SignoriniTests;

namespace
{
  void
  describe(const Triangulation<2> &mesh, const AdaptiveMesh<2> &adaptive)
  {
    DoFHandler<2> dof_handler(mesh);
    dof_handler.distribute_dofs(FE_SimplexP<2>(1));
    AffineConstraints<double> hanging;
    DoFTools::make_hanging_node_constraints(dof_handler, hanging);

    double                         area = 0., perimeter = 0.;
    std::map<unsigned int, double> length_of_id;
    for (const auto &cell : mesh.active_cell_iterators())
      {
        area += cell->measure();
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              perimeter += face->measure();
              length_of_id[face->boundary_id()] += face->measure();
            }
      }
    const auto &levels = adaptive.levels();
    deallog << mesh.n_active_cells() << " cells (" << adaptive.n_green_cells()
            << " green), " << mesh.n_used_vertices() << " nodes, levels "
            << *std::min_element(levels.begin(), levels.end()) << ".."
            << *std::max_element(levels.begin(), levels.end())
            << ", hanging-node constraints " << hanging.n_constraints()
            << ", area " << area << ", boundary length " << perimeter
            << ", minimum angle " << minimum_angle(mesh) << std::endl;
    deallog << "   boundary lengths by id:";
    for (const auto &[id, length] : length_of_id)
      deallog << ' ' << id << ':' << length;
    deallog << std::endl;
  }
} // namespace

int
main()
{
  initlog();
  ParameterHandler prm;
  read_parameters(prm, "block.prm", {});
  MeshInput<2> input;
  input.parse_parameters(prm);

  AdaptiveMesh<2>  adaptive;
  Triangulation<2> mesh;
  adaptive.initialize(input, mesh);
  describe(mesh, adaptive);

  // three levels within 0.15 of the contact/separation point
  const Point<2>   separation(0.64, 0.);
  std::vector<int> change(mesh.n_active_cells(), 0);
  for (const auto &cell : mesh.active_cell_iterators())
    if (cell->center().distance(separation) < 0.15)
      change[cell->active_cell_index()] = 3;
  adaptive.remesh(input, change, mesh);
  describe(mesh, adaptive);
  unsigned int near = 0, near_fine = 0;
  for (const auto &cell : mesh.active_cell_iterators())
    if (cell->center().distance(separation) < 0.05)
      {
        ++near;
        near_fine += adaptive.levels()[cell->active_cell_index()] == 3 ? 1 : 0;
      }
  deallog << "cells within 0.05 of the separation point at level 3: "
          << near_fine << " of " << near << std::endl;

  // one more level everywhere
  change.assign(mesh.n_active_cells(), 1);
  adaptive.remesh(input, change, mesh);
  describe(mesh, adaptive);

  // back to the initial mesh: sizes grow
  change.resize(mesh.n_active_cells());
  for (unsigned int c = 0; c < change.size(); ++c)
    change[c] = -int(adaptive.levels()[c]);
  adaptive.remesh(input, change, mesh);
  describe(mesh, adaptive);
}
