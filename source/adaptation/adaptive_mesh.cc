#include <deal.II/grid/grid_tools.h>

#include <signorini/adaptation/adaptive_mesh.h>
#include <signorini/free_memory.h>
#include <signorini/input_error.h>
#include <signorini/registry.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

namespace Signorini
{
  namespace
  {
    template <int dim>
    const NamedValues<typename AdaptiveMesh<dim>::Realisation> &
    realisation_names()
    {
      using Realisation = typename AdaptiveMesh<dim>::Realisation;
      static const NamedValues<Realisation> names(
        {{"refinement",
          Realisation::refinement,
          "red refinement of the initial mesh in whole levels (sizes in steps "
          "of 2), made conforming by green closure; 3D: uniform only"},
         {"bisection",
          Realisation::bisection,
          "newest-vertex bisection of the initial mesh (sizes in steps of "
          "sqrt 2), conforming without closure cells, 2D"},
         {"remeshing",
          Realisation::remeshing,
          "the geometry meshed anew by Gmsh with the predicted sizes as a "
          "continuous size field, 2D and 3D"}});
      return names;
    }
  } // namespace



  template <int dim>
  void
  AdaptiveMesh<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    prm.declare_entry("Realisation",
                      realisation_names<dim>().default_name(),
                      Patterns::Selection(realisation_names<dim>().selection()),
                      realisation_names<dim>().help(
                        "How the predicted sizes become the next mesh"));
    prm.leave_subsection();
  }



  template <int dim>
  void
  AdaptiveMesh<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh adaptation");
    chosen_realisation = realisation_names<dim>().value(prm.get("Realisation"));
    prm.leave_subsection();
    if (dim != 2 && chosen_realisation == Realisation::bisection)
      throw InputError("Mesh adaptation/Realisation = bisection: newest-vertex "
                       "bisection is implemented for triangles (2D) only");
  }



  template <int dim>
  typename AdaptiveMesh<dim>::Realisation
  AdaptiveMesh<dim>::realisation() const
  {
    return chosen_realisation;
  }



  template <int dim>
  double
  AdaptiveMesh<dim>::level_size_ratio() const
  {
    return chosen_realisation == Realisation::bisection ?
             std::pow(2., -1. / dim) :
             0.5;
  }



  template <int dim>
  void
  AdaptiveMesh<dim>::initialize(const MeshInput<dim> &input,
                                Triangulation<dim>   &mesh)
  {
    hierarchy.clear();
    hierarchy_released = false;
    from_input         = true;
    if (dim == 3)
      {
        // The input's tetrahedra are usually the mesh itself (one level,
        // every vertex used): built as the mesh, without a hierarchy to copy
        // them from, which on every rank held the mesh twice while it was
        // made (the peak of a 5.3M-DoF run: doc/parallel.md)
        mesh.clear();
        input.create(mesh);
        if (index_as_flat_mesh(mesh, input.initial_refinements))
          return;
        mesh.clear();
      }
    input.create(hierarchy);
    if (chosen_realisation == Realisation::bisection)
      {
        bisect(mesh, nullptr);
        return;
      }
    build_conforming_mesh(mesh);
    if (dim == 3) // (the 3D block is built refined: its cells are level 0)
      level_of.assign(level_of.size(), input.initial_refinements);
  }



  template <int dim>
  void
  AdaptiveMesh<dim>::adopt(Triangulation<dim> &mesh)
  {
    hierarchy.clear();
    hierarchy_released = false;
    from_input         = false;
    if (dim == 3 && index_as_flat_mesh(mesh, 0))
      return;
    hierarchy.copy_triangulation(mesh);
    build_conforming_mesh(mesh);
  }



  template <int dim>
  bool
  AdaptiveMesh<dim>::index_as_flat_mesh(const Triangulation<dim> &mesh,
                                        const unsigned int        level)
  {
    const auto &used = mesh.get_used_vertices();
    if (mesh.n_levels() != 1 ||
        !std::all_of(used.begin(), used.end(), [](const bool u) { return u; }))
      return false;
    hierarchy_cell_of.resize(mesh.n_active_cells());
    std::iota(hierarchy_cell_of.begin(), hierarchy_cell_of.end(), 0u);
    level_of.assign(mesh.n_active_cells(), level);
    green_cells = 0;
    return true;
  }



  template <int dim>
  void
  AdaptiveMesh<dim>::remesh(const MeshInput<dim>   &input,
                            const std::vector<int> &level_change,
                            Triangulation<dim>     &mesh)
  {
    AssertDimension(level_change.size(), level_of.size());
    Assert(from_input,
           ExcMessage("remesh() rebuilds from the input: not after adopt()"));
    Assert(!hierarchy_released,
           ExcMessage("remesh() after release_hierarchy()"));
    if (chosen_realisation == Realisation::bisection)
      {
        bisect(mesh, &level_change);
        return;
      }
    if (dim == 3)
      {
        // uniform changes only: the input is built anew at its new level
        // (MeshInput refines the 3D block itself, see there)
        const int change = level_change.empty() ? 0 : level_change[0];
        if (std::any_of(level_change.begin(),
                        level_change.end(),
                        [change](const int k) { return k != change; }))
          throw InputError("Mesh adaptation/Realisation: adapted meshes of "
                           "tetrahedra are made by remeshing (Realisation = "
                           "remeshing); refinement is uniform only in 3D");
        MeshInput<dim> refined      = input;
        refined.initial_refinements = std::max(0, int(level_of[0]) + change);
        initialize(refined, mesh);
        return;
      }
    using cell_iterator = typename Triangulation<dim>::cell_iterator;

    // requested level of every active cell of the current hierarchy
    std::vector<int> target(hierarchy.n_active_cells(), 0);
    for (unsigned int c = 0; c < level_change.size(); ++c)
      {
        const unsigned int h = hierarchy_cell_of[c];
        target[h] = std::max(target[h], int(level_of[c]) + level_change[c]);
      }
    const std::function<int(const cell_iterator &)> subtree_target =
      [&](const cell_iterator &cell) {
        if (cell->is_active())
          return target[cell->active_cell_index()];
        int result = 0;
        for (unsigned int child = 0; child < cell->n_children(); ++child)
          result = std::max(result, subtree_target(cell->child(child)));
        return result;
      };

    // Both hierarchies refine the same coarse cells with deal.II's fixed
    // child numbering, so they are walked together: a new cell is refined
    // while it is coarser than what the old cells inside it (or the old
    // active cell around it) ask for.
    Triangulation<dim> next;
    input.create(next);
    const std::function<bool(const cell_iterator &, const cell_iterator &, int)>
      flag = [&](const cell_iterator &cell,
                 const cell_iterator &old_cell,
                 const int            inherited) {
        const bool old_valid = (old_cell != hierarchy.end());
        if (cell->is_active())
          {
            const int wanted = old_valid ? subtree_target(old_cell) : inherited;
            if (int(cell->level()) < wanted)
              {
                cell->set_refine_flag();
                return true;
              }
            return false;
          }
        bool      any       = false;
        const int passed_on = (old_valid && old_cell->is_active()) ?
                                target[old_cell->active_cell_index()] :
                                inherited;
        for (unsigned int child = 0; child < cell->n_children(); ++child)
          any |= flag(cell->child(child),
                      (old_valid && old_cell->has_children()) ?
                        old_cell->child(child) :
                        hierarchy.end(),
                      passed_on);
        return any;
      };
    bool refined = true;
    while (refined)
      {
        refined       = false;
        auto old_cell = hierarchy.begin(0);
        for (auto cell = next.begin(0); cell != next.end(0); ++cell, ++old_cell)
          refined |= flag(cell, old_cell, 0);
        if (refined)
          next.execute_coarsening_and_refinement();
      }
    hierarchy.clear();
    hierarchy.copy_triangulation(next);
    build_conforming_mesh(mesh);
  }



  template <int dim>
  void
  AdaptiveMesh<dim>::build_conforming_mesh(Triangulation<dim> &mesh)
  {
    Assert(dim == 2, ExcNotImplemented());
    const auto n_hanging = [](const auto &cell) {
      unsigned int n = 0;
      for (const unsigned int f : cell->face_indices())
        n += cell->face(f)->has_children() ? 1 : 0;
      return n;
    };
    // 1. no cell with more than one hanging node (red refinement; deal.II
    //    keeps at most one hanging node per face)
    for (bool refined = true; refined;)
      {
        refined = false;
        for (const auto &cell : hierarchy.active_cell_iterators())
          if (n_hanging(cell) > 1)
            {
              cell->set_refine_flag();
              refined = true;
            }
        if (refined)
          hierarchy.execute_coarsening_and_refinement();
      }

    // 2. green closure: bisect the cells with one hanging node towards it.
    //    Face f of a triangle joins its vertices f and f+1 (mod 3); both
    //    halves keep the orientation of the cell.
    std::vector<CellData<dim>> cells;
    SubCellData                boundary;
    hierarchy_cell_of.clear();
    level_of.clear();
    green_cells = 0;
    for (const auto &cell : hierarchy.active_cell_iterators())
      {
        CellData<dim> data(3);
        data.material_id        = cell->material_id();
        unsigned int split_face = numbers::invalid_unsigned_int;
        for (const unsigned int f : cell->face_indices())
          {
            if (cell->face(f)->has_children())
              split_face = f;
            if (cell->face(f)->at_boundary())
              {
                CellData<1> line;
                line.vertices    = {cell->face(f)->vertex_index(0),
                                    cell->face(f)->vertex_index(1)};
                line.boundary_id = cell->face(f)->boundary_id();
                boundary.boundary_lines.push_back(line);
              }
          }
        const auto v = [&](const unsigned int i) {
          return cell->vertex_index(i % 3);
        };
        if (split_face == numbers::invalid_unsigned_int)
          {
            data.vertices = {v(0), v(1), v(2)};
            cells.push_back(data);
          }
        else
          {
            const unsigned int f = split_face;
            // deal.II keeps neighbours within one level across a face, so
            // the face has exactly one hanging node, its midpoint
            AssertThrow(!cell->face(f)->child(0)->has_children() &&
                          !cell->face(f)->child(1)->has_children(),
                        ExcMessage("green closure: a face with more than one "
                                   "hanging node"));
            const unsigned int midpoint =
              cell->face(f)->child(0)->vertex_index(1);
            Assert(cell->face(f)->child(0)->vertex_index(0) == v(f) ||
                     cell->face(f)->child(0)->vertex_index(0) == v(f + 1),
                   ExcInternalError());
            data.vertices = {v(f), midpoint, v(f + 2)};
            cells.push_back(data);
            data.vertices = {midpoint, v(f + 1), v(f + 2)};
            cells.push_back(data);
            green_cells += 2;
          }
        const unsigned int n_new =
          (split_face == numbers::invalid_unsigned_int) ? 1 : 2;
        for (unsigned int k = 0; k < n_new; ++k)
          {
            hierarchy_cell_of.push_back(cell->active_cell_index());
            level_of.push_back(cell->level());
          }
      }
    std::vector<Point<dim>> vertices = hierarchy.get_vertices();
    GridTools::delete_unused_vertices(vertices, cells, boundary);
    mesh.clear();
    mesh.create_triangulation(vertices, cells, boundary);
    AssertDimension(mesh.n_active_cells(), hierarchy_cell_of.size());
    // the cells keep the order of `cells`, which hierarchy_cell_of relies on
    for (const auto &cell : mesh.active_cell_iterators())
      {
        (void)cell;
        Assert(cell->vertex_index(0) ==
                 cells[cell->active_cell_index()].vertices[0],
               ExcInternalError());
      }
  }



  template <int dim>
  void
  AdaptiveMesh<dim>::bisect(Triangulation<dim>     &mesh,
                            const std::vector<int> *level_change)
  {
    if constexpr (dim == 2)
      {
        // the forest's roots are the input mesh, the hierarchy of level
        // initial_level
        if (level_change == nullptr)
          {
            forest.initialize(hierarchy);
            initial_level = hierarchy.n_levels() - 1;
          }
        else
          forest.refine(*level_change);
        forest.write(mesh);
        level_of.resize(forest.n_leaves());
        hierarchy_cell_of.clear(); // (no hierarchy cells: red refinement's)
        for (unsigned int c = 0; c < level_of.size(); ++c)
          level_of[c] = forest.generation(c);
        green_cells = 0;
      }
    else
      {
        (void)mesh;
        (void)level_change;
        Assert(false, ExcNotImplemented());
      }
  }



  template <int dim>
  std::pair<std::vector<int>, unsigned int>
  AdaptiveMesh<dim>::trial_remesh(const std::vector<int> &level_change)
  {
    Assert(!hierarchy_released,
           ExcMessage("trial_remesh() after release_hierarchy()"));
    if constexpr (dim == 2)
      if (chosen_realisation == Realisation::bisection)
        return forest.trial_refine(level_change);
    (void)level_change;
    return {};
  }



  template <int dim>
  double
  AdaptiveMesh<dim>::finest_halvings() const
  {
    const unsigned int finest =
      *std::max_element(level_of.begin(), level_of.end());
    return chosen_realisation == Realisation::bisection ?
             initial_level + double(finest) / dim :
             finest;
  }



  template <int dim>
  void
  AdaptiveMesh<dim>::release_hierarchy()
  {
    hierarchy.clear();
    hierarchy_released = true;
    forest             = BisectionForest();
    return_free_memory_to_system(); // (about 0.3 GiB at 1.6M cells)
  }



  template <int dim>
  const std::vector<unsigned int> &
  AdaptiveMesh<dim>::levels() const
  {
    return level_of;
  }



  template <int dim>
  unsigned int
  AdaptiveMesh<dim>::n_green_cells() const
  {
    return green_cells;
  }

  template <>
  void
  AdaptiveMesh<3>::build_conforming_mesh(Triangulation<3> &mesh)
  {
    // In 3D the hierarchy is the input's mesh, refined by MeshInput itself
    // (uniform cycles rebuild it, see remesh()). A flat one is the mesh
    // itself and never stored (index_as_flat_mesh()); the others' active
    // tetrahedra are copied, with the boundary ids of their faces.
    std::vector<CellData<3>> cells;
    SubCellData              boundary;
    hierarchy_cell_of.clear();
    level_of.clear();
    green_cells = 0;
    for (const auto &cell : hierarchy.active_cell_iterators())
      {
        hierarchy_cell_of.push_back(cell->active_cell_index());
        level_of.push_back(cell->level());
        for (const unsigned int f : cell->face_indices())
          {
            if (cell->face(f)->has_children())
              throw InputError(
                "Mesh adaptation/Realisation: adapted meshes of tetrahedra "
                "are made by remeshing (Realisation = remeshing); refinement "
                "is uniform only in 3D");
            if (cell->face(f)->at_boundary())
              {
                CellData<2> face(3);
                for (unsigned int i = 0; i < 3; ++i)
                  face.vertices[i] = cell->face(f)->vertex_index(i);
                face.boundary_id = cell->face(f)->boundary_id();
                boundary.boundary_quads.push_back(face);
              }
          }
        CellData<3> data(4);
        for (unsigned int i = 0; i < 4; ++i)
          data.vertices[i] = cell->vertex_index(i);
        data.material_id = cell->material_id();
        cells.push_back(data);
      }
    mesh.clear();
    std::vector<Point<3>> vertices = hierarchy.get_vertices();
    GridTools::delete_unused_vertices(vertices, cells, boundary);
    mesh.create_triangulation(vertices, cells, boundary);
    AssertDimension(mesh.n_active_cells(), hierarchy_cell_of.size());
  }

  template class AdaptiveMesh<2>;
  template class AdaptiveMesh<3>;
} // namespace Signorini
