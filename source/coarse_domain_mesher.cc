#include <deal.II/base/mpi.h>

#include <deal.II/numerics/rtree.h>

#include <signorini/coarse_domain_mesher.h>
#include <signorini/gmsh_child_process.h>
#include <signorini/gmsh_mesh.h>

#include <algorithm>
#include <cmath>
#include <gmsh.h>
#include <map>
#include <numeric>
#include <stdexcept>

namespace Signorini
{
  namespace
  {
    /// (the signed area of a closed polygon)
    double
    signed_area(const std::vector<Point<2>> &polygon)
    {
      double area = 0.;
      for (unsigned int i = 0; i < polygon.size(); ++i)
        {
          const Point<2> &a = polygon[i];
          const Point<2> &b = polygon[(i + 1) % polygon.size()];
          area += a[0] * b[1] - a[1] * b[0];
        }
      return area / 2.;
    }
  } // namespace



  template <int dim>
  CoarseDomainMesher<dim>::CoarseDomainMesher(
    const Triangulation<dim>  &fine,
    const std::vector<double> &relative_sizes)
  {
    double                               total_edge_length = 0., n_edges = 0.;
    std::map<unsigned int, unsigned int> boundary_index;
    for (const auto &cell : fine.active_cell_iterators())
      {
        for (unsigned int l = 0; l < cell->n_lines(); ++l)
          {
            total_edge_length += cell->line(l)->diameter();
            n_edges += 1.;
          }
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              BoundaryFace boundary_face;
              for (unsigned int v = 0; v < dim; ++v)
                {
                  const auto [entry, added] =
                    boundary_index.emplace(face->vertex_index(v),
                                           boundary_vertices.size());
                  if (added)
                    boundary_vertices.push_back(face->vertex(v));
                  boundary_face.vertices[v] = entry->second;
                }
              boundary_face.centre = face->center();
              boundary_face.id     = face->boundary_id();
              boundary_faces.push_back(boundary_face);
            }
      }
    // (the mean length of the cells' edges: Gmsh's sense of a size)
    const double fine_size = total_edge_length / n_edges;
    for (const double relative_size : relative_sizes)
      sizes.push_back(fine_size * relative_size);
  }



  template <>
  void
  CoarseDomainMesher<2>::add_curves_geometry() const
  {
    // the two boundary edges at each boundary vertex
    const unsigned int n_vertices = boundary_vertices.size();
    std::vector<std::vector<unsigned int>> edges_at(n_vertices);
    for (unsigned int f = 0; f < boundary_faces.size(); ++f)
      for (const unsigned int v : boundary_faces[f].vertices)
        edges_at[v].push_back(f);
    const auto other_vertex = [&](const unsigned int f, const unsigned int v) {
      const auto &vertices = boundary_faces[f].vertices;
      return vertices[0] == v ? vertices[1] : vertices[0];
    };
    const auto other_edge = [&](const unsigned int v, const unsigned int f) {
      return edges_at[v][0] == f ? edges_at[v][1] : edges_at[v][0];
    };
    std::vector<bool> corner(n_vertices, false);
    for (unsigned int v = 0; v < n_vertices; ++v)
      {
        if (edges_at[v].size() != 2)
          throw std::runtime_error("the boundary is not a set of closed "
                                   "curves (a vertex on " +
                                   std::to_string(edges_at[v].size()) +
                                   " boundary edges)");
        const unsigned int e0 = edges_at[v][0], e1 = edges_at[v][1];
        const Tensor<1, 2> a =
          boundary_vertices[v] - boundary_vertices[other_vertex(e0, v)];
        const Tensor<1, 2> b =
          boundary_vertices[other_vertex(e1, v)] - boundary_vertices[v];
        const double cosine = a * b / (a.norm() * b.norm());
        corner[v]           = boundary_faces[e0].id != boundary_faces[e1].id ||
                    cosine < std::cos(M_PI / 6.);
      }

    // Each closed boundary curve, in order; at least three corners on it,
    // so that no two curves join the same two corners.
    std::vector<bool> visited(n_vertices, false);
    for (unsigned int start = 0; start < n_vertices; ++start)
      if (!visited[start])
        {
          std::vector<unsigned int> loop;
          unsigned int              v = start, edge = edges_at[start][0];
          do
            {
              visited[v] = true;
              loop.push_back(v);
              v    = other_vertex(edge, v);
              edge = other_edge(v, edge);
          } while (v != start);
          std::vector<unsigned int> loop_corners;
          for (const unsigned int w : loop)
            if (corner[w])
              loop_corners.push_back(w);
          if (loop_corners.size() < 3)
            for (const unsigned int third : {0u, 1u, 2u})
              corner[loop[third * loop.size() / 3]] = true;
        }

    // The curves from corner to corner, and the loops of curves.
    std::vector<int> point_tag(n_vertices, 0);
    const auto       point = [&](const unsigned int v) {
      if (point_tag[v] == 0)
        point_tag[v] = gmsh::model::geo::addPoint(boundary_vertices[v][0],
                                                  boundary_vertices[v][1],
                                                  0.);
      return point_tag[v];
    };
    std::vector<bool> edge_done(boundary_faces.size(), false);
    std::vector<std::pair<std::vector<int>, double>> loops;
    for (unsigned int start = 0; start < n_vertices; ++start)
      if (corner[start] && !edge_done[edges_at[start][0]])
        {
          std::vector<int>      loop;
          std::vector<Point<2>> polygon;
          unsigned int          v = start, edge = edges_at[start][0];
          do
            {
              // one curve: from corner v along edge to the next corner
              std::vector<unsigned int> chain{v};
              while (true)
                {
                  edge_done[edge] = true;
                  v               = other_vertex(edge, v);
                  chain.push_back(v);
                  if (corner[v])
                    break;
                  edge = other_edge(v, edge);
                }
              edge = other_edge(v, edge);
              for (unsigned int i = 0; i + 1 < chain.size(); ++i)
                polygon.push_back(boundary_vertices[chain[i]]);
              const Point<2> &a        = boundary_vertices[chain.front()];
              const Point<2> &b        = boundary_vertices[chain.back()];
              double          off_line = 0.;
              for (const unsigned int w : chain)
                {
                  const Tensor<1, 2> ab = b - a, aw = boundary_vertices[w] - a;
                  off_line = std::max(off_line,
                                      std::abs(ab[0] * aw[1] - ab[1] * aw[0]) /
                                        ab.norm_square());
                }
              int curve;
              if (off_line < 1e-8)
                curve = gmsh::model::geo::addLine(point(chain.front()),
                                                  point(chain.back()));
              else
                {
                  std::vector<int> points;
                  for (const unsigned int w : chain)
                    points.push_back(point(w));
                  curve = gmsh::model::geo::addSpline(points);
                }
              loop.push_back(curve);
          } while (v != start);
          loops.emplace_back(loop, std::abs(signed_area(polygon)));
        }

    // the outer curve encloses the largest area, the others are holes
    std::sort(loops.begin(), loops.end(), [](const auto &a, const auto &b) {
      return a.second > b.second;
    });
    std::vector<int> curve_loops;
    for (const auto &loop : loops)
      curve_loops.push_back(gmsh::model::geo::addCurveLoop(loop.first));
    const int surface = gmsh::model::geo::addPlaneSurface(curve_loops);
    gmsh::model::geo::synchronize();
    gmsh::model::addPhysicalGroup(2, {surface}, 1);
  }



  template <>
  void
  CoarseDomainMesher<3>::add_surfaces_geometry() const
  {
    const int                surface = gmsh::model::addDiscreteEntity(2);
    std::vector<std::size_t> node_tags(boundary_vertices.size());
    std::iota(node_tags.begin(), node_tags.end(), 1);
    std::vector<double> coordinates;
    for (const Point<3> &x : boundary_vertices)
      coordinates.insert(coordinates.end(), {x[0], x[1], x[2]});
    gmsh::model::mesh::addNodes(2, surface, node_tags, coordinates);
    std::vector<std::size_t> triangle_nodes;
    for (const BoundaryFace &face : boundary_faces)
      for (const unsigned int v : face.vertices)
        triangle_nodes.push_back(v + 1);
    gmsh::model::mesh::addElementsByType(surface, 2, {}, triangle_nodes);
    gmsh::model::mesh::classifySurfaces(40. * M_PI / 180.,
                                        /*boundary=*/true,
                                        /*forReparametrization=*/true,
                                        M_PI);
    gmsh::model::mesh::createGeometry();
    gmsh::vectorpair surfaces;
    gmsh::model::getEntities(surfaces, 2);
    std::vector<int> surface_tags;
    for (const auto &[d, tag] : surfaces)
      surface_tags.push_back(tag);
    const int loop   = gmsh::model::geo::addSurfaceLoop(surface_tags);
    const int volume = gmsh::model::geo::addVolume({loop});
    gmsh::model::geo::synchronize();
    gmsh::model::addPhysicalGroup(3, {volume}, 1);
  }



  template <int dim>
  std::string
  CoarseDomainMesher<dim>::meshes_in_gmsh() const
  {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 0);
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeMin", 0.);
    // Each mesh as its length in 20 digits, then its bytes. (A model for
    // each size: Gmsh 4.8 cannot remesh the reparametrised surfaces of 3D
    // once their mesh is cleared.)
    std::string bytes;
    for (const double size : sizes)
      {
        gmsh::model::add("coarser domain");
        if constexpr (dim == 2)
          add_curves_geometry();
        else
          add_surfaces_geometry();
        gmsh::option::setNumber("Mesh.MeshSizeMax", size);
        gmsh::model::mesh::generate(dim);
        const std::string mesh   = GmshModelMesh::of_current_model().to_bytes();
        const std::string length = std::to_string(mesh.size());
        bytes += std::string(20 - length.size(), '0') + length + mesh;
        gmsh::model::remove();
      }
    gmsh::finalize();
    return bytes;
  }



  template <int dim>
  void
  CoarseDomainMesher<dim>::create(const unsigned int  i,
                                  Triangulation<dim> &coarse) const
  {
    AssertIndexRange(i, sizes.size());
    if (mesh_bytes.empty())
      {
        // rank 0 meshes, every rank builds the same meshes
        std::string bytes;
        try
          {
            bytes = run_on_rank_0([&]() {
              return run_in_gmsh_child([&]() { return meshes_in_gmsh(); },
                                       "meshing the domain coarser");
            });
          }
        catch (const std::runtime_error &exc)
          {
            throw std::runtime_error("the coarser meshes of the domain: " +
                                     std::string(exc.what()));
          }
        for (std::size_t position = 0; position + 20 <= bytes.size();)
          {
            const std::size_t length = std::stoull(bytes.substr(position, 20));
            mesh_bytes.push_back(bytes.substr(position + 20, length));
            position += 20 + length;
          }
        if (mesh_bytes.size() != sizes.size())
          throw std::runtime_error(
            "the coarser meshes of the domain: Gmsh returned " +
            std::to_string(mesh_bytes.size()) + " of " +
            std::to_string(sizes.size()) + " meshes");
      }
    GmshMesh<dim> mesh =
      checked_mesh<dim>(GmshModelMesh::from_bytes(mesh_bytes[i]),
                        "the coarser mesh of the domain");
    coarse.create_triangulation(mesh.vertices, mesh.cells, SubCellData());

    // boundary ids from the nearest fine boundary face
    std::vector<Point<dim>> centres;
    for (const BoundaryFace &face : boundary_faces)
      centres.push_back(face.centre);
    const auto tree = pack_rtree_of_indices(centres);
    for (const auto &cell : coarse.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          for (const unsigned int nearest :
               tree | boost::geometry::index::adaptors::queried(
                        boost::geometry::index::nearest(face->center(), 1)))
            face->set_boundary_id(boundary_faces[nearest].id);
  }



  template class CoarseDomainMesher<2>;
  template class CoarseDomainMesher<3>;
} // namespace Signorini
