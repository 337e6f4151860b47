#ifndef signorini_estimator_local_loops_h
#define signorini_estimator_local_loops_h

#include <deal.II/base/work_stream.h>

#include <deal.II/dofs/dof_handler.h>

#include <exception>
#include <mutex>

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
} // namespace Signorini

#endif
