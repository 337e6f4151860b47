#include <deal.II/distributed/tria_base.h>

#include <signorini/estimator/vertex_patches.h>

#include <algorithm>

namespace Signorini
{
  VertexPatches::VertexPatches(const Triangulation<2> &triangulation)
    : vertex_of_owned_cell(triangulation.n_vertices(), false)
    , computing_vertex(triangulation.n_vertices(), false)
    , owned_cell(triangulation.n_active_cells(), false)
    , needed_cell(triangulation.n_active_cells(), false)
    , first_cell_of_vertex(triangulation.n_vertices() + 1, 0)
    , cell_vertices(triangulation.n_active_cells())
    , cell_edges(triangulation.n_active_cells())
    , edge_cells(triangulation.n_raw_faces(),
                 {{numbers::invalid_unsigned_int,
                   numbers::invalid_unsigned_int}})
  {
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          owned_cell[cell->active_cell_index()] = true;
          for (const unsigned int v : cell->vertex_indices())
            vertex_of_owned_cell[cell->vertex_index(v)] = true;
        }

    // the lowest owner among the cells around each vertex computes its patch
    // (a serial triangulation owns everything: its subdomain ids are all 0)
    const auto *distributed =
      dynamic_cast<const parallel::TriangulationBase<2> *>(&triangulation);
    const types::subdomain_id this_rank =
      distributed != nullptr ? distributed->locally_owned_subdomain() : 0;
    std::vector<types::subdomain_id> lowest_owner(
      triangulation.n_vertices(), numbers::invalid_subdomain_id);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        lowest_owner[cell->vertex_index(v)] =
          std::min(lowest_owner[cell->vertex_index(v)],
                   distributed != nullptr ? cell->subdomain_id() :
                                            types::subdomain_id(0));
    for (unsigned int vertex = 0; vertex < triangulation.n_vertices(); ++vertex)
      computing_vertex[vertex] =
        vertex_of_owned_cell[vertex] && lowest_owner[vertex] == this_rank;

    // in active cell order, so that the patch cells and the first cell of
    // an edge do not depend on anything else (the cells around the vertices
    // counted, then placed)
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
            ++first_cell_of_vertex[cell->vertex_index(v) + 1];
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
    for (unsigned int vertex = 0; vertex < triangulation.n_vertices(); ++vertex)
      first_cell_of_vertex[vertex + 1] += first_cell_of_vertex[vertex];
    cells_around_vertices.resize(first_cell_of_vertex.back());
    std::vector<unsigned int> next_cell(first_cell_of_vertex.begin(),
                                        first_cell_of_vertex.end() - 1);
    for (unsigned int index = 0; index < cell_vertices.size(); ++index)
      if (needed_cell[index])
        for (const unsigned int vertex : cell_vertices[index])
          cells_around_vertices[next_cell[vertex]++] = index;
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
