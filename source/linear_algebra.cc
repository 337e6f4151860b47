#include <deal.II/base/mpi.h>

#include <signorini/linear_algebra.h>

#include <dlfcn.h>

namespace Signorini
{
  namespace
  {
    /**
     * The small dense factorisations of the estimator's local problems run
     * on deal.II's worker threads (and one process per core under MPI);
     * OpenBLAS's own threads would oversubscribe the cores (the star-patch
     * estimator ran 10x slower on two cores). Set once when the library is
     * loaded, if the BLAS is OpenBLAS (looked up, not linked).
     */
    const bool single_threaded_blas = []() {
      using SetThreads = void (*)(int);
      if (const auto set_threads = reinterpret_cast<SetThreads>(
            dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
        set_threads(1);
      return true;
    }();
  } // namespace

  dealii::Vector<double>
  gather(const LA::Vector                                   &v,
         const std::vector<dealii::types::global_dof_index> &indices)
  {
    dealii::Vector<double> values(indices.size());
    const dealii::IndexSet owned = v.locally_owned_elements();
    for (unsigned int k = 0; k < indices.size(); ++k)
      if (owned.is_element(indices[k]))
        values[k] = v[indices[k]];
    if (dealii::Utilities::MPI::n_mpi_processes(v.get_mpi_communicator()) > 1)
      dealii::Utilities::MPI::sum(values, v.get_mpi_communicator(), values);
    return values;
  }



  dealii::Vector<double>
  replicate(const LA::Vector &v)
  {
    dealii::Vector<double> values(v.size());
    for (const auto i : v.locally_owned_elements())
      values[i] = v[i];
    if (dealii::Utilities::MPI::n_mpi_processes(v.get_mpi_communicator()) > 1)
      dealii::Utilities::MPI::sum(values, v.get_mpi_communicator(), values);
    return values;
  }



  LA::Vector
  with_ghosts(const LA::Vector &v, const dealii::IndexSet &ghosts)
  {
    dealii::IndexSet relevant = v.locally_owned_elements();
    relevant.add_indices(ghosts);
    LA::Vector result(v.locally_owned_elements(),
                      relevant,
                      v.get_mpi_communicator());
    result = v;
    return result;
  }
} // namespace Signorini
