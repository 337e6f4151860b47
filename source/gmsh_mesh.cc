#include <deal.II/base/mpi.h>
#include <deal.II/base/tensor.h>

#include <signorini/gmsh_child_process.h>
#include <signorini/gmsh_geometry.h>
#include <signorini/gmsh_mesh.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gmsh.h>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <sys/resource.h>
#include <unordered_map>

namespace Signorini
{
  namespace
  {
    /// Append the size and the elements of @p values to @p bytes.
    template <typename T>
    void
    put(std::string &bytes, const std::vector<T> &values)
    {
      const std::uint64_t n = values.size();
      bytes.append(reinterpret_cast<const char *>(&n), sizeof(n));
      bytes.append(reinterpret_cast<const char *>(values.data()),
                   n * sizeof(T));
    }

    /// Read from @p bytes at @p position what put() wrote.
    template <typename T>
    void
    get(const std::string &bytes, std::size_t &position, std::vector<T> &values)
    {
      std::uint64_t n = 0;
      if (position + sizeof(n) > bytes.size())
        throw std::runtime_error("truncated mesh from Gmsh");
      std::memcpy(&n, bytes.data() + position, sizeof(n));
      position += sizeof(n);
      if (n > (bytes.size() - position) / sizeof(T))
        throw std::runtime_error("truncated mesh from Gmsh");
      values.resize(n);
      std::memcpy(values.data(), bytes.data() + position, n * sizeof(T));
      position += n * sizeof(T);
    }
  } // namespace



  GmshModelMesh
  GmshModelMesh::of_current_model()
  {
    GmshModelMesh       mesh;
    std::vector<double> parametric;
    gmsh::model::mesh::getNodes(
      mesh.node_tags, mesh.coordinates, parametric, -1, -1, true, false);
    gmsh::vectorpair entities;
    gmsh::model::getEntities(entities);
    for (const auto &[dimension, tag] : entities)
      {
        std::vector<int> physical_tags;
        gmsh::model::getPhysicalGroupsForEntity(dimension, tag, physical_tags);
        std::vector<int>                      types;
        std::vector<std::vector<std::size_t>> element_tags, element_nodes;
        gmsh::model::mesh::getElements(
          types, element_tags, element_nodes, dimension, tag);
        for (unsigned int t = 0; t < types.size(); ++t)
          mesh.blocks.push_back({types[t],
                                 dimension,
                                 tag,
                                 physical_tags,
                                 std::move(element_tags[t]),
                                 std::move(element_nodes[t])});
      }
    return mesh;
  }



  std::string
  GmshModelMesh::to_bytes() const
  {
    std::string bytes;
    put(bytes, node_tags);
    put(bytes, coordinates);
    // (n_announced_elements: the Gmsh child sends 0, rank 0 the count it
    // scanned, to the ranks that check the same bytes)
    put(bytes, std::vector<std::uint64_t>{blocks.size(), n_announced_elements});
    for (const Block &block : blocks)
      {
        put(bytes,
            std::vector<int>{block.type,
                             block.entity_dimension,
                             block.entity_tag});
        put(bytes, block.physical_tags);
        put(bytes, block.element_tags);
        put(bytes, block.element_nodes);
      }
    return bytes;
  }



  GmshModelMesh
  GmshModelMesh::from_bytes(const std::string &bytes)
  {
    GmshModelMesh              mesh;
    std::size_t                position = 0;
    std::vector<std::uint64_t> n_blocks;
    get(bytes, position, mesh.node_tags);
    get(bytes, position, mesh.coordinates);
    get(bytes, position, n_blocks);
    if (n_blocks.size() != 2 ||
        mesh.coordinates.size() != 3 * mesh.node_tags.size())
      throw std::runtime_error("malformed mesh from Gmsh");
    mesh.n_announced_elements = n_blocks[1];
    for (std::uint64_t b = 0; b < n_blocks[0]; ++b)
      {
        std::vector<int> header;
        Block            block;
        get(bytes, position, header);
        if (header.size() != 3)
          throw std::runtime_error("malformed mesh from Gmsh");
        block.type             = header[0];
        block.entity_dimension = header[1];
        block.entity_tag       = header[2];
        get(bytes, position, block.physical_tags);
        get(bytes, position, block.element_tags);
        get(bytes, position, block.element_nodes);
        mesh.blocks.push_back(std::move(block));
      }
    if (position != bytes.size())
      throw std::runtime_error("malformed mesh from Gmsh");
    return mesh;
  }



  namespace
  {
    /// Relative tolerance on distances: nodes closer than this times the
    /// diameter of the mesh are one point, and a cell whose smallest height
    /// is below this times its longest edge is flat.
    constexpr double distance_tolerance = 1e-10;

    /// Relative tolerance on the measure of a cell, times the diameter of
    /// the mesh to the power dim: 1e-12 for areas, 1e-18 for volumes.
    constexpr double
    measure_tolerance(const unsigned int dim)
    {
      return dim == 2 ? 1e-12 : 1e-18;
    }

    /// The cells of a grid next to one, itself included, in dimension 2 or 3.
    template <int dim>
    constexpr unsigned int n_neighbours = dim == 2 ? 9 : 27;

    /// "(x, y)" or "(x, y, z)" for messages.
    std::string
    coordinates_text(const double *x, const unsigned int dim)
    {
      std::ostringstream out;
      out << "(" << x[0] << ", " << x[1];
      if (dim == 3)
        out << ", " << x[2];
      out << ")";
      return out.str();
    }

    /// What an element of Gmsh's @p type is, for a message about it.
    std::string
    element_type_text(const int type)
    {
      switch (type)
        {
          case 3:
            return "quadrilateral elements (type 3)";
          case 5:
            return "hexahedra (type 5)";
          case 6:
            return "prisms (type 6)";
          case 7:
            return "pyramids (type 7)";
          default:
            return "high-order elements (type " + std::to_string(type) + ")";
        }
    }

    /// Disjoint sets of cells (union-find with path halving).
    class UnionFind
    {
    public:
      explicit UnionFind(const unsigned int n)
        : parent(n)
      {
        for (unsigned int i = 0; i < n; ++i)
          parent[i] = i;
      }

      unsigned int
      root(unsigned int i)
      {
        while (parent[i] != i)
          i = parent[i] = parent[parent[i]];
        return i;
      }

      void
      join(const unsigned int i, const unsigned int j)
      {
        parent[root(i)] = root(j);
      }

    private:
      std::vector<unsigned int> parent;
    };

    /// A hash of a few vertex indices (a face) or grid coordinates.
    struct ArrayHash
    {
      template <typename T, std::size_t n>
      std::size_t
      operator()(const std::array<T, n> &v) const
      {
        std::uint64_t h = 0x9E3779B97F4A7C15ULL;
        for (const T x : v)
          h = (h ^ static_cast<std::uint64_t>(x)) * 0xC2B2AE3D27D4EB4FULL;
        return h ^ (h >> 29);
      }
    };

    /// An element of the model: its tag, physical tag (0: none) and nodes
    /// (indices into the model's nodes).
    struct Element
    {
      std::size_t                 tag;
      int                         physical;
      std::array<unsigned int, 4> nodes;
    };

    /**
     * The checks of checked_mesh(), one step per function. The nodes are
     * the model's; "vertices" are the nodes the cells use, numbered in the
     * model's order.
     */
    template <int dim>
    class MeshChecker
    {
    public:
      MeshChecker(const GmshModelMesh &model, const std::string &name);

      GmshMesh<dim>
      run();

    private:
      /// A face: its vertices, sorted.
      using FaceKey = std::array<unsigned int, dim>;

      /// The cells on either side of a face (-1: none).
      struct FaceCells
      {
        std::array<int, 2> side = {{-1, -1}};
      };

      const GmshModelMesh &model;
      const std::string    name;
      const std::string    cell_name, cells_name, face_element_name;

      std::vector<Element>                              cells, face_elements;
      std::vector<unsigned int>                         vertex_of_node;
      std::vector<unsigned int>                         node_of_vertex;
      std::array<double, 3>                             low, high;
      double                                            diameter = 0;
      std::unordered_map<FaceKey, FaceCells, ArrayHash> faces;

      [[noreturn]] void
      fail(const std::string &what) const
      {
        throw InputError("<" + name + ">: " + what);
      }

      const double *
      x(const unsigned int node) const
      {
        return &model.coordinates[3 * node];
      }

      std::string
      node_text(const unsigned int node) const
      {
        return std::to_string(model.node_tags[node]) + " " +
               coordinates_text(x(node), dim);
      }

      void
      collect_elements();

      void
      check_nodes();

      void
      check_coincident_nodes() const;

      void
      orient_cells();

      void
      collect_faces();

      void
      check_hanging_nodes() const;

      void
      check_one_body() const;

      void
      add_boundary_ids(GmshMesh<dim> &mesh) const;
    };



    template <int dim>
    MeshChecker<dim>::MeshChecker(const GmshModelMesh &model,
                                  const std::string   &name)
      : model(model)
      , name(name)
      , cell_name(dim == 2 ? "triangle" : "tetrahedron")
      , cells_name(dim == 2 ? "triangles" : "tetrahedra")
      , face_element_name(dim == 2 ? "line element" : "triangle element")
    {}



    /// The cells (triangles, tetrahedra) and the elements of their faces,
    /// refusing any other element but points and (in 3D) lines.
    template <int dim>
    void
    MeshChecker<dim>::collect_elements()
    {
      std::unordered_map<std::size_t, unsigned int> node_index;
      node_index.reserve(model.node_tags.size());
      for (unsigned int n = 0; n < model.node_tags.size(); ++n)
        node_index.emplace(model.node_tags[n], n);
      const int   cell_type = dim == 2 ? 2 : 4, face_type = dim == 2 ? 1 : 2;
      const char *entity_names[] = {"point", "curve", "surface", "volume"};
      for (const GmshModelMesh::Block &block : model.blocks)
        {
          if (block.type == 15 || (dim == 3 && block.type == 1))
            continue;
          if (dim == 2 && block.type == 4)
            fail("tetrahedra (type 4) are 3D elements: signorini reads them "
                 "with Dimension = 3");
          if (block.type != cell_type && block.type != face_type)
            fail(element_type_text(block.type) +
                 " are not supported: signorini needs " +
                 (dim == 2 ? "3-node triangles" : "4-node tetrahedra"));
          if (block.physical_tags.size() > 1)
            {
              std::string tags;
              for (std::size_t i = 0; i < block.physical_tags.size(); ++i)
                tags += (i == 0                              ? "" :
                         i + 1 == block.physical_tags.size() ? " and " :
                                                               ", ") +
                        std::to_string(block.physical_tags[i]);
              fail(std::string(
                     entity_names[std::clamp(block.entity_dimension, 0, 3)]) +
                   " " + std::to_string(block.entity_tag) + " belongs to " +
                   std::to_string(block.physical_tags.size()) +
                   " physical groups (tags " + tags +
                   "), so that its elements have no single id (an msh 2 file "
                   "may tag the elements of one entity differently): give "
                   "each physical group entities of its own");
            }
          const int physical =
            block.physical_tags.empty() ? 0 : block.physical_tags[0];
          if (physical < 0)
            fail("physical tag " + std::to_string(physical) +
                 " is negative: ids are numbers from 0 on");
          const unsigned int n_nodes = block.type == cell_type ? dim + 1 : dim;
          if (block.element_nodes.size() != n_nodes * block.element_tags.size())
            fail("Gmsh gives elements of type " + std::to_string(block.type) +
                 " an unexpected number of nodes");
          auto &list = block.type == cell_type ? cells : face_elements;
          for (unsigned int e = 0; e < block.element_tags.size(); ++e)
            {
              Element element{block.element_tags[e], physical, {}};
              for (unsigned int k = 0; k < n_nodes; ++k)
                {
                  const auto p =
                    node_index.find(block.element_nodes[n_nodes * e + k]);
                  if (p == node_index.end())
                    fail("element " + std::to_string(element.tag) +
                         " refers to node " +
                         std::to_string(block.element_nodes[n_nodes * e + k]) +
                         ", which is not in the mesh");
                  element.nodes[k] = p->second;
                }
              list.push_back(element);
            }
        }
      std::size_t n_read = 0;
      for (const GmshModelMesh::Block &block : model.blocks)
        n_read += block.element_tags.size();
      if (n_read < model.n_announced_elements)
        fail("$Elements announces " +
             std::to_string(model.n_announced_elements) +
             " elements, Gmsh read " + std::to_string(n_read) +
             " (a wrong count of element blocks, or a truncated file?)");
      if (cells.empty())
        fail(dim == 2 ? "contains no triangles: signorini needs a 2D mesh of "
                        "3-node triangles" :
                        "contains no tetrahedra: with Dimension = 3 "
                        "signorini needs a 3D mesh of 4-node tetrahedra");
    }



    /// The vertices (the nodes the cells use), the range of their
    /// coordinates, the diameter of the mesh, a flat mesh in 2D.
    template <int dim>
    void
    MeshChecker<dim>::check_nodes()
    {
      const unsigned int unused = static_cast<unsigned int>(-1);
      vertex_of_node.assign(model.node_tags.size(), unused);
      for (const Element &cell : cells)
        for (unsigned int k = 0; k <= dim; ++k)
          vertex_of_node[cell.nodes[k]] = 0;
      for (unsigned int n = 0; n < vertex_of_node.size(); ++n)
        if (vertex_of_node[n] != unused)
          {
            vertex_of_node[n] = node_of_vertex.size();
            node_of_vertex.push_back(n);
            for (unsigned int d = 0; d < 3; ++d)
              if (!std::isfinite(x(n)[d]))
                fail("node " + std::to_string(model.node_tags[n]) +
                     " has a coordinate that is not a finite number");
          }

      const unsigned int first = node_of_vertex[0];
      for (unsigned int d = 0; d < 3; ++d)
        low[d] = high[d] = x(first)[d];
      for (const unsigned int n : node_of_vertex)
        for (unsigned int d = 0; d < 3; ++d)
          {
            low[d]  = std::min(low[d], x(n)[d]);
            high[d] = std::max(high[d], x(n)[d]);
          }
      diameter =
        std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
      if (diameter == 0.)
        fail("all nodes of the " + cells_name + " are at the point " +
             coordinates_text(low.data(), dim));
      // extreme scales: measures and squared lengths would underflow or
      // overflow in the assembly and the checks
      // (in 3D products of volumes already leave the range: the cube 1e-65
      // or 1e60 across gave eps = 77 % instead of 27.5 %, 1e-60 and 1e60
      // the right one)
      const double largest_diameter = (dim == 3) ? 1e50 : 1e100;
      if (!std::isfinite(diameter) || diameter > largest_diameter ||
          diameter < 1. / largest_diameter)
        {
          std::ostringstream message;
          message << "the mesh is " << diameter << " across, outside [1e-"
                  << (dim == 3 ? 50 : 100) << ", 1e" << (dim == 3 ? 50 : 100)
                  << "]: change the units";
          fail(message.str());
        }
      for (const unsigned int n : node_of_vertex)
        for (unsigned int d = 0; d < 3; ++d)
          if (std::abs(x(n)[d]) > 1e150)
            {
              std::ostringstream message;
              message << "node " << model.node_tags[n] << " has the coordinate "
                      << x(n)[d]
                      << ", beyond 1e150 in absolute value (its square "
                         "overflows): change the units or the origin";
              fail(message.str());
            }
      // far from the origin for its size, the coordinates are resolved to
      // a fraction of the mesh (a unit square 1e15 from the origin: to 0.125,
      // its nodes moved by up to a third of its cells)
      // (in 2D of x and y only: a plane z = const plays no part)
      double farthest = 0.;
      for (unsigned int d = 0; d < dim; ++d)
        farthest = std::max({farthest, std::abs(low[d]), std::abs(high[d])});
      const double resolution =
        farthest * std::numeric_limits<double>::epsilon();
      if (resolution > 1e-5 * diameter)
        {
          std::ostringstream message;
          message.precision(3);
          message << "the mesh is " << diameter
                  << " across but has a coordinate of " << farthest
                  << ": double precision resolves its coordinates only to "
                  << resolution
                  << " (double precision), which moves its nodes; move the "
                     "origin into or near the mesh";
          fail(message.str());
        }
      if (dim == 2)
        for (const unsigned int n : node_of_vertex)
          if (std::abs(x(n)[2] - x(first)[2]) > distance_tolerance * diameter)
            {
              std::ostringstream message;
              message << "node " << model.node_tags[n] << " has z = " << x(n)[2]
                      << " while node " << model.node_tags[first]
                      << " has z = " << x(first)[2]
                      << ": signorini needs a flat mesh in a plane z = const "
                         "(a 3D mesh needs Dimension = 3)";
              fail(message.str());
            }
    }



    /// No two vertices at the same point: the points are hashed into cells
    /// of the size of the tolerance, and neighbouring cells compared.
    template <int dim>
    void
    MeshChecker<dim>::check_coincident_nodes() const
    {
      const double tolerance = distance_tolerance * diameter;
      using GridCell         = std::array<long long, dim>;
      const auto grid_cell   = [&](const unsigned int n) {
        GridCell cell;
        for (unsigned int d = 0; d < dim; ++d)
          cell[d] =
            static_cast<long long>(std::floor((x(n)[d] - low[d]) / tolerance));
        return cell;
      };
      std::unordered_multimap<GridCell, unsigned int, ArrayHash> grid;
      grid.reserve(node_of_vertex.size());
      for (const unsigned int n : node_of_vertex)
        {
          const GridCell centre = grid_cell(n);
          for (unsigned int neighbour = 0; neighbour < n_neighbours<dim>;
               ++neighbour)
            {
              GridCell     cell = centre;
              unsigned int code = neighbour;
              for (unsigned int d = 0; d < dim; ++d, code /= 3)
                cell[d] += static_cast<long long>(code % 3) - 1;
              const auto range = grid.equal_range(cell);
              for (auto p = range.first; p != range.second; ++p)
                {
                  double distance = 0;
                  for (unsigned int d = 0; d < dim; ++d)
                    distance = std::hypot(distance, x(n)[d] - x(p->second)[d]);
                  if (distance <= tolerance)
                    fail("nodes " + std::to_string(model.node_tags[p->second]) +
                         " and " + std::to_string(model.node_tags[n]) +
                         " are at the same point " +
                         coordinates_text(x(n), dim) +
                         ": the mesh would have a crack or a collapsed cell "
                         "there; merge them");
                }
            }
          grid.emplace(centre, n);
        }
    }



    /// No cell of (nearly) zero measure; the others oriented as deal.II's
    /// reference cell (positive measure), by swapping two nodes.
    template <int dim>
    void
    MeshChecker<dim>::orient_cells()
    {
      for (Element &cell : cells)
        {
          // the edges from node 0, in units of the diameter (no overflow)
          Tensor<2, dim> edges;
          double         longest = 0;
          for (unsigned int a = 0; a <= dim; ++a)
            for (unsigned int b = a + 1; b <= dim; ++b)
              {
                Tensor<1, dim> edge;
                for (unsigned int d = 0; d < dim; ++d)
                  edge[d] =
                    (x(cell.nodes[b])[d] - x(cell.nodes[a])[d]) / diameter;
                longest = std::max(longest, edge.norm());
                if (a == 0)
                  edges[b - 1] = edge;
              }
          const double factorial = dim == 2 ? 2. : 6.;
          const double measure   = determinant(edges) / factorial;
          if (std::abs(measure) <= measure_tolerance(dim) ||
              std::abs(measure) * factorial <=
                distance_tolerance * std::pow(longest, dim))
            {
              std::ostringstream message;
              message << cell_name << " " << cell.tag << " has "
                      << (measure == 0. ? "zero " : "nearly zero ")
                      << (dim == 2 ? "area" : "volume");
              if (measure != 0.)
                message << " " << std::abs(measure) * std::pow(diameter, dim);
              message << ": its nodes";
              for (unsigned int k = 0; k <= dim; ++k)
                message << (k > 0 ? ", " : " ") << node_text(cell.nodes[k]);
              message << " are " << (measure == 0. ? "" : "nearly ")
                      << (dim == 2 ? "collinear" : "coplanar");
              fail(message.str());
            }
          if (measure < 0)
            std::swap(cell.nodes[1], cell.nodes[2]);
        }
    }



    /// The faces of the cells, each with the cell on either side: a face
    /// with two cells on one side is a folded or repeated cell. The face
    /// opposite node k of a positively oriented cell, its nodes in
    /// increasing order, is outward for even k; its side is that parity
    /// times the parity of the permutation that sorts its vertices.
    template <int dim>
    void
    MeshChecker<dim>::collect_faces()
    {
      faces.reserve((dim + 1) * cells.size() / 2 + 16);
      for (unsigned int c = 0; c < cells.size(); ++c)
        for (unsigned int k = 0; k <= dim; ++k)
          {
            FaceKey      key;
            unsigned int i = 0;
            for (unsigned int j = 0; j <= dim; ++j)
              if (j != k)
                key[i++] = vertex_of_node[cells[c].nodes[j]];
            unsigned int swaps = k;
            for (unsigned int a = 0; a < dim; ++a)
              for (unsigned int b = 0; b + 1 < dim - a; ++b)
                if (key[b] > key[b + 1])
                  {
                    std::swap(key[b], key[b + 1]);
                    ++swaps;
                  }
            FaceCells &face = faces[key];
            int       &side = face.side[swaps % 2];
            if (side >= 0)
              {
                std::string between;
                for (unsigned int v = 0; v < dim; ++v)
                  between +=
                    (v == 0       ? "" :
                     v + 1 == dim ? " and " :
                                    ", ") +
                    std::to_string(model.node_tags[node_of_vertex[key[v]]]);
                fail(cells_name + " " + std::to_string(cells[side].tag) +
                     " and " + std::to_string(cells[c].tag) +
                     " overlap: they lie on the same side of their " +
                     (dim == 2 ? "edge" : "face") + " between nodes " +
                     between + " (a repeated or folded " + cell_name + ", or " +
                     (dim == 2 ? "a surface" : "a volume") +
                     " in two physical groups?)");
              }
            side = c;
          }
    }



    /// No node on a boundary face (one cell only) without being one of its
    /// corners (a T-junction: the mesh is not conforming, a crack the solver
    /// would not see). The boundary faces go into hash grids, one per size
    /// class (cells of 2^l times the smallest face size, a face in the
    /// class of its longest edge, so that a graded mesh puts few faces into
    /// any cell), entered in every grid cell their box, widened by the
    /// tolerance, meets; each vertex is compared with the faces of its own
    /// grid cell in each class (one look-up per class, not one per
    /// neighbouring cell: most vertices meet an empty cell).
    template <int dim>
    void
    MeshChecker<dim>::check_hanging_nodes() const
    {
      const auto point = [&](const unsigned int v) {
        Point<dim> p;
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = x(node_of_vertex[v])[d];
        return p;
      };
      std::vector<FaceKey> boundary_faces;
      std::vector<double>  face_size;
      for (const auto &[key, face] : faces)
        if (face.side[0] < 0 || face.side[1] < 0)
          {
            double longest = 0;
            for (unsigned int a = 0; a < dim; ++a)
              for (unsigned int b = a + 1; b < dim; ++b)
                longest =
                  std::max(longest, point(key[a]).distance(point(key[b])));
            boundary_faces.push_back(key);
            face_size.push_back(longest);
          }
      if (boundary_faces.empty())
        return;
      const double smallest =
        *std::min_element(face_size.begin(), face_size.end());
      const double tolerance = distance_tolerance * diameter;
      using GridCell = std::array<long long, dim + 1>; // level, then indices
      const auto index =
        [&](const double coordinate, const unsigned int d, const int level) {
          return static_cast<long long>(
            std::floor((coordinate - low[d]) / std::ldexp(smallest, level)));
        };
      std::unordered_multimap<GridCell, unsigned int, ArrayHash> grid;
      int                                                        n_levels = 0;
      for (unsigned int f = 0; f < boundary_faces.size(); ++f)
        {
          const int level =
            std::max(0,
                     static_cast<int>(
                       std::ceil(std::log2(face_size[f] / smallest) - 1e-12)));
          n_levels = std::max(n_levels, level + 1);
          std::array<long long, dim> first, last;
          for (unsigned int d = 0; d < dim; ++d)
            {
              double a = point(boundary_faces[f][0])[d], b = a;
              for (unsigned int k = 1; k < dim; ++k)
                {
                  a = std::min(a, point(boundary_faces[f][k])[d]);
                  b = std::max(b, point(boundary_faces[f][k])[d]);
                }
              first[d] = index(a - tolerance, d, level);
              last[d]  = index(b + tolerance, d, level);
            }
          GridCell cell;
          cell[0] = level;
          for (cell[1] = first[0]; cell[1] <= last[0]; ++cell[1])
            for (cell[2] = first[1]; cell[2] <= last[1]; ++cell[2])
              {
                if constexpr (dim == 2)
                  grid.emplace(cell, f);
                else
                  for (cell[3] = first[2]; cell[3] <= last[2]; ++cell[3])
                    grid.emplace(cell, f);
              }
        }

      for (unsigned int v = 0; v < node_of_vertex.size(); ++v)
        for (int level = 0; level < n_levels; ++level)
          {
            const Point<dim> p = point(v);
            GridCell         cell;
            cell[0] = level;
            for (unsigned int d = 0; d < dim; ++d)
              cell[d + 1] = index(p[d], d, level);
            const auto range = grid.equal_range(cell);
            for (auto q = range.first; q != range.second; ++q)
              {
                const FaceKey &face = boundary_faces[q->second];
                if (std::find(face.begin(), face.end(), v) != face.end())
                  continue;
                // p's projection onto the face's plane (line), in the
                // barycentric coordinates of the face: the Gram system
                const Point<dim>                    a = point(face[0]);
                Tensor<1, dim - 1>                  rhs;
                Tensor<2, dim - 1>                  gram;
                std::array<Tensor<1, dim>, dim - 1> edges;
                for (unsigned int i = 0; i + 1 < dim; ++i)
                  edges[i] = point(face[i + 1]) - a;
                for (unsigned int i = 0; i + 1 < dim; ++i)
                  {
                    rhs[i] = edges[i] * (p - a);
                    for (unsigned int j = 0; j + 1 < dim; ++j)
                      gram[i][j] = edges[i] * edges[j];
                  }
                const Tensor<1, dim - 1> lambda = invert(gram) * rhs;
                Tensor<1, dim>           offset = p - a;
                double                   sum    = 0;
                bool                     inside = true;
                for (unsigned int i = 0; i + 1 < dim; ++i)
                  {
                    offset -= lambda[i] * edges[i];
                    sum += lambda[i];
                    inside = inside && lambda[i] >= -distance_tolerance;
                  }
                if (inside && sum <= 1 + distance_tolerance &&
                    offset.norm() <= tolerance)
                  {
                    std::string corners;
                    for (unsigned int k = 0; k < dim; ++k)
                      corners += (k == 0       ? "" :
                                  k + 1 == dim ? " and " :
                                                 ", ") +
                                 std::to_string(
                                   model.node_tags[node_of_vertex[face[k]]]);
                    fail("node " + node_text(node_of_vertex[v]) +
                         " lies on the boundary " +
                         (dim == 2 ? "edge" : "face") + " between nodes " +
                         corners + " without being a corner of its " +
                         cell_name +
                         " (a hanging node): the mesh is not conforming "
                         "there");
                  }
              }
          }
    }



    /// One body: the cells connected through their shared faces (a second
    /// part would float free in the solver).
    template <int dim>
    void
    MeshChecker<dim>::check_one_body() const
    {
      UnionFind parts(cells.size());
      for (const auto &face : faces)
        if (face.second.side[0] >= 0 && face.second.side[1] >= 0)
          parts.join(face.second.side[0], face.second.side[1]);
      unsigned int n_parts = 0, second = 0;
      for (unsigned int c = 0; c < cells.size(); ++c)
        if (parts.root(c) == c)
          ++n_parts;
      if (n_parts < 2)
        return;
      while (parts.root(second) == parts.root(0))
        ++second;
      std::array<double, 3> centre = {{0, 0, 0}};
      for (unsigned int k = 0; k <= dim; ++k)
        for (unsigned int d = 0; d < dim; ++d)
          centre[d] += x(cells[second].nodes[k])[d] / (dim + 1);
      fail("has " + std::to_string(n_parts) +
           " separate parts (one body is modelled); part 2 contains the " +
           cell_name + " " + std::to_string(cells[second].tag) + " at " +
           coordinates_text(centre.data(), dim));
    }



    /// The boundary ids: a face element's physical tag goes to the boundary
    /// face it lies on (deal.II refuses ids on interior faces, and an
    /// element away from the cells would silently lose its id).
    template <int dim>
    void
    MeshChecker<dim>::add_boundary_ids(GmshMesh<dim> &mesh) const
    {
      std::map<FaceKey, const Element *> tagged;
      const unsigned int                 unused = static_cast<unsigned int>(-1);
      for (const Element &element : face_elements)
        {
          if (element.physical == 0)
            continue; // no id: nothing to pass on
          FaceKey key;
          for (unsigned int k = 0; k < dim; ++k)
            key[k] = vertex_of_node[element.nodes[k]];
          std::sort(key.begin(), key.end());
          std::string nodes;
          for (unsigned int k = 0; k < dim; ++k)
            nodes += (k == 0       ? "" :
                      k + 1 == dim ? " and " :
                                     ", ") +
                     std::to_string(model.node_tags[element.nodes[k]]);
          const std::string what =
            face_element_name + " " + std::to_string(element.tag) +
            " (physical tag " + std::to_string(element.physical) + ", nodes " +
            nodes + ")";
          const auto face =
            key[dim - 1] == unused ? faces.end() : faces.find(key);
          if (face == faces.end())
            fail(what + " is not " + (dim == 2 ? "an edge" : "a face") +
                 " of any " + cell_name + ", so its boundary id would be lost");
          if (face->second.side[0] >= 0 && face->second.side[1] >= 0)
            fail(what + " lies inside the mesh, between " + cells_name + " " +
                 std::to_string(cells[face->second.side[0]].tag) + " and " +
                 std::to_string(cells[face->second.side[1]].tag) +
                 ": only boundary " + (dim == 2 ? "edges" : "faces") +
                 " take a boundary id");
          const auto other = tagged.emplace(key, &element);
          if (!other.second)
            {
              if (other.first->second->physical != element.physical)
                fail(what + " and " + face_element_name + " " +
                     std::to_string(other.first->second->tag) +
                     " (physical tag " +
                     std::to_string(other.first->second->physical) +
                     ") are the same " + (dim == 2 ? "edge" : "face") +
                     " with two boundary ids (a " +
                     (dim == 2 ? "curve" : "surface") +
                     " in two physical groups?)");
              continue;
            }
          CellData<dim - 1> boundary_face(dim);
          for (unsigned int k = 0; k < dim; ++k)
            boundary_face.vertices[k] = vertex_of_node[element.nodes[k]];
          boundary_face.boundary_id =
            static_cast<types::boundary_id>(element.physical);
          if constexpr (dim == 2)
            mesh.boundary.boundary_lines.push_back(boundary_face);
          else
            mesh.boundary.boundary_quads.push_back(boundary_face);
        }
    }



    template <int dim>
    GmshMesh<dim>
    MeshChecker<dim>::run()
    {
      collect_elements();
      check_nodes();
      check_coincident_nodes();
      orient_cells();
      collect_faces();
      check_hanging_nodes();
      check_one_body();

      GmshMesh<dim> mesh;
      add_boundary_ids(mesh);
      for (const unsigned int n : node_of_vertex)
        {
          Point<dim> p;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = x(n)[d];
          mesh.vertices.push_back(p);
        }
      for (const Element &cell : cells)
        {
          CellData<dim> data(dim + 1);
          for (unsigned int k = 0; k <= dim; ++k)
            data.vertices[k] = vertex_of_node[cell.nodes[k]];
          data.material_id = static_cast<types::material_id>(cell.physical);
          mesh.cells.push_back(data);
        }
      return mesh;
    }



    /// Read the ASCII msh file @p path before Gmsh does. Throw if it holds
    /// a tag that Gmsh would read into a 32-bit int (it wraps silently:
    /// 2^32 + 2 becomes the id 2): the physical and entity tags of msh 4
    /// ($Entities), every number of the element lines of msh 2, the tags of
    /// $PhysicalNames. Return the number of elements its $Elements section
    /// announces (0 if the file is binary or has no such header): Gmsh
    /// stops at the announced number of element blocks, so that a wrong one
    /// silently drops elements.
    std::size_t
    scan_ascii_msh(const std::string &path)
    {
      std::ifstream in(path);
      std::string   line, section;
      double        version   = 0;
      std::size_t   announced = 0;
      const auto    largest =
        static_cast<long double>(std::numeric_limits<int>::max());
      const auto refuse = [&](const std::string &what, const std::string &tag) {
        throw std::runtime_error(
          section + ": " + what + " " + tag +
          " is beyond 2147483647, the largest tag Gmsh reads (a 32-bit "
          "integer, which would silently wrap it to another id)");
      };
      // an integer token beyond int, as a tag (up to 9 digits it fits)
      const auto check = [&](const std::string &token,
                             const std::string &what) {
        if (token.size() > 9 &&
            token.find_first_not_of("+-0123456789") == std::string::npos &&
            std::abs(std::strtold(token.c_str(), nullptr)) > largest)
          refuse(what, token);
      };
      while (std::getline(in, line))
        {
          if (!line.empty() && line.back() == '\r')
            line.pop_back();
          if (line.rfind("$MeshFormat", 0) == 0)
            {
              int file_type = 0;
              if (!(in >> version >> file_type) || file_type != 0)
                return 0; // (binary: the tags are ints already)
              continue;
            }
          if (line.rfind("$End", 0) == 0)
            {
              section.clear();
              continue;
            }
          if (line.rfind("$", 0) == 0)
            {
              section = line;
              if (section == "$Elements")
                {
                  // msh 2: the count; msh 4: the blocks, then the count
                  std::getline(in, line);
                  std::istringstream header(line);
                  std::size_t        first = 0, second = 0;
                  if (header >> first)
                    announced = version < 4        ? first :
                                (header >> second) ? second :
                                                     0;
                  std::istringstream numbers(line);
                  for (std::string number; version < 4 && numbers >> number;)
                    check(number, "number");
                }
              if (section == "$Entities" && version >= 4)
                {
                  // points: tag x y z n physical...; curves, surfaces,
                  // volumes: tag 6 bounds n physical... n bounding...
                  std::array<std::size_t, 4> count{};
                  std::getline(in, line);
                  std::istringstream header(line);
                  for (auto &c : count)
                    header >> c;
                  for (unsigned int d = 0; d < 4; ++d)
                    for (std::size_t e = 0; e < count[d]; ++e)
                      {
                        if (!std::getline(in, line))
                          return announced; // (Gmsh reports the truncation)
                        std::istringstream       entity(line);
                        std::string              token;
                        std::vector<std::string> tokens;
                        while (entity >> token)
                          tokens.push_back(token);
                        const std::size_t n_bounds = d == 0 ? 3 : 6;
                        if (tokens.size() < n_bounds + 2)
                          return announced;
                        check(tokens[0], "entity tag");
                        const std::size_t n_physical =
                          std::strtoul(tokens[n_bounds + 1].c_str(),
                                       nullptr,
                                       10);
                        for (std::size_t k = 0;
                             k < n_physical && n_bounds + 2 + k < tokens.size();
                             ++k)
                          check(tokens[n_bounds + 2 + k], "physical tag");
                      }
                }
              continue;
            }
          std::istringstream tokens(line);
          std::string        token;
          if (section == "$PhysicalNames")
            {
              std::string dimension;
              if (tokens >> dimension >> token)
                check(token, "physical tag");
            }
          else if (section == "$Elements" && version < 4)
            while (tokens >> token)
              check(token, "number");
        }
      return announced;
    }



    /// In a child: the mesh of the msh file @p path, as bytes.
    std::string
    read_in_child(const std::string &path)
    {
      // A wrong count in a corrupted file can make Gmsh allocate without
      // bound: the child gets at most 4 GB and 100 times the file more
      // address space than it has now.
      std::ifstream statm("/proc/self/statm");
      std::size_t   pages = 0;
      if (statm >> pages)
        {
          const double limit =
            pages * static_cast<double>(::sysconf(_SC_PAGESIZE)) + 4e9 +
            100. * std::filesystem::file_size(path);
          const rlimit address_space = {static_cast<rlim_t>(limit),
                                        static_cast<rlim_t>(limit)};
          ::setrlimit(RLIMIT_AS, &address_space);
        }
      gmsh::initialize(0, nullptr, false);
      gmsh::option::setNumber("General.Terminal", 0);
      gmsh::option::setNumber("General.Verbosity", 1);
      gmsh::logger::start();
      try
        {
          gmsh::open(path);
        }
      catch (const std::bad_alloc &)
        {
          throw std::runtime_error("Gmsh ran out of memory reading it (a "
                                   "corrupted count?)");
        }
      catch (...)
        {
          // Gmsh 4.8 throws no message: it is in the log
          std::string error;
          gmsh::logger::getLastError(error);
          throw std::runtime_error(error.empty() ? "Gmsh cannot read it" :
                                                   error);
        }
      const GmshModelMesh mesh = GmshModelMesh::of_current_model();
      gmsh::finalize();
      return mesh.to_bytes();
    }



    /// The model mesh of the file @p path (on this rank; Gmsh in a child).
    GmshModelMesh
    model_mesh_of(const std::string &path,
                  const unsigned int dim,
                  const double       max_cells)
    {
      const std::filesystem::path        file(path);
      const bool                         geometry = file.extension() == ".geo";
      const std::string                  kind = geometry ? "geometry" : "mesh";
      std::error_code                    error;
      const std::filesystem::file_status status =
        std::filesystem::status(file, error);
      if (!std::filesystem::exists(status) || !std::ifstream(path))
        throw InputError("cannot open " + kind + " file <" + path + ">");
      if (std::filesystem::is_directory(status))
        throw InputError("cannot read " + kind + " file <" + path +
                         ">: it is a directory");
      if (!std::filesystem::is_regular_file(status))
        throw InputError("cannot read " + kind + " file <" + path +
                         ">: it is not a regular file");
      if (std::filesystem::file_size(file, error) == 0)
        throw InputError(kind + " file <" + path + "> is empty");
      if (geometry)
        return mesh_geometry(path, dim, max_cells);
      std::size_t announced = 0;
      try
        {
          announced = scan_ascii_msh(path);
        }
      catch (const std::runtime_error &exc)
        {
          throw InputError("cannot read mesh file <" + path +
                           ">: " + exc.what());
        }
      try
        {
          GmshModelMesh mesh = GmshModelMesh::from_bytes(
            run_in_gmsh_child([&]() { return read_in_child(path); },
                              "reading " + path));
          mesh.n_announced_elements = announced;
          return mesh;
        }
      catch (const std::exception &exc)
        {
          std::string reason = one_line_message(exc.what());
          if (reason.rfind("Gmsh failed: ", 0) == 0)
            reason = "Gmsh: " + reason.substr(13);
          throw InputError("cannot read mesh file <" + path + ">: " + reason);
        }
    }
  } // namespace



  template <int dim>
  GmshMesh<dim>
  checked_mesh(const GmshModelMesh &model, const std::string &name)
  {
    return MeshChecker<dim>(model, name).run();
  }



  template <int dim>
  GmshMesh<dim>
  read_gmsh_mesh(const std::string &path, const double max_cells)
  {
    // rank 0 reads (Gmsh meshes a .geo once), every rank checks the same
    // bytes and gets the same mesh or the same error (also without MPI)
    std::string bytes;
    try
      {
        bytes = run_on_rank_0(
          [&]() { return model_mesh_of(path, dim, max_cells).to_bytes(); });
      }
    catch (const std::runtime_error &exc)
      {
        throw InputError(exc.what());
      }
    const bool geometry = std::filesystem::path(path).extension() == ".geo";
    return checked_mesh<dim>(GmshModelMesh::from_bytes(bytes),
                             geometry ? path + " as meshed by Gmsh" : path);
  }



  template GmshMesh<2>
  checked_mesh<2>(const GmshModelMesh &, const std::string &);
  template GmshMesh<3>
  checked_mesh<3>(const GmshModelMesh &, const std::string &);
  template GmshMesh<2>
  read_gmsh_mesh<2>(const std::string &, const double);
  template GmshMesh<3>
  read_gmsh_mesh<3>(const std::string &, const double);
} // namespace Signorini
