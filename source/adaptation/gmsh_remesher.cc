#include <deal.II/base/mpi.h>

#include <signorini/adaptation/gmsh_remesher.h>
#include <signorini/cell_locator.h>
#include <signorini/domain_summary.h>
#include <signorini/gmsh_child_process.h>
#include <signorini/gmsh_mesh.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <gmsh.h>
#include <iterator>
#include <set>
#include <stdexcept>

namespace Signorini
{
  namespace
  {
    /// The size of Gmsh's cells of measure @p measure: the edge of the
    /// equilateral triangle of that area in 2D. In 3D Gmsh's Delaunay
    /// tetrahedra of size h are larger than the regular one of edge h,
    /// h^3 / (6 sqrt 2): it makes about 0.55 times as many (measured on the
    /// unit cube: 0.59 at size 0.1, 0.54 at 0.05), and the size is taken
    /// accordingly, so that the mesh has about N* cells.
    template <int dim>
    double
    gmsh_size_of(const double measure)
    {
      const double unit_measure =
        (dim == 2) ? std::sqrt(3.) / 4. : 1. / (6. * std::sqrt(2.) * 0.55);
      return std::pow(measure / unit_measure, 1. / dim);
    }



    /// log of the size asked for at every vertex of @p mesh: the mean of
    /// log(r_E h_E) over its cells, h_E the size of Gmsh's cells of the
    /// measure of E.
    template <int dim>
    std::vector<double>
    vertex_log_sizes(const Triangulation<dim> &mesh,
                     const Vector<double>     &size_ratio)
    {
      AssertDimension(size_ratio.size(), mesh.n_active_cells());
      std::vector<double>       log_size(mesh.n_vertices(), 0.);
      std::vector<unsigned int> n_cells(mesh.n_vertices(), 0);
      for (const auto &cell : mesh.active_cell_iterators())
        {
          const double log_cell_size =
            std::log(size_ratio[cell->active_cell_index()] *
                     gmsh_size_of<dim>(cell->measure()));
          for (const unsigned int v : cell->vertex_indices())
            {
              log_size[cell->vertex_index(v)] += log_cell_size;
              ++n_cells[cell->vertex_index(v)];
            }
        }
      for (unsigned int v = 0; v < log_size.size(); ++v)
        if (n_cells[v] > 0)
          log_size[v] /= n_cells[v];
      return log_size;
    }



    /// The generated block (MeshInput): the unit square, boundary ids 1
    /// (x = 0), 2 (y = 0), 3 and 5 (y = 1, x < or > 1/2), 4 and 6 (x = 1,
    /// y > or < 1/2); for @p dim = 3 extruded to the unit cube.
    void
    add_block_geometry(const unsigned int dim)
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
      if (dim == 2)
        {
          geo::synchronize();
          for (const auto &[line, id] : edges)
            gmsh::model::addPhysicalGroup(1, {line}, id);
          gmsh::model::addPhysicalGroup(2, {surface}, 1);
          return;
        }
      // The block extruded (MeshInput): the unit cube, each side face the
      // id of its edge, the faces z = 0 and z = 1 the id 7. Gmsh returns
      // the face z = 1, the volume, then the side faces in the order of the
      // curve loop.
      gmsh::vectorpair extruded;
      geo::extrude({{2, surface}}, 0, 0, 1, extruded);
      geo::synchronize();
      AssertDimension(extruded.size(), 2 + edges.size());
      for (unsigned int e = 0; e < edges.size(); ++e)
        gmsh::model::addPhysicalGroup(2,
                                      {extruded[2 + e].second},
                                      edges[e].second);
      gmsh::model::addPhysicalGroup(2, {surface, extruded[0].second}, 7);
      gmsh::model::addPhysicalGroup(3, {extruded[1].second}, 1);
    }



    /// The message of a failure of Gmsh on @p geometry_file (empty: the
    /// block), from the message @p what of run_in_gmsh_child().
    std::string
    gmsh_failure(const std::string &geometry_file, const std::string &what)
    {
      const std::string failed = "Gmsh failed";
      std::string       reason = one_line_message(what);
      if (reason.compare(0, failed.size(), failed) == 0)
        reason = reason.substr(std::min(reason.size(), failed.size() + 2));
      return "Mesh adaptation/Realisation = remeshing: Gmsh failed" +
             (geometry_file.empty() ? std::string() :
                                      " on <" + geometry_file + ">") +
             ": " + reason;
    }



    /// Mesh the geometry Gmsh holds with the remeshing's options, the size
    /// at a point given by @p size_at, and return the mesh as bytes.
    template <int dim>
    std::string
    mesh_gmsh_model(const std::function<double(const Point<dim> &)> &size_at)
    {
      // (after the file, which may set options of its own; the default
      // of every option a file could set to make other cells than
      // simplices)
      gmsh::option::setNumber("General.NumThreads", 1);
      gmsh::option::setNumber("Mesh.Algorithm", 6);   // Frontal-Delaunay
      gmsh::option::setNumber("Mesh.Algorithm3D", 1); // Delaunay
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFactor", 1);
      gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
      gmsh::option::setNumber("Mesh.MeshSizeMax", 1e22);
      gmsh::option::setNumber("Mesh.ElementOrder", 1);
      gmsh::option::setNumber("Mesh.RecombineAll", 0);
      gmsh::option::setNumber("Mesh.Recombine3DAll", 0);
      gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 0);
      gmsh::model::mesh::setSizeCallback(
        [&](int, int, double x, double y, double z) {
          Point<dim> p;
          p[0] = x;
          p[1] = y;
          if constexpr (dim == 3)
            p[2] = z;
          else
            (void)z;
          return size_at(p);
        });
      gmsh::model::mesh::generate(dim);
      return GmshModelMesh::of_current_model().to_bytes();
    }



    /// Mesh the geometry with Gmsh (in a child process: a crash of Gmsh on
    /// the file is reported, not suffered), the size at a point given by
    /// @p size_at.
    template <int dim>
    GmshModelMesh
    mesh_with_gmsh(const std::string &geometry_file,
                   const std::function<double(const Point<dim> &)> &size_at)
    {
      const auto job = [&]() {
        // (not the user's Gmsh configuration files: the same mesh everywhere)
        gmsh::initialize(0, nullptr, false);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::option::setNumber("General.Verbosity", 0);
        if (geometry_file.empty())
          {
            gmsh::model::add("remeshed");
            add_block_geometry(dim);
          }
        else
          gmsh::open(geometry_file);
        const std::string bytes = mesh_gmsh_model<dim>(size_at);
        gmsh::finalize();
        return bytes;
      };
      GmshModelMesh model;
      try
        {
          model = GmshModelMesh::from_bytes(
            run_in_gmsh_child(job,
                              "remeshing " +
                                (geometry_file.empty() ?
                                   std::string("the block") :
                                   geometry_file) +
                                " in " + std::to_string(dim) + "D"));
        }
      catch (const std::exception &exc)
        {
          throw std::runtime_error(gmsh_failure(geometry_file, exc.what()));
        }
      if (std::none_of(model.blocks.begin(),
                       model.blocks.end(),
                       [](const GmshModelMesh::Block &block) {
                         return block.type == (dim == 2 ? 2 : 4);
                       }))
        throw std::runtime_error(
          "Mesh adaptation/Realisation = remeshing: Gmsh made no " +
          std::string(dim == 2 ? "triangles" : "tetrahedra") +
          (geometry_file.empty() ?
             std::string() :
             " from <" + geometry_file + "> (does it define a " +
               (dim == 2 ? "plane surface" : "volume") + "?)"));
      return model;
    }
  } // namespace



  namespace
  {
    /// Throw an InputError if the .geo text of @p path (comments and strings
    /// aside) has a meshing constraint that would override the sizes a
    /// remeshing prescribes: a size field (Field[...], Background Field),
    /// transfinite or recombined entities. Gmsh applies them on top of the
    /// size callback: a Threshold field gave 9 058 triangles for the
    /// predicted 1 085, transfinite curves kept 3 nodes on GC whatever the
    /// sizes, and a fine background field meshed for minutes.
    void
    refuse_meshing_constraints(const std::string &path)
    {
      std::ifstream     in(path);
      const std::string text((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
      unsigned int      line = 1;
      std::string       word;
      const auto        refuse_word = [&]() {
        static const std::set<std::string> constraints = {"Field",
                                                          "Transfinite",
                                                          "Recombine",
                                                          "BoundaryLayer"};
        if (constraints.count(word) != 0)
          throw InputError(
            "Mesh/Geometry file: <" + path + "> line " + std::to_string(line) +
            " has a meshing constraint (" + word +
            ") that would override the sizes the remeshing prescribes: the "
                   "geometry of a remeshing gives the domain and its physical "
                   "groups only (keep such constraints in the .geo of the first "
                   "mesh, Mesh/File name)");
        word.clear();
      };
      for (std::size_t i = 0; i < text.size(); ++i)
        {
          const char c = text[i];
          if (std::isalnum(static_cast<unsigned char>(c)) || c == '_')
            {
              word += c;
              continue;
            }
          refuse_word();
          if (c == '\n')
            ++line;
          else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/')
            for (; i + 1 < text.size() && text[i + 1] != '\n'; ++i)
              ;
          else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*')
            for (i += 2;
                 i + 1 < text.size() && !(text[i] == '*' && text[i + 1] == '/');
                 ++i)
              line += (text[i] == '\n') ? 1 : 0;
          else if (c == '"')
            for (++i; i < text.size() && text[i] != '"'; ++i)
              line += (text[i] == '\n') ? 1 : 0;
        }
      refuse_word();
    }
  } // namespace



  template <int dim>
  void
  GmshRemesher<dim>::check_geometry(
    const MeshInput<dim>               &input,
    const std::set<types::boundary_id> &boundary_ids) const
  {
    if (input.source != MeshInput<dim>::Source::block &&
        input.geometry_file_name.empty())
      throw InputError(
        "Mesh adaptation/Realisation = remeshing needs the geometry of the "
        "domain: the generated block (Mesh/Source = block) has one; for a "
        "Gmsh mesh file give its .geo as Mesh/Geometry file");
    if (input.source != MeshInput<dim>::Source::file)
      return;
    const std::string path = input.path_of(input.geometry_file_name);
    if (!std::ifstream(path))
      throw InputError("Mesh/Geometry file: cannot open <" + path + ">");
    // a mesh would be "remeshed" into itself: the sizes ignored
    if (path.size() < 4 || path.compare(path.size() - 4, 4, ".geo") != 0)
      throw InputError("Mesh/Geometry file: <" + path +
                       "> is not a Gmsh geometry (.geo) file: remeshing "
                       "needs the geometry of the domain, not a mesh");
    refuse_meshing_constraints(path);
    const GmshMesh<dim> &mesh = input.file_mesh(); // (collective)

    // Rank 0 meshes the geometry as a remeshing would (in a child process:
    // a geometry that crashes Gmsh is bad input, found now), with about the
    // cells of the mesh, and compares the two domains.
    const MPI_Comm communicator = MPI_COMM_WORLD;
    std::string    error;
    if (Utilities::MPI::this_mpi_process(communicator) == 0)
      try
        {
          const DomainSummary<dim> mesh_summary(mesh.vertices,
                                                mesh.cells,
                                                mesh.boundary);
          const double             mesh_size =
            gmsh_size_of<dim>(mesh_summary.domain.measure / mesh.cells.size());
          const auto job = [&]() -> std::string {
            gmsh::initialize(0, nullptr, false);
            gmsh::option::setNumber("General.Terminal", 0);
            gmsh::option::setNumber("General.Verbosity", 0);
            gmsh::open(path);
            gmsh::vectorpair domains, boundary_groups;
            gmsh::model::getEntities(domains, dim);
            gmsh::model::getPhysicalGroups(boundary_groups, dim - 1);
            std::set<int> tags;
            for (const auto &[group_dim, tag] : boundary_groups)
              tags.insert(tag);
            if (domains.empty())
              return dim == 2 ? "Eit defines no surface to mesh" :
                                "Eit defines no volume to mesh";
            for (const auto id : boundary_ids)
              if (tags.count(id) == 0)
                return std::string(dim == 2 ? "Eno physical curve" :
                                              "Eno physical surface") +
                       " has the tag " + std::to_string(id) +
                       ", a boundary id of the input (the remeshed mesh "
                       "would lack it)";
            // at most about 2e5 cells, whatever the size of the geometry
            double x0, y0, z0, x1, y1, z1;
            gmsh::model::getBoundingBox(-1, -1, x0, y0, z0, x1, y1, z1);
            const double box_measure =
              (x1 - x0) * (y1 - y0) * (dim == 3 ? z1 - z0 : 1.);
            const double size =
              std::max(mesh_size, gmsh_size_of<dim>(box_measure / 2e5));
            const std::string bytes =
              mesh_gmsh_model<dim>([size](const Point<dim> &) { return size; });
            gmsh::finalize();
            return "M" + bytes;
          };
          std::string result;
          try
            {
              result = run_in_gmsh_child(job,
                                         "meshing " + path +
                                           " to compare it with the mesh");
            }
          catch (const GmshEndedProgram &exc)
            {
              throw InputError("Mesh/Geometry file <" + path +
                               ">: " + exc.what());
            }
          if (result.empty() || result[0] == 'E')
            throw InputError("Mesh/Geometry file: <" + path +
                             ">: " + (result.empty() ? "" : result.substr(1)));
          // (the checks of any mesh: one body among them)
          GmshMesh<dim> geometry_mesh;
          try
            {
              geometry_mesh =
                checked_mesh<dim>(GmshModelMesh::from_bytes(result.substr(1)),
                                  path + " as meshed by Gmsh");
            }
          catch (const InputError &exc)
            {
              throw InputError("Mesh/Geometry file: " +
                               std::string(exc.what()));
            }
          const DomainSummary<dim> geometry(geometry_mesh.vertices,
                                            geometry_mesh.cells,
                                            geometry_mesh.boundary);
          const std::string        difference =
            geometry.difference_from(mesh_summary, 2e-2);
          if (!difference.empty())
            throw InputError("Mesh/Geometry file: <" + path +
                             "> is not the domain of the mesh <" +
                             input.path_of(input.file_name) +
                             ">: " + difference);
        }
      catch (const InputError &exc)
        {
          error = exc.what();
        }
      catch (const std::exception &exc)
        {
          error = "Mesh/Geometry file: <" + path +
                  ">: " + one_line_message(exc.what());
        }
    error = Utilities::MPI::broadcast(communicator, error);
    if (!error.empty())
      throw InputError(error);
  }



  template <int dim>
  void
  GmshRemesher<dim>::remesh(const MeshInput<dim> &input,
                            const Vector<double> &size_ratio,
                            Triangulation<dim>   &mesh) const
  {
    // (check_geometry() ran at input)
    const MPI_Comm communicator = MPI_COMM_WORLD;
    std::string    bytes;
    // rank 0 meshes; a failure there is sent to every rank with the (empty)
    // mesh, so that all stop together
    std::string failure;
    if (Utilities::MPI::this_mpi_process(communicator) == 0)
      try
        {
          const std::vector<double> log_size =
            vertex_log_sizes(mesh, size_ratio);
          const CellLocator<dim> locator(mesh);
          const auto             size_at = [&](const Point<dim> &p) {
            // (outside the mesh, near a curved boundary: the nearest cell,
            // without extrapolation)
            const auto  location  = locator.locate(p);
            const auto &cell      = locator.cell(location.cell);
            double      log_value = 0., weight_sum = 0.;
            for (const unsigned int v : cell->vertex_indices())
              {
                const double weight = std::clamp(location.weights[v], 0., 1.);
                log_value += weight * log_size[cell->vertex_index(v)];
                weight_sum += weight;
              }
            return std::exp(log_value / weight_sum);
          };
          bytes =
            mesh_with_gmsh<dim>(input.source == MeshInput<dim>::Source::block ?
                                  std::string() :
                                  input.path_of(input.geometry_file_name),
                                size_at)
              .to_bytes();
        }
      catch (const std::exception &exc)
        {
          failure = exc.what();
        }
    failure = Utilities::MPI::broadcast(communicator, failure);
    if (!failure.empty())
      throw std::runtime_error(failure);
    bytes = Utilities::MPI::broadcast(communicator, bytes);

    // (the checks of an input mesh: Gmsh's output is not trusted blindly)
    const GmshMesh<dim> remeshed =
      checked_mesh<dim>(GmshModelMesh::from_bytes(bytes), "remeshed mesh");
    mesh.clear();
    mesh.create_triangulation(remeshed.vertices,
                              remeshed.cells,
                              remeshed.boundary);
  }



  template class GmshRemesher<2>;
  template class GmshRemesher<3>;
} // namespace Signorini
