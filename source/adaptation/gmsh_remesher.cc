#include <deal.II/base/mpi.h>

#include <deal.II/grid/grid_tools.h>

#include <signorini/adaptation/gmsh_remesher.h>
#include <signorini/cell_locator.h>
#include <signorini/gmsh_geometry.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <gmsh.h>
#include <map>
#include <set>
#include <stdexcept>

namespace Signorini
{
  namespace
  {
    /// The mesh Gmsh made, flat, as rank 0 sends it to the others.
    struct FlatMesh
    {
      std::vector<double>       coordinates;    // x, y per vertex
      std::vector<unsigned int> triangles;      // 3 vertices per cell
      std::vector<unsigned int> boundary_lines; // 2 vertices and the id
    };



    /// The generated block (MeshInput): the unit square, boundary ids 1
    /// (x = 0), 2 (y = 0), 3 and 5 (y = 1, x < or > 1/2), 4 and 6 (x = 1,
    /// y > or < 1/2).
    void
    add_block_geometry()
    {
      namespace geo = gmsh::model::geo;
      const int p0 = geo::addPoint(0, 0, 0), p1 = geo::addPoint(1, 0, 0),
                p2 = geo::addPoint(1, 0.5, 0), p3 = geo::addPoint(1, 1, 0),
                p4 = geo::addPoint(0.5, 1, 0), p5 = geo::addPoint(0, 1, 0);
      // (line, boundary id) counterclockwise
      const std::vector<std::pair<int, int>> edges = {{geo::addLine(p0, p1), 2},
                                                      {geo::addLine(p1, p2), 6},
                                                      {geo::addLine(p2, p3), 4},
                                                      {geo::addLine(p3, p4), 5},
                                                      {geo::addLine(p4, p5), 3},
                                                      {geo::addLine(p5, p0),
                                                       1}};
      std::vector<int>                       loop;
      for (const auto &[line, id] : edges)
        loop.push_back(line);
      const int surface = geo::addPlaneSurface({geo::addCurveLoop(loop)});
      geo::synchronize();
      for (const auto &[line, id] : edges)
        gmsh::model::addPhysicalGroup(1, {line}, id);
      gmsh::model::addPhysicalGroup(2, {surface}, 1);
    }



    /// The message of a failure of Gmsh on @p geometry_file (empty: the
    /// block).
    std::string
    gmsh_failure(const std::string &geometry_file, const std::string &what)
    {
      return "Mesh adaptation/Realisation = remeshing: Gmsh failed" +
             (geometry_file.empty() ? std::string() :
                                      " on <" + geometry_file + ">") +
             ": " + one_line_message(what);
    }



    /// Mesh the geometry with Gmsh, the size at a point given by
    /// @p size_at, and flatten the result.
    FlatMesh
    mesh_with_gmsh(const std::string                           &geometry_file,
                   const std::function<double(double, double)> &size_at)
    {
      const GmshExitGuard guard("Mesh/Geometry file <" + geometry_file + ">");
      // (not the user's Gmsh configuration files: the same mesh everywhere)
      gmsh::initialize(0, nullptr, false);
      FlatMesh flat;
      try
        {
          gmsh::option::setNumber("General.Terminal", 0);
          gmsh::option::setNumber("General.Verbosity", 0);
          if (geometry_file.empty())
            {
              gmsh::model::add("remeshed");
              add_block_geometry();
            }
          else
            gmsh::open(geometry_file);
          // (after the file, which may set options of its own)
          gmsh::option::setNumber("General.NumThreads", 1);
          gmsh::option::setNumber("Mesh.Algorithm", 6); // Frontal-Delaunay
          gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
          gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
          gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
          gmsh::option::setNumber("Mesh.MeshSizeFactor", 1);
          gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
          gmsh::option::setNumber("Mesh.MeshSizeMax", 1e22);
          gmsh::option::setNumber("Mesh.ElementOrder", 1);
          gmsh::option::setNumber("Mesh.RecombineAll", 0);
          gmsh::model::mesh::setSizeCallback(
            [&](int, int, double x, double y, double) {
              return size_at(x, y);
            });
          gmsh::model::mesh::generate(2);

          std::vector<std::size_t> node_tags;
          std::vector<double>      coordinates, parametric;
          gmsh::model::mesh::getNodes(node_tags, coordinates, parametric);
          std::map<std::size_t, unsigned int> vertex_of_tag;
          std::vector<std::size_t>            element_tags, element_nodes;
          gmsh::model::mesh::getElementsByType(2, element_tags, element_nodes);
          std::map<std::size_t, unsigned int> index_of_node;
          for (unsigned int n = 0; n < node_tags.size(); ++n)
            index_of_node[node_tags[n]] = n;
          const auto vertex = [&](const std::size_t tag) {
            const auto [entry, inserted] =
              vertex_of_tag.emplace(tag, vertex_of_tag.size());
            if (inserted)
              for (unsigned int d = 0; d < 2; ++d)
                flat.coordinates.push_back(
                  coordinates[3 * index_of_node.at(tag) + d]);
            return entry->second;
          };
          for (const std::size_t tag : element_nodes)
            flat.triangles.push_back(vertex(tag));

          gmsh::vectorpair groups;
          gmsh::model::getPhysicalGroups(groups, 1);
          for (const auto &[group_dim, id] : groups)
            {
              std::vector<int> entities;
              gmsh::model::getEntitiesForPhysicalGroup(group_dim, id, entities);
              for (const int entity : entities)
                {
                  // (Gmsh 4.8 leaves non-empty outputs as they are)
                  element_tags.clear();
                  element_nodes.clear();
                  gmsh::model::mesh::getElementsByType(1,
                                                       element_tags,
                                                       element_nodes,
                                                       entity);
                  for (unsigned int e = 0; e < element_tags.size(); ++e)
                    {
                      flat.boundary_lines.push_back(
                        vertex(element_nodes[2 * e]));
                      flat.boundary_lines.push_back(
                        vertex(element_nodes[2 * e + 1]));
                      flat.boundary_lines.push_back(id);
                    }
                }
            }
        }
      // (Gmsh 4.8 throws its last error message as a std::string)
      catch (const std::string &message)
        {
          gmsh::finalize();
          throw std::runtime_error(gmsh_failure(geometry_file, message));
        }
      catch (const std::exception &exc)
        {
          gmsh::finalize();
          throw std::runtime_error(gmsh_failure(geometry_file, exc.what()));
        }
      gmsh::finalize();
      if (flat.triangles.empty())
        throw std::runtime_error("Mesh adaptation/Realisation = remeshing: "
                                 "Gmsh made no triangles" +
                                 (geometry_file.empty() ?
                                    std::string() :
                                    " from <" + geometry_file +
                                      "> (does it define a plane surface?)"));
      return flat;
    }
  } // namespace



  template <int dim>
  void
  GmshRemesher<dim>::check_geometry(
    const MeshInput<dim>               &input,
    const std::set<types::boundary_id> &boundary_ids) const
  {
    if (dim != 2 || (input.source != MeshInput<dim>::Source::block &&
                     input.geometry_file_name.empty()))
      throw InputError(
        "Mesh adaptation/Realisation = remeshing needs the geometry of the "
        "domain: the generated block (Mesh/Source = block, 2D) has one; for "
        "a Gmsh mesh file give its .geo as Mesh/Geometry file");
    if (input.source == MeshInput<dim>::Source::file)
      {
        const std::string path = input.path_of(input.geometry_file_name);
        if (!std::ifstream(path))
          throw InputError("Mesh/Geometry file: cannot open <" + path + ">");
        // read it now, so that a bad geometry is an input error
        const GmshExitGuard guard("Mesh/Geometry file <" + path + ">");
        gmsh::initialize(0, nullptr, false);
        std::string error;
        try
          {
            gmsh::option::setNumber("General.Terminal", 0);
            gmsh::open(path);
            gmsh::vectorpair surfaces, curves;
            gmsh::model::getEntities(surfaces, 2);
            gmsh::model::getPhysicalGroups(curves, 1);
            std::set<int> tags;
            for (const auto &[curve_dim, tag] : curves)
              tags.insert(tag);
            if (surfaces.empty())
              error = "it defines no surface to mesh";
            for (const auto id : boundary_ids)
              if (error.empty() && tags.count(id) == 0)
                error = "no physical curve has the tag " + std::to_string(id) +
                        ", a boundary id of the input (the remeshed mesh "
                        "would lack it)";
          }
        catch (const std::string &message)
          {
            error = message.empty() ? "Gmsh cannot read it" : message;
          }
        catch (const std::exception &exc)
          {
            error = exc.what();
          }
        gmsh::finalize();
        if (!error.empty())
          throw InputError("Mesh/Geometry file: <" + path +
                           ">: " + one_line_message(error));
      }
  }



  template <int dim>
  void
  GmshRemesher<dim>::remesh(const MeshInput<dim> &input,
                            const Vector<double> &size_ratio,
                            Triangulation<dim>   &mesh) const
  {
    // (check_geometry() ran at input)
    Assert(dim == 2, ExcInternalError());
    if constexpr (dim == 2)
      {
        const MPI_Comm communicator = MPI_COMM_WORLD;
        FlatMesh       flat;
        // rank 0 meshes; a failure there is sent to every rank with the
        // (empty) mesh, so that all stop together
        std::string failure;
        if (Utilities::MPI::this_mpi_process(communicator) == 0)
          try
            {
              // log of the size asked for at every vertex: the mean over its
              // cells of log(r_E (4 |E| / sqrt 3)^(1/2))
              std::vector<double>       log_size(mesh.n_vertices(), 0.);
              std::vector<unsigned int> n_cells(mesh.n_vertices(), 0);
              for (const auto &cell : mesh.active_cell_iterators())
                {
                  const double size =
                    size_ratio[cell->active_cell_index()] *
                    std::sqrt(4. * cell->measure() / std::sqrt(3.));
                  for (const unsigned int v : cell->vertex_indices())
                    {
                      log_size[cell->vertex_index(v)] += std::log(size);
                      ++n_cells[cell->vertex_index(v)];
                    }
                }
              for (unsigned int v = 0; v < log_size.size(); ++v)
                if (n_cells[v] > 0)
                  {
                    log_size[v] /= n_cells[v];
                  }
              const CellLocator<dim> locator(mesh);
              const auto size_at = [&](const double x, const double y) {
                // (outside the mesh, near a curved boundary: the nearest
                // cell, without extrapolation)
                const auto  location  = locator.locate(Point<dim>(x, y));
                const auto &cell      = locator.cell(location.cell);
                double      log_value = 0., weight_sum = 0.;
                for (const unsigned int v : cell->vertex_indices())
                  {
                    const double weight =
                      std::clamp(location.weights[v], 0., 1.);
                    log_value += weight * log_size[cell->vertex_index(v)];
                    weight_sum += weight;
                  }
                return std::exp(log_value / weight_sum);
              };
              flat =
                mesh_with_gmsh(input.source == MeshInput<dim>::Source::block ?
                                 std::string() :
                                 input.path_of(input.geometry_file_name),
                               size_at);
            }
          catch (const std::exception &exc)
            {
              failure = exc.what();
            }
        failure = Utilities::MPI::broadcast(communicator, failure);
        if (!failure.empty())
          throw std::runtime_error(failure);
        flat.coordinates =
          Utilities::MPI::broadcast(communicator, flat.coordinates);
        flat.triangles =
          Utilities::MPI::broadcast(communicator, flat.triangles);
        flat.boundary_lines =
          Utilities::MPI::broadcast(communicator, flat.boundary_lines);

        std::vector<Point<dim>> vertices;
        for (unsigned int v = 0; 2 * v < flat.coordinates.size(); ++v)
          vertices.emplace_back(flat.coordinates[2 * v],
                                flat.coordinates[2 * v + 1]);
        std::vector<CellData<dim>> cells;
        for (unsigned int c = 0; 3 * c < flat.triangles.size(); ++c)
          {
            CellData<dim> cell(3);
            cell.vertices = {flat.triangles[3 * c],
                             flat.triangles[3 * c + 1],
                             flat.triangles[3 * c + 2]};
            cells.push_back(cell);
          }
        SubCellData boundary;
        for (unsigned int l = 0; 3 * l < flat.boundary_lines.size(); ++l)
          {
            CellData<1> line;
            line.vertices    = {flat.boundary_lines[3 * l],
                                flat.boundary_lines[3 * l + 1]};
            line.boundary_id = flat.boundary_lines[3 * l + 2];
            boundary.boundary_lines.push_back(line);
          }
        GridTools::invert_cells_with_negative_measure(vertices, cells);
        mesh.clear();
        mesh.create_triangulation(vertices, cells, boundary);
      }
  }

  template class GmshRemesher<2>;
  template class GmshRemesher<3>;
} // namespace Signorini
