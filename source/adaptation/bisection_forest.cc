#include <deal.II/base/exceptions.h>

#include <signorini/adaptation/bisection_forest.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace Signorini
{
  std::uint64_t
  BisectionForest::edge(const unsigned int a, const unsigned int b)
  {
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
  }



  void
  BisectionForest::initialize(const Triangulation<2> &coarse)
  {
    vertices = coarse.get_vertices();
    triangles.clear();
    leaves.clear();
    midpoint.clear();
    boundary_id.clear();
    for (const auto &cell : coarse.active_cell_iterators())
      {
        AssertThrow(cell->n_vertices() == 3,
                    ExcMessage("bisection: a mesh of triangles only"));
        const std::array<unsigned int, 3> v = {{cell->vertex_index(0),
                                                cell->vertex_index(1),
                                                cell->vertex_index(2)}};
        // The longest edge is the refinement edge, ties broken by the
        // vertex numbers so that both neighbours of an edge agree.
        unsigned int apex = 0;
        for (unsigned int k = 1; k < 3; ++k)
          {
            const auto opposite = [&](const unsigned int i) {
              const unsigned int a = v[(i + 1) % 3], b = v[(i + 2) % 3];
              return std::make_pair((vertices[a] - vertices[b]).norm_square(),
                                    edge(a, b));
            };
            if (opposite(k) > opposite(apex))
              apex = k;
          }
        Triangle root;
        // a cyclic permutation keeps the orientation of the cell
        root.vertex      = {{v[apex], v[(apex + 1) % 3], v[(apex + 2) % 3]}};
        root.material_id = cell->material_id();
        leaves.push_back(triangles.size());
        triangles.push_back(root);
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            boundary_id[edge(face->vertex_index(0), face->vertex_index(1))] =
              face->boundary_id();
      }
    n_roots = triangles.size();
  }



  std::array<int, 2>
  BisectionForest::children(const unsigned int t)
  {
    if (triangles[t].child[0] >= 0)
      return triangles[t].child;
    const Triangle     parent = triangles[t];
    const unsigned int a = parent.vertex[0], b = parent.vertex[1],
                       c = parent.vertex[2];
    const auto [entry, is_new] =
      midpoint.try_emplace(edge(b, c),
                           static_cast<unsigned int>(vertices.size()));
    const unsigned int m = entry->second;
    if (is_new)
      {
        vertices.push_back(0.5 * (vertices[b] + vertices[c]));
        const auto on_boundary = boundary_id.find(edge(b, c));
        if (on_boundary != boundary_id.end())
          {
            const types::boundary_id id = on_boundary->second;
            boundary_id[edge(b, m)]     = id;
            boundary_id[edge(m, c)]     = id;
          }
      }
    // The midpoint is the newest vertex of both halves; their refinement
    // edges are the parent's other two edges. Both keep its orientation.
    Triangle first = parent, second = parent;
    first.vertex  = {{m, a, b}};
    second.vertex = {{m, c, a}};
    for (Triangle *child : {&first, &second})
      {
        child->generation = parent.generation + 1;
        child->parent     = t;
        child->child      = {{-1, -1}};
      }
    const int n        = triangles.size();
    triangles[t].child = {{n, n + 1}};
    triangles.push_back(first);
    triangles.push_back(second);
    return triangles[t].child;
  }



  void
  BisectionForest::refine(const std::vector<int> &generation_change)
  {
    AssertDimension(generation_change.size(), leaves.size());
    const unsigned int n = triangles.size();
    // request of every current leaf, and the largest request inside every
    // triangle of the current forest (-1: none)
    std::vector<int> request(n, -1), inside(n, -1);
    for (unsigned int i = 0; i < leaves.size(); ++i)
      {
        const unsigned int t = leaves[i];
        const int          wanted =
          std::max(int(triangles[t].generation) + generation_change[i], 0);
        request[t] = wanted;
        // the requests inside grow towards the roots: stop where one is met
        for (int a = t; a >= 0 && inside[a] < wanted; a = triangles[a].parent)
          inside[a] = wanted;
      }

    // A triangle is bisected while it is coarser than the current leaf
    // around it, or than a current leaf inside it, asks.
    leaves.clear();
    std::vector<std::pair<unsigned int, int>> stack; // (triangle, inherited)
    for (unsigned int r = n_roots; r-- > 0;)
      stack.emplace_back(r, -1);
    while (!stack.empty())
      {
        auto [t, inherited] = stack.back();
        stack.pop_back();
        if (t < n && request[t] >= 0)
          inherited = request[t];
        const int wanted = std::max(inherited, t < n ? inside[t] : -1);
        if (int(triangles[t].generation) < wanted)
          {
            const std::array<int, 2> child = children(t);
            stack.emplace_back(child[1], inherited);
            stack.emplace_back(child[0], inherited);
          }
        else
          leaves.push_back(t);
      }
    close();
  }



  std::pair<std::vector<int>, unsigned int>
  BisectionForest::trial_refine(const std::vector<int> &generation_change)
  {
    const std::vector<unsigned int> current = leaves;
    refine(generation_change);
    std::vector<int> old_leaf(triangles.size(), -1),
      new_leaf(triangles.size(), -1);
    for (unsigned int i = 0; i < current.size(); ++i)
      old_leaf[current[i]] = i;
    for (unsigned int i = 0; i < leaves.size(); ++i)
      new_leaf[leaves[i]] = i;
    std::vector<int> change(current.size(), std::numeric_limits<int>::max());
    // a new leaf inside (or equal to) a current one
    for (const unsigned int t : leaves)
      for (int a = t; a >= 0; a = triangles[a].parent)
        if (old_leaf[a] >= 0)
          {
            int &smallest = change[old_leaf[a]];
            smallest      = std::min(smallest,
                                int(triangles[t].generation) -
                                  int(triangles[a].generation));
            break;
          }
    // a current leaf inside a new one
    for (unsigned int i = 0; i < current.size(); ++i)
      for (int a = triangles[current[i]].parent; a >= 0;
           a     = triangles[a].parent)
        if (new_leaf[a] >= 0)
          {
                change[i] = int(triangles[a].generation) -
                            int(triangles[current[i]].generation);
                break;
          }
    const unsigned int n_new = leaves.size();
    leaves                   = current;
    return {change, n_new};
  }



  void
  BisectionForest::close()
  {
    // A leaf has a hanging node iff the midpoint of one of its edges is a
    // vertex of a leaf: the leaves on its side of the edge are itself.
    std::vector<unsigned int> use(vertices.size(), 0);
    for (const unsigned int t : leaves)
      for (const unsigned int v : triangles[t].vertex)
        ++use[v];
    const auto has_hanging_node = [&](const unsigned int t) {
      const auto &v = triangles[t].vertex;
      for (unsigned int k = 0; k < 3; ++k)
        {
          const auto m = midpoint.find(edge(v[k], v[(k + 1) % 3]));
          if (m != midpoint.end() && m->second < use.size() &&
              use[m->second] > 0)
            return true;
        }
      return false;
    };
    for (bool bisected = true; bisected;)
      {
        bisected = false;
        for (unsigned int i = 0; i < leaves.size();)
          {
            const unsigned int t = leaves[i];
            if (!has_hanging_node(t))
              {
                ++i;
                continue;
              }
            // Mitchell's condition (longest edges first) bounds the
            // recursion; this only guards against a broken forest
            if (triangles[t].generation > 200)
              throw std::runtime_error(
                "bisection: the conforming closure does not end");
            const std::array<int, 2> child = children(t);
            use.resize(vertices.size(), 0);
            for (const unsigned int v : triangles[t].vertex)
              --use[v];
            for (const int c : child)
              for (const unsigned int v : triangles[c].vertex)
                ++use[v];
            leaves[i] = child[0];
            leaves.push_back(child[1]);
            bisected = true;
          }
      }

    // the leaves in depth-first order of the trees, for locality
    std::vector<bool> is_leaf(triangles.size(), false);
    for (const unsigned int t : leaves)
      is_leaf[t] = true;
    leaves.clear();
    std::vector<unsigned int> stack;
    for (unsigned int r = n_roots; r-- > 0;)
      stack.push_back(r);
    while (!stack.empty())
      {
        const unsigned int t = stack.back();
        stack.pop_back();
        if (is_leaf[t])
          leaves.push_back(t);
        else
          {
            stack.push_back(triangles[t].child[1]);
            stack.push_back(triangles[t].child[0]);
          }
      }
  }



  void
  BisectionForest::write(Triangulation<2> &mesh) const
  {
    std::vector<unsigned int> number(vertices.size(),
                                     numbers::invalid_unsigned_int);
    std::vector<Point<2>>     points;
    std::vector<CellData<2>>  cells;
    SubCellData               boundary;
    cells.reserve(leaves.size());
    for (const unsigned int t : leaves)
      {
        const Triangle &triangle = triangles[t];
        CellData<2>     cell(3);
        cell.material_id = triangle.material_id;
        for (unsigned int k = 0; k < 3; ++k)
          {
            const unsigned int v = triangle.vertex[k];
            if (number[v] == numbers::invalid_unsigned_int)
              {
                number[v] = points.size();
                points.push_back(vertices[v]);
              }
            cell.vertices[k] = number[v];
          }
        for (unsigned int k = 0; k < 3; ++k)
          {
            const unsigned int a = triangle.vertex[k],
                               b = triangle.vertex[(k + 1) % 3];
            const auto id        = boundary_id.find(edge(a, b));
            if (id != boundary_id.end())
              {
                CellData<1> line;
                line.vertices    = {number[a], number[b]};
                line.boundary_id = id->second;
                boundary.boundary_lines.push_back(line);
              }
          }
        cells.push_back(cell);
      }
    mesh.clear();
    mesh.create_triangulation(points, cells, boundary);
    AssertDimension(mesh.n_active_cells(), leaves.size());
  }



  unsigned int
  BisectionForest::n_leaves() const
  {
    return leaves.size();
  }



  unsigned int
  BisectionForest::generation(const unsigned int i) const
  {
    return triangles[leaves[i]].generation;
  }
} // namespace Signorini
