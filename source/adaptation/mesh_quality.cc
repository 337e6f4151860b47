#include <deal.II/base/exceptions.h>

#include <signorini/adaptation/mesh_quality.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>

namespace Signorini
{
  namespace
  {
    /// The smallest dihedral angle of the tetrahedra of @p mesh, in degrees;
    /// throws like minimum_angle() for a degenerate or inverted cell.
    double
    minimum_dihedral_angle(const Triangulation<3> &mesh)
    {
      double smallest    = 180.;
      int    orientation = 0; // of the first cell: +1 or -1
      for (const auto &cell : mesh.active_cell_iterators())
        {
          AssertThrow(cell->n_vertices() == 4,
                      ExcMessage("minimum_angle: a 3D mesh of tetrahedra "
                                 "only"));
          std::array<Point<3>, 4> x;
          for (unsigned int i = 0; i < 4; ++i)
            x[i] = cell->vertex(i);
          const Tensor<1, 3> a = x[1] - x[0], b = x[2] - x[0], c = x[3] - x[0];
          const double       signed_volume = (a * cross_product_3d(b, c)) / 6.;
          const double       scale =
            a.norm_square() + b.norm_square() + c.norm_square();
          const int sign = signed_volume > 0. ? 1 : -1;
          if (orientation == 0)
            orientation = sign;
          if (!(std::abs(signed_volume) > 1e-14 * scale * std::sqrt(scale)) ||
              sign != orientation)
            throw std::runtime_error("mesh cell " +
                                     std::to_string(cell->active_cell_index()) +
                                     " is inverted or degenerate");
          // the angle along edge (i, j) between the faces through the other
          // vertices k and l: that of their components normal to the edge
          static constexpr unsigned int edges[6][4] = {{0, 1, 2, 3},
                                                       {0, 2, 1, 3},
                                                       {0, 3, 1, 2},
                                                       {1, 2, 0, 3},
                                                       {1, 3, 0, 2},
                                                       {2, 3, 0, 1}};
          for (const auto &[i, j, k, l] : edges)
            {
              const Tensor<1, 3> e = (x[j] - x[i]) / (x[j] - x[i]).norm();
              Tensor<1, 3>       u = x[k] - x[i], w = x[l] - x[i];
              u -= (u * e) * e;
              w -= (w * e) * e;
              const double cosine = (u * w) / (u.norm() * w.norm());
              smallest            = std::min(smallest,
                                  std::acos(std::clamp(cosine, -1., 1.)) *
                                    180. / numbers::PI);
            }
        }
      return smallest;
    }



    /// The smallest interior angle of the triangles of @p mesh, in degrees.
    double
    minimum_triangle_angle(const Triangulation<2> &mesh)
    {
      constexpr int dim         = 2;
      double        smallest    = 180.;
      int           orientation = 0; // of the first cell: +1 or -1
      for (const auto &cell : mesh.active_cell_iterators())
        {
          const Point<dim> a = cell->vertex(0), b = cell->vertex(1),
                           c       = cell->vertex(2);
          const double signed_area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) -
                                            (b[1] - a[1]) * (c[0] - a[0]));
          const double scale = (b - a).norm_square() + (c - a).norm_square();
          // degenerate, or oriented unlike the others (folded)
          const int sign = signed_area > 0. ? 1 : -1;
          if (orientation == 0)
            orientation = sign;
          if (!(std::abs(signed_area) > 1e-14 * scale) || sign != orientation)
            throw std::runtime_error("mesh cell " +
                                     std::to_string(cell->active_cell_index()) +
                                     " is inverted or degenerate");
          for (unsigned int i = 0; i < 3; ++i)
            {
              const Point<dim> &p    = cell->vertex(i),
                               &q    = cell->vertex((i + 1) % 3),
                               &r    = cell->vertex((i + 2) % 3);
              const Tensor<1, dim> u = q - p, w = r - p;
              const double         cosine = (u * w) / (u.norm() * w.norm());
              smallest                    = std::min(smallest,
                                  std::acos(std::clamp(cosine, -1., 1.)) *
                                    180. / numbers::PI);
            }
        }
      return smallest;
    }
  } // namespace



  template <int dim>
  double
  minimum_angle(const Triangulation<dim> &mesh)
  {
    if constexpr (dim == 3)
      return minimum_dihedral_angle(mesh);
    else
      return minimum_triangle_angle(mesh);
  }



  template <int dim>
  std::vector<bool>
  cells_near_singular_points(const Triangulation<dim>        &mesh,
                             const std::vector<unsigned int> &extra_vertices)
  {
    // boundary ids met at every boundary vertex
    std::vector<std::set<types::boundary_id>> ids(mesh.n_vertices());
    for (const auto &face : mesh.active_face_iterators())
      if (face->at_boundary())
        for (const unsigned int v : face->vertex_indices())
          ids[face->vertex_index(v)].insert(face->boundary_id());
    std::vector<bool> singular(mesh.n_vertices(), false);
    for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
      singular[v] = ids[v].size() > 1;
    for (const unsigned int v : extra_vertices)
      singular[v] = true;

    std::vector<bool> near(mesh.n_active_cells(), false);
    for (const auto &cell : mesh.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (singular[cell->vertex_index(v)])
          near[cell->active_cell_index()] = true;
    return near;
  }

  template double
  minimum_angle(const Triangulation<2> &);
  template double
  minimum_angle(const Triangulation<3> &);
  template std::vector<bool>
  cells_near_singular_points(const Triangulation<2> &,
                             const std::vector<unsigned int> &);
  template std::vector<bool>
  cells_near_singular_points(const Triangulation<3> &,
                             const std::vector<unsigned int> &);
} // namespace Signorini
