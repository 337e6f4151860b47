#include <signorini/cell_locator.h>

#include <algorithm>
#include <iterator>

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



    template <int dim>
    std::vector<std::pair<BoundingBox<dim>, unsigned int>>
    cell_boxes(const Triangulation<dim> &mesh)
    {
      std::vector<std::pair<BoundingBox<dim>, unsigned int>> boxes;
      for (const auto &cell : mesh.active_cell_iterators())
        {
          BoundingBox<dim> box = cell->bounding_box();
          box.extend(1e-6 * cell->diameter());
          boxes.emplace_back(box, cell->active_cell_index());
        }
      return boxes;
    }
  } // namespace



  template <int dim>
  CellLocator<dim>::CellLocator(const Triangulation<dim> &mesh)
    : tree(pack_rtree(cell_boxes(mesh)))
  {
    cells.resize(mesh.n_active_cells());
    for (const auto &cell : mesh.active_cell_iterators())
      cells[cell->active_cell_index()] = cell;
  }



  template <int dim>
  typename CellLocator<dim>::Location
  CellLocator<dim>::locate(const Point<dim> &p) const
  {
    namespace bgi = boost::geometry::index;
    std::vector<std::pair<BoundingBox<dim>, unsigned int>> hits;
    tree.query(bgi::intersects(p), std::back_inserter(hits));
    if (hits.empty())
      tree.query(bgi::nearest(p, 1), std::back_inserter(hits));
    Location location;
    double   best_margin = -1e300;
    for (const auto &hit : hits)
      {
        const auto   lambda = barycentric(cells[hit.second], p);
        const double margin = *std::min_element(lambda.begin(), lambda.end());
        if (margin > best_margin)
          {
            best_margin      = margin;
            location.found   = true;
            location.cell    = hit.second;
            location.weights = lambda;
          }
      }
    return location;
  }



  template <int dim>
  const typename Triangulation<dim>::active_cell_iterator &
  CellLocator<dim>::cell(const unsigned int cell) const
  {
    return cells[cell];
  }

  template class CellLocator<2>;
  template class CellLocator<3>;
} // namespace Signorini
