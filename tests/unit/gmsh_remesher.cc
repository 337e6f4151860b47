// The remeshing realisation (GmshRemesher) on the generated block, in 2D and
// 3D: the block meshed anew by Gmsh with requested size ratios, a uniform
// one (every size of the initial mesh halved), then on that mesh a graded
// one (sizes halved again for the cells within 0.2 of the clamped face
// x = 0), and checked for
// - the domain: the cells fill the unit square or cube (area or volume 1);
// - the boundary ids: every boundary face has one, and each id covers its
//   part of the boundary exactly (x = 0 and y = 0: 1; the loaded halves and
//   their complements: 1/2; in 3D the faces z = 0 and z = 1: 2), which an id
//   lost or put on the wrong Gmsh entity would change;
// - the count: the realised cells against N* = sum_E r_E^-d, within 20 %
//   (in 3D, the calibration of Gmsh's Delaunay tetrahedra in the size);
// - the sizes: the mean size of the cells within the graded region against
//   the rest, about 1/2;
// - no cell is degenerate or inverted (minimum angle).

#include <deal.II/base/mpi.h>

#include <signorini/adaptation/gmsh_remesher.h>
#include <signorini/adaptation/mesh_quality.h>
#include <signorini/mesh_input.h>

#include "tests.h"

#include <map>

using namespace SignoriniTests;

namespace
{
  template <int dim>
  void
  check_mesh(const Triangulation<dim> &mesh,
             const double              predicted_cells,
             unsigned int             &failures)
  {
    double                               measure = 0.;
    std::map<types::boundary_id, double> measure_of_id;
    for (const auto &cell : mesh.active_cell_iterators())
      {
        measure += cell->measure();
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            measure_of_id[face->boundary_id()] += face->measure();
      }
    const double ratio = mesh.n_active_cells() / predicted_cells;
    deallog << mesh.n_active_cells()
            << " cells, N* = " << std::lround(predicted_cells)
            << ", realised / N* = " << std::setprecision(2) << ratio
            << std::setprecision(6) << std::endl;
    expect_below("realised within 20 % of N*",
                 std::abs(std::log(ratio)),
                 std::log(1.2),
                 failures);
    expect_below("measure of the domain = 1",
                 std::abs(measure - 1.),
                 1e-12,
                 failures);
    std::map<types::boundary_id, double> expected = {
      {1, 1.}, {2, 1.}, {3, 0.5}, {4, 0.5}, {5, 0.5}, {6, 0.5}};
    if (dim == 3)
      expected[7] = 2.;
    for (const auto &[id, value] : measure_of_id)
      if (expected.count(id) == 0)
        {
          deallog << "boundary id " << id << ": FAILED (not the block's)"
                  << std::endl;
          ++failures;
        }
    for (const auto &[id, value] : expected)
      expect_below("boundary id " + std::to_string(id) + " covers " +
                     std::to_string(value).substr(0, 3),
                   std::abs(measure_of_id[id] - value),
                   1e-12,
                   failures);
    deallog << "minimum angle " << std::setprecision(3) << minimum_angle(mesh)
            << " degrees" << std::setprecision(6) << std::endl;
  }



  template <int dim>
  unsigned int
  remesh_block()
  {
    deallog << dim << "D block" << std::endl;
    ParameterHandler prm;
    MeshInput<dim>::declare_parameters(prm);
    MeshInput<dim> input;
    input.parse_parameters(prm);
    Triangulation<dim> mesh;
    input.create(mesh);
    const GmshRemesher<dim> remesher;
    remesher.check_geometry(input, {1, 2, 3, 4, 5, 6});
    unsigned int failures = 0;

    deallog << "uniform: r_E = 1/2" << std::endl;
    Vector<double> ratio(mesh.n_active_cells());
    ratio                      = 0.5;
    const double uniform_cells = mesh.n_active_cells() * std::pow(2., dim);
    Triangulation<dim> uniform;
    uniform.copy_triangulation(mesh);
    remesher.remesh(input, ratio, uniform);
    check_mesh(uniform, uniform_cells, failures);

    deallog << "graded: r_E = 1/2 for x < 0.2" << std::endl;
    double predicted_cells = 0.;
    ratio.reinit(uniform.n_active_cells());
    for (const auto &cell : uniform.active_cell_iterators())
      {
        const double r                   = cell->center()[0] < 0.2 ? 0.5 : 1.;
        ratio[cell->active_cell_index()] = r;
        predicted_cells += std::pow(r, -double(dim));
      }
    Triangulation<dim> graded;
    graded.copy_triangulation(uniform);
    remesher.remesh(input, ratio, graded);
    check_mesh(graded, predicted_cells, failures);

    // mean size (measure^(1/d)) near x = 0 against beyond the transition
    double size_near = 0., size_far = 0.;
    int    n_near = 0, n_far = 0;
    for (const auto &cell : graded.active_cell_iterators())
      {
        const double size = std::pow(cell->measure(), 1. / dim);
        if (cell->center()[0] < 0.1)
          {
            size_near += size;
            ++n_near;
          }
        else if (cell->center()[0] > 0.4)
          {
            size_far += size;
            ++n_far;
          }
      }
    const double size_ratio = (size_near / n_near) / (size_far / n_far);
    deallog << "mean size for x < 0.1 / for x > 0.4 = " << std::setprecision(2)
            << size_ratio << std::setprecision(6) << std::endl;
    expect_below("graded sizes within 25 % of 1/2",
                 std::abs(std::log(2. * size_ratio)),
                 std::log(1.25),
                 failures);
    return failures;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const unsigned int failures = remesh_block<2>() + remesh_block<3>();
  deallog << (failures == 0 ? "all checks passed" : "FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
