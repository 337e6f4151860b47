#include <deal.II/base/bounding_box.h>

#include <deal.II/numerics/rtree.h>

#include <deal.II/boost_adaptors/bounding_box.h>
#include <deal.II/boost_adaptors/point.h>

#include <signorini/nodal_interpolation.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <stdexcept>

namespace Signorini
{
  namespace
  {
    /// Barycentric coordinates of @p p in the triangle or tetrahedron of
    /// @p cell.
    template <typename Iterator, int dim>
    std::array<double, dim + 1>
    barycentric(const Iterator &cell, const Point<dim> &p)
    {
      if constexpr (dim == 2)
        {
          const Point<dim> a = cell->vertex(0), b = cell->vertex(1),
                           c = cell->vertex(2);
          const double det =
            (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
          const double l1 =
            ((p[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[1] - a[1])) /
            det;
          const double l2 =
            ((b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])) /
            det;
          return {{1. - l1 - l2, l1, l2}};
        }
      else
        {
          // p - x_0 = sum_k lambda_k (x_k - x_0), k = 1..dim
          Tensor<2, dim> edges;
          for (unsigned int k = 1; k <= dim; ++k)
            for (unsigned int d = 0; d < dim; ++d)
              edges[d][k - 1] = cell->vertex(k)[d] - cell->vertex(0)[d];
          const Tensor<1, dim> lambda = invert(edges) * (p - cell->vertex(0));
          std::array<double, dim + 1> result;
          result[0] = 1.;
          for (unsigned int k = 1; k <= dim; ++k)
            {
              result[k] = lambda[k - 1];
              result[0] -= lambda[k - 1];
            }
          return result;
        }
    }
  } // namespace



  template <int dim>
  Vector<double>
  interpolate_at_vertices(const DoFHandler<dim> &source,
                          const Vector<double>  &u,
                          const DoFHandler<dim> &target)
  {
    namespace bgi  = boost::geometry::index;
    using Iterator = typename DoFHandler<dim>::active_cell_iterator;

    std::vector<Iterator>                                  cells;
    std::vector<std::pair<BoundingBox<dim>, unsigned int>> boxes;
    for (const auto &cell : source.active_cell_iterators())
      {
        BoundingBox<dim> box = cell->bounding_box();
        box.extend(1e-6 * cell->diameter());
        boxes.emplace_back(box, cells.size());
        cells.push_back(cell);
      }
    const auto tree = pack_rtree(boxes);

    Vector<double>    result(target.n_dofs());
    std::vector<bool> done(target.get_triangulation().n_vertices(), false);
    std::vector<std::pair<BoundingBox<dim>, unsigned int>> hits;
    for (const auto &cell : target.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        {
          if (done[cell->vertex_index(v)])
            continue;
          done[cell->vertex_index(v)] = true;
          const Point<dim> &p         = cell->vertex(v);
          hits.clear();
          tree.query(bgi::intersects(p), std::back_inserter(hits));
          // the candidate the point is deepest inside (round-off on edges)
          double                      best_margin = -1e300;
          unsigned int                best        = 0;
          std::array<double, dim + 1> weights{};
          for (const auto &hit : hits)
            {
              const auto   lambda = barycentric(cells[hit.second], p);
              const double margin =
                *std::min_element(lambda.begin(), lambda.end());
              if (margin > best_margin)
                {
                  best_margin = margin;
                  best        = hit.second;
                  weights     = lambda;
                }
            }
          // (a vertex just outside, e.g. on a curved boundary, extrapolates)
          if (hits.empty())
            throw std::runtime_error(
              "interpolate_at_vertices: a vertex of the target mesh lies "
              "outside the source mesh");
          for (unsigned int c = 0; c < dim; ++c)
            {
              double value = 0.;
              for (unsigned int w = 0; w <= dim; ++w)
                value += weights[w] * u[cells[best]->vertex_dof_index(w, c)];
              result[cell->vertex_dof_index(v, c)] = value;
            }
        }
    return result;
  }

  template Vector<double>
  interpolate_at_vertices(const DoFHandler<2> &,
                          const Vector<double> &,
                          const DoFHandler<2> &);
  template Vector<double>
  interpolate_at_vertices(const DoFHandler<3> &,
                          const Vector<double> &,
                          const DoFHandler<3> &);
} // namespace Signorini
