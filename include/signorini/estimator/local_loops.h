#ifndef signorini_estimator_local_loops_h
#define signorini_estimator_local_loops_h

#include <deal.II/base/parallel.h>

#include <deal.II/dofs/dof_handler.h>

#include <exception>
#include <mutex>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  /**
   * A parallel loop over the active cells without a copier, for workers
   * that write only their own cell's entries: ranges of cells go to the
   * threads, each with its own copy of @p scratch (a WorkStream pipeline
   * cost a tenth of these loops at 1.6M DoFs). deal.II aborts the program
   * on an exception in a task: the first one is kept and rethrown here, so
   * that it reaches the caller's error handling.
   */
  template <int dim, typename Scratch, typename Worker>
  void
  for_each_cell(const DoFHandler<dim> &dof_handler,
                const Worker          &worker,
                const Scratch         &scratch)
  {
    using Iterator = typename DoFHandler<dim>::active_cell_iterator;
    std::vector<Iterator> cells;
    cells.reserve(dof_handler.get_triangulation().n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
      cells.push_back(cell);
    std::exception_ptr error;
    std::mutex         error_mutex;
    parallel::apply_to_subranges(
      std::size_t(0),
      cells.size(),
      [&](const std::size_t begin, const std::size_t end) {
        try
          {
            Scratch scratch_data(scratch);
            for (std::size_t i = begin; i < end; ++i)
              worker(cells[i], scratch_data);
          }
        catch (...)
          {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error)
              error = std::current_exception();
          }
      },
      256);
    if (error)
      std::rethrow_exception(error);
  }
} // namespace Signorini

#endif
