// The meshes of the adaptive computation (AdaptiveMesh), with both
// refinements of the initial mesh: from the paper's 96-triangle block, refine
// three levels around the contact/separation point (red refinement with green
// closure; or newest-vertex bisection, six generations: the same sizes) and
// check that
// - it is conforming: no hanging-node constraints, the boundary has the
//   length of the square's perimeter (an interior hanging edge would count)
//   and the areas add up to one;
// - every boundary id keeps its length;
// - the requested levels are met (and not exceeded), no cell is inverted and
//   the minimum angle is reported;
// - sizes can grow again: a rebuild with negative level changes gives the
//   initial mesh back, since each mesh is rebuilt from the initial one;
// - bisection: the trial of a request (trial_remesh) predicts the mesh
//   remesh() builds (cell count, smallest level change per cell), and the
//   Hertz mesh of Gmsh (arbitrary triangles) is refined conformingly too.

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/mapping_fe.h>

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/grid_tools_cache.h>

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



  /// Back to the initial mesh (sizes grow: every mesh is rebuilt from it).
  void
  back_to_initial_mesh(const MeshInput<2> &input,
                       AdaptiveMesh<2>    &adaptive,
                       Triangulation<2>   &mesh)
  {
    std::vector<int> change(mesh.n_active_cells());
    for (unsigned int c = 0; c < change.size(); ++c)
      change[c] = -int(adaptive.levels()[c]);
    adaptive.remesh(input, change, mesh);
    describe(mesh, adaptive);
  }



  void
  adapt_block(const AdaptiveMesh<2>::Realisation realisation,
              const std::string                 &name)
  {
    deallog << "Realisation = " << name << std::endl;
    ParameterHandler prm;
    read_parameters(prm, "block.prm", {{"Mesh adaptation/Realisation", name}});
    MeshInput<2> input;
    input.parse_parameters(prm);
    AdaptiveMesh<2> adaptive;
    adaptive.parse_parameters(prm);
    AssertThrow(adaptive.realisation() == realisation, ExcInternalError());
    // levels per halving of the size
    const int per_halving = static_cast<int>(
      std::round(-1. / std::log2(adaptive.level_size_ratio())));

    Triangulation<2> mesh;
    adaptive.initialize(input, mesh);
    describe(mesh, adaptive);

    // three halvings within 0.15 of the contact/separation point
    const Point<2>   separation(0.64, 0.);
    std::vector<int> change(mesh.n_active_cells(), 0);
    for (const auto &cell : mesh.active_cell_iterators())
      if (cell->center().distance(separation) < 0.15)
        change[cell->active_cell_index()] = 3 * per_halving;
    adaptive.remesh(input, change, mesh);
    describe(mesh, adaptive);
    unsigned int near = 0, near_fine = 0;
    for (const auto &cell : mesh.active_cell_iterators())
      if (cell->center().distance(separation) < 0.05)
        {
          ++near;
          near_fine += adaptive.levels()[cell->active_cell_index()] ==
                           unsigned(3 * per_halving) ?
                         1 :
                         0;
        }
    deallog << "cells within 0.05 of the separation point at level "
            << 3 * per_halving << ": " << near_fine << " of " << near
            << std::endl;

    // one more halving everywhere
    change.assign(mesh.n_active_cells(), per_halving);
    if (realisation == AdaptiveMesh<2>::Realisation::bisection)
      {
        const std::vector<unsigned int> old_levels = adaptive.levels();
        Triangulation<2>                old_mesh;
        old_mesh.copy_triangulation(mesh);
        const auto [trial_change, trial_cells] = adaptive.trial_remesh(change);
        adaptive.remesh(input, change, mesh);
        // the smallest level change per old cell, found by locating the
        // centre of every new cell in the old mesh
        std::vector<int>    smallest(old_levels.size(), 1000);
        const MappingFE<2>  mapping(FE_SimplexP<2>(1));
        GridTools::Cache<2> cache(old_mesh, mapping);
        for (const auto &cell : mesh.active_cell_iterators())
          {
            const auto found =
              GridTools::find_active_cell_around_point(cache, cell->center());
            const unsigned int old = found.first->active_cell_index();
            smallest[old] =
              std::min(smallest[old],
                       int(adaptive.levels()[cell->active_cell_index()]) -
                         int(old_levels[old]));
          }
        deallog << "trial_remesh: " << trial_cells << " cells predicted, "
                << mesh.n_active_cells() << " built; level changes "
                << (smallest == trial_change ? "as predicted" : "DIFFER")
                << std::endl;
      }
    else
      adaptive.remesh(input, change, mesh);
    describe(mesh, adaptive);

    back_to_initial_mesh(input, adaptive, mesh);
  }



  /// Bisection of the Gmsh mesh of tests/inputs/hertz.prm: five generations
  /// more in the cells with an edge on the contact boundary, then back.
  void
  bisect_hertz()
  {
    deallog << "Realisation = bisection, Hertz mesh" << std::endl;
    ParameterHandler prm;
    read_parameters(prm,
                    "hertz.prm",
                    {{"Mesh adaptation/Realisation", "bisection"}});
    MeshInput<2> input;
    input.parse_parameters(prm);
    input.set_input_directory(input_directory());
    AdaptiveMesh<2> adaptive;
    adaptive.parse_parameters(prm);
    Triangulation<2> mesh;
    adaptive.initialize(input, mesh);
    describe(mesh, adaptive);
    std::vector<int> change(mesh.n_active_cells(), 0);
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() == 2)
          change[cell->active_cell_index()] = 5;
    adaptive.remesh(input, change, mesh);
    describe(mesh, adaptive);
    back_to_initial_mesh(input, adaptive, mesh);
  }
} // namespace

int
main()
{
  initlog();
  adapt_block(AdaptiveMesh<2>::Realisation::refinement, "refinement");
  adapt_block(AdaptiveMesh<2>::Realisation::bisection, "bisection");
  bisect_hertz();
}
