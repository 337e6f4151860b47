#include <signorini/estimator/vertex_patches.h>

#include <algorithm>

namespace Signorini
{
  VertexPatches::VertexPatches(const Triangulation<2> &triangulation)
    : vertex_of_owned_cell(triangulation.n_vertices(), false)
    , needed_cell(triangulation.n_active_cells(), false)
    , cells_around_vertex(triangulation.n_vertices())
    , cell_vertices(triangulation.n_active_cells())
    , cell_edges(triangulation.n_active_cells())
    , edge_cells(triangulation.n_raw_faces(),
                 {{numbers::invalid_unsigned_int,
                   numbers::invalid_unsigned_int}})
  {
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          vertex_of_owned_cell[cell->vertex_index(v)] = true;

    // in active cell order, so that the patch cells and the first cell of
    // an edge do not depend on anything else
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const unsigned int index = cell->active_cell_index();
        for (const unsigned int v : cell->vertex_indices())
          if (vertex_of_owned_cell[cell->vertex_index(v)])
            needed_cell[index] = true;
        if (!needed_cell[index])
          continue;
        for (const unsigned int v : cell->vertex_indices())
          {
            cell_vertices[index][v] = cell->vertex_index(v);
            cells_around_vertex[cell->vertex_index(v)].push_back(index);
          }
        for (const unsigned int e : cell->face_indices())
          {
            cell_edges[index][e] = cell->face_index(e);
            Assert((cell->face(e)->vertex_index(0) == cell->vertex_index(e) &&
                    cell->face(e)->vertex_index(1) ==
                      cell->vertex_index((e + 1) % 3)) ||
                     (cell->face(e)->vertex_index(1) == cell->vertex_index(e) &&
                      cell->face(e)->vertex_index(0) ==
                        cell->vertex_index((e + 1) % 3)),
                   ExcInternalError());
            auto &cells = edge_cells[cell_edges[index][e]];
            cells[cells[0] == numbers::invalid_unsigned_int ? 0 : 1] = index;
          }
      }
  }



  unsigned int
  VertexPatches::local_vertex(const unsigned int cell,
                              const unsigned int vertex) const
  {
    const auto &global = cell_vertices[cell];
    const auto  found  = std::find(global.begin(), global.end(), vertex);
    Assert(found != global.end(), ExcInternalError());
    return found - global.begin();
  }
} // namespace Signorini
