#ifndef signorini_estimator_local_loops_h
#define signorini_estimator_local_loops_h

#include <deal.II/base/work_stream.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/grid/tria.h>

#include <exception>
#include <mutex>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * WorkStream::run over the active cells without a copier, for workers
   * that write only their own cell's entries. deal.II 9.4 aborts the
   * program on an exception in a worker: the first one is kept and
   * rethrown here, so that it reaches the caller's error handling.
   */
  template <int dim, typename Scratch, typename Worker>
  void
  for_each_cell(const DoFHandler<dim> &dof_handler,
                const Worker          &worker,
                const Scratch         &scratch)
  {
    using Iterator = typename DoFHandler<dim>::active_cell_iterator;
    struct NoCopy
    {};
    std::exception_ptr error;
    std::mutex         error_mutex;
    WorkStream::run(
      dof_handler.begin_active(),
      Iterator(dof_handler.end()),
      [&](const Iterator &cell, Scratch &scratch_data, NoCopy &) {
        try
          {
            worker(cell, scratch_data);
          }
        catch (...)
          {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error)
              error = std::current_exception();
          }
      },
      [](const NoCopy &) {},
      scratch,
      NoCopy());
    if (error)
      std::rethrow_exception(error);
  }

  /**
   * The vertex patches a rank treats and the cells they cover: every rank
   * holds the whole mesh (parallel::shared) and computes the error of the
   * cells it owns, whose local problems involve the patches of their
   * vertices (@p vertex_of_owned_cell), which cover the cells around them
   * (the returned flags, by active cell index).
   */
  template <int dim>
  std::vector<bool>
  cells_around_owned_cells(const Triangulation<dim> &triangulation,
                           std::vector<bool>        &vertex_of_owned_cell)
  {
    vertex_of_owned_cell.assign(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          vertex_of_owned_cell[cell->vertex_index(v)] = true;
    std::vector<bool> needed(triangulation.n_active_cells(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (vertex_of_owned_cell[cell->vertex_index(v)])
          needed[cell->active_cell_index()] = true;
    return needed;
  }
} // namespace Signorini

#endif
