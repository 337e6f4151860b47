#include <deal.II/base/mpi.h>

#include <signorini/linear_algebra.h>

namespace Signorini
{
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
