#include <signorini/gmsh_child_process.h>
#include <signorini/gmsh_geometry.h>
#include <signorini/gmsh_mesh.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <gmsh.h>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace Signorini
{
  namespace
  {
    /// The measure of a cell of size h is unit_measure(dim) h^dim: the
    /// equilateral triangle in 2D; in 3D Gmsh's Delaunay tetrahedra of size
    /// h, 1 / 0.55 times the regular one (measured, see GmshRemesher).
    double
    unit_measure(const unsigned int dim)
    {
      return (dim == 2) ? std::sqrt(3.) / 4. : 1. / (6. * std::sqrt(2.) * 0.55);
    }



    /// The coordinates of all nodes of the current Gmsh model, by tag.
    std::map<std::size_t, std::array<double, 3>>
    node_coordinates()
    {
      std::vector<std::size_t> tags;
      std::vector<double>      coordinates, parametric;
      gmsh::model::mesh::getNodes(
        tags, coordinates, parametric, -1, -1, true, false);
      std::map<std::size_t, std::array<double, 3>> nodes;
      for (unsigned int n = 0; n < tags.size(); ++n)
        nodes[tags[n]] = {
          {coordinates[3 * n], coordinates[3 * n + 1], coordinates[3 * n + 2]}};
      return nodes;
    }



    /// The sum of the measures of the triangles (@p dim = 2) or tetrahedra
    /// (3) of the current Gmsh mesh.
    double
    mesh_measure(const unsigned int dim)
    {
      const auto               nodes = node_coordinates();
      std::vector<std::size_t> tags, element_nodes;
      gmsh::model::mesh::getElementsByType(dim == 2 ? 2 : 4,
                                           tags,
                                           element_nodes);
      double measure = 0;
      for (unsigned int e = 0; e < tags.size(); ++e)
        {
          std::array<double, 3> edge[3] = {};
          const auto           &origin = nodes.at(element_nodes[(dim + 1) * e]);
          for (unsigned int k = 0; k < dim; ++k)
            for (unsigned int d = 0; d < 3; ++d)
              edge[k][d] =
                nodes.at(element_nodes[(dim + 1) * e + k + 1])[d] - origin[d];
          const std::array<double, 3> normal = {
            {edge[0][1] * edge[1][2] - edge[0][2] * edge[1][1],
             edge[0][2] * edge[1][0] - edge[0][0] * edge[1][2],
             edge[0][0] * edge[1][1] - edge[0][1] * edge[1][0]}};
          measure +=
            (dim == 2) ?
              std::hypot(normal[0], normal[1], normal[2]) / 2. :
              std::abs(normal[0] * edge[2][0] + normal[1] * edge[2][1] +
                       normal[2] * edge[2][2]) /
                6.;
        }
      return measure;
    }



    /// The longest edge of the current Gmsh mesh of the curves.
    double
    longest_curve_element()
    {
      const auto nodes  = node_coordinates();
      double     length = 0;
      // 2- and 3-node lines: the first two nodes are the ends
      for (const auto &[type, n_nodes] : {std::pair<int, int>(1, 2), {8, 3}})
        {
          std::vector<std::size_t> tags, element_nodes;
          gmsh::model::mesh::getElementsByType(type, tags, element_nodes);
          for (unsigned int e = 0; e < tags.size(); ++e)
            {
              const auto &a = nodes.at(element_nodes[n_nodes * e]),
                         &b = nodes.at(element_nodes[n_nodes * e + 1]);
              length =
                std::max(length,
                         std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
            }
        }
      return length;
    }



    /**
     * In a child: the measure of the domain of @p path (from a coarse mesh)
     * and the longest element Gmsh makes on its curves with the file's
     * sizes, but none shorter than the size @p floor_size at which the
     * domain would hold 4 @p max_cells cells (a tiny size cannot make the
     * estimate itself slow): "S<measure> <size>"; "" if the file defines no
     * domain (the reader of the mesh says so later).
     */
    std::string
    estimate_sizes(const std::string &path,
                   const unsigned int dim,
                   const double       max_cells)
    {
      gmsh::initialize(0, nullptr, false);
      gmsh::option::setNumber("General.Terminal", 0);
      gmsh::option::setNumber("General.Verbosity", 0);
      gmsh::open(path);
      gmsh::option::setNumber("General.NumThreads", 1);
      gmsh::vectorpair domains;
      gmsh::model::getEntities(domains, dim);
      if (domains.empty())
        return "";
      double x0, y0, z0, x1, y1, z1;
      gmsh::model::getBoundingBox(-1, -1, x0, y0, z0, x1, y1, z1);
      const double diameter = std::hypot(x1 - x0, y1 - y0, z1 - z0);
      double       size_min = 0, size_max = 0, size_factor = 1;
      gmsh::option::getNumber("Mesh.MeshSizeMin", size_min);
      gmsh::option::getNumber("Mesh.MeshSizeMax", size_max);
      // (the file's Mesh.MeshSizeFactor scales every size Gmsh computes,
      // the coarse mesh of the measure's too: applied to the result)
      gmsh::option::getNumber("Mesh.MeshSizeFactor", size_factor);
      // A point size < 0 makes Gmsh throw where it cannot be caught (the
      // child then reports "Wrong mesh element size"). Scaled by 1e300, any
      // positive size gives one element per curve: a quick 1D mesh finds
      // such sizes before the floor below would hide them.
      gmsh::option::setNumber("Mesh.MeshSizeFactor", 1e300);
      gmsh::option::setNumber("Mesh.MeshSizeMin", 0.);
      gmsh::option::setNumber("Mesh.MeshSizeMax", diameter);
      gmsh::model::mesh::generate(1);
      gmsh::model::mesh::clear();
      gmsh::option::setNumber("Mesh.MeshSizeFactor", 1.);
      gmsh::option::setNumber("Mesh.MeshSizeMin", diameter / 20.);
      gmsh::option::setNumber("Mesh.MeshSizeMax", diameter / 20.);
      gmsh::model::mesh::generate(dim);
      const double measure = mesh_measure(dim);
      gmsh::model::mesh::clear();
      if (!(measure > 0) || !std::isfinite(measure))
        return "";
      const double floor_size =
        std::pow(measure / (unit_measure(dim) * 4. * std::min(max_cells, 2e9)),
                 1. / dim);
      gmsh::option::setNumber("Mesh.MeshSizeMin",
                              std::max(size_min, floor_size));
      gmsh::option::setNumber("Mesh.MeshSizeMax", size_max);
      gmsh::model::mesh::generate(1);
      std::ostringstream text;
      text << std::setprecision(17) << "S" << measure << ' '
           << size_factor * longest_curve_element();
      gmsh::finalize();
      return text.str();
    }



    /// In a child: the mesh of @p path as Gmsh makes it, as bytes.
    std::string
    mesh_in_child(const std::string &path, const unsigned int dim)
    {
      // (not the user's Gmsh configuration files: the same mesh everywhere)
      gmsh::initialize(0, nullptr, false);
      gmsh::option::setNumber("General.Terminal", 0);
      gmsh::option::setNumber("General.Verbosity", 0);
      gmsh::open(path);
      gmsh::option::setNumber("General.NumThreads", 1);
      gmsh::model::mesh::generate(dim);
      const std::string bytes = GmshModelMesh::of_current_model().to_bytes();
      gmsh::finalize();
      return bytes;
    }



    /// A number of cells for a message.
    std::string
    cell_count(const double n)
    {
      std::ostringstream text;
      if (n < 1e15)
        text << static_cast<long long>(std::round(n));
      else
        text << std::setprecision(3) << n;
      return text.str();
    }



  } // namespace



  GmshModelMesh
  mesh_geometry(const std::string &path,
                const unsigned int dim,
                const double       max_cells)
  {
    if (!std::filesystem::is_regular_file(path))
      throw InputError("cannot open geometry file <" + path + ">");
    const std::string what = "geometry file <" + path + ">: ";
    try
      {
        const std::string estimate = run_in_gmsh_child(
          [&]() { return estimate_sizes(path, dim, max_cells); },
          "estimating the mesh of " + path);
        std::istringstream numbers(
          estimate.substr(std::min<std::size_t>(1, estimate.size())));
        double measure = 0, size = 0;
        if (numbers >> measure >> size && size > 0)
          {
            const double n_cells =
              measure / (unit_measure(dim) * std::pow(size, dim));
            if (n_cells > max_cells)
              {
                std::ostringstream n;
                n << std::setprecision(2) << n_cells << " "
                  << (dim == 2 ? "triangles (its area " :
                                 "tetrahedra (its volume ")
                  << std::setprecision(4) << measure
                  << " over cells of the largest size on its curves, " << size
                  << ")";
                throw InputError(
                  what + "its mesh sizes would make at least about " + n.str() +
                  ", more than Maximum cells = " + cell_count(max_cells) +
                  "; refused before meshing");
              }
          }
        return GmshModelMesh::from_bytes(
          run_in_gmsh_child([&]() { return mesh_in_child(path, dim); },
                            "meshing " + path + " in " + std::to_string(dim) +
                              "D"));
      }
    catch (const InputError &)
      {
        throw;
      }
    catch (const std::exception &exc)
      {
        // (Gmsh 4.8 names neither the point nor its size)
        const std::string message = one_line_message(exc.what());
        throw InputError(
          what + message +
          (message.find("Wrong mesh element size") != std::string::npos ?
             " (are the mesh sizes of its points positive?)" :
             ""));
      }
  }
} // namespace Signorini
