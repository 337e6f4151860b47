#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <signorini/gmsh_file_check.h>
#include <signorini/input_error.h>
#include <signorini/mesh_input.h>
#include <signorini/registry.h>

#include <cmath>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// The names of the values of Mesh/Source.
    template <int dim>
    const NamedValues<typename MeshInput<dim>::Source> &
    source_names()
    {
      using Source = typename MeshInput<dim>::Source;
      static const NamedValues<Source> names(
        {{"block", Source::block, ""}, {"file", Source::file, ""}});
      return names;
    }
  } // namespace



  template <int dim>
  void
  MeshInput<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    {
      prm.declare_entry("Source",
                        source_names<dim>().default_name(),
                        Patterns::Selection(source_names<dim>().selection()),
                        "'block': the unit square of the paper's example, "
                        "generated; 'file': read 'File name'.");
      prm.declare_entry("File name",
                        "",
                        Patterns::Anything(),
                        "ASCII Gmsh mesh (msh 2.2 or 4.x) of triangles; "
                        "physical curve tags are boundary ids (do not use "
                        "0); a relative path is taken from the directory of "
                        "the parameter file.");
      prm.declare_entry("Geometry file",
                        "",
                        Patterns::Anything(),
                        "Gmsh .geo file of the domain of 'File name' (its "
                        "physical curves the same boundary ids, no mesh size "
                        "fields): what Mesh adaptation/Realisation = "
                        "remeshing meshes anew; a relative path is taken "
                        "from the directory of the parameter file.");
      prm.declare_entry("Block subdivisions",
                        "4, 3",
                        // (the block is 2D only)
                        Patterns::List(Patterns::Integer(1), 2, 2),
                        "Rectangles per direction of the generated block; "
                        "each is cut into 8 triangles (4 x 3 gives the "
                        "paper's 96).");
      prm.declare_entry("Initial refinements",
                        "0",
                        Patterns::Integer(0, 12),
                        "Uniform refinements of the initial mesh (each "
                        "multiplies the number of triangles by 4).");
    }
    prm.leave_subsection();
  }



  template <int dim>
  void
  MeshInput<dim>::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    {
      source             = source_names<dim>().value(prm.get("Source"));
      file_name          = prm.get("File name");
      geometry_file_name = prm.get("Geometry file");
      block_subdivisions.clear();
      for (const auto &s :
           Utilities::split_string_list(prm.get("Block subdivisions")))
        block_subdivisions.push_back(Utilities::string_to_int(s));
      initial_refinements = prm.get_integer("Initial refinements");
    }
    prm.leave_subsection();
    if (source == Source::file && file_name.empty())
      throw InputError("Mesh/File name is empty but Mesh/Source = file");
    // both sources make triangles
    if (dim != 2)
      throw InputError("Mesh/Source = " + source_names<dim>().name(source) +
                       ": " +
                       (source == Source::block ?
                          "the generated block" :
                          "the Gmsh reader (strictly checked triangles)") +
                       " is implemented in 2D only");
  }



  template <int dim>
  void
  MeshInput<dim>::set_input_directory(const std::string &directory)
  {
    input_directory = directory.empty() ? "." : directory;
  }



  template <int dim>
  std::string
  MeshInput<dim>::path_of(const std::string &name) const
  {
    return (name.empty() || name[0] == '/') ? name :
                                              input_directory + "/" + name;
  }



  namespace
  {
    template <int dim>
    void
    create_block(const std::vector<unsigned int> &subdivisions,
                 Triangulation<dim>              &triangulation)
    {
      Assert(dim == 2, ExcNotImplemented());
      Triangulation<dim> quads;
      GridGenerator::subdivided_hyper_rectangle(quads,
                                                subdivisions,
                                                Point<dim>(),
                                                Point<dim>(1., 1.));
      GridGenerator::convert_hypercube_to_simplex_mesh(quads, triangulation);

      // Boundary ids by position, see the class documentation.
      const double tol = 1e-10;
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const Point<dim> c = face->center();
              if (std::abs(c[0]) < tol)
                face->set_boundary_id(1);
              else if (std::abs(c[1]) < tol)
                face->set_boundary_id(2);
              else if (std::abs(c[1] - 1.) < tol)
                face->set_boundary_id(c[0] < 0.5 ? 3 : 5);
              else
                face->set_boundary_id(c[1] > 0.5 ? 4 : 6);
            }
    }
  } // namespace



  template <int dim>
  double
  MeshInput<dim>::n_block_cells() const
  {
    // convert_hypercube_to_simplex_mesh() cuts each rectangle into 8
    double n = 8.;
    for (const unsigned int s : block_subdivisions)
      n *= s;
    return n;
  }



  template <int dim>
  void
  MeshInput<dim>::create(Triangulation<dim> &triangulation) const
  {
    if (source == Source::block)
      {
        if (dim != 2)
          throw InputError("Mesh/Source = block is only defined in 2D");
        // deal.II numbers vertices and cells with 32-bit integers
        if (n_block_cells() * std::pow(4., initial_refinements) > 2e9)
          throw InputError(
            "Mesh/Block subdivisions: " +
            std::to_string(block_subdivisions[0]) + " x " +
            std::to_string(block_subdivisions[1]) + " rectangles and " +
            std::to_string(initial_refinements) +
            " initial refinements give more than 2e9 triangles (deal.II "
            "numbers them with 32-bit integers)");
        // Whatever the subdivisions, x = 1/2 and y = 1/2 are nodes (vertices
        // for even counts, edge midpoints added by the conversion for odd
        // ones), so the load boundaries are resolved exactly.
        create_block(block_subdivisions, triangulation);
      }
    else
      {
        const std::string path = path_of(file_name);
        if constexpr (dim == 2)
          {
            // The file is checked by a strict parser first: deal.II's reader
            // trusts it and crashes, hangs or allocates without bound on a
            // corrupted one, and it would accept degenerate triangles and
            // nodes at the same point, which only fail in the solver.
            GmshTriangleMesh mesh;
            try
              {
                mesh = read_gmsh_file(path);
              }
            catch (const InputError &exc)
              {
                throw InputError(std::string("Mesh/File name: ") + exc.what());
              }
            // as GridIn::read_msh() does: clockwise triangles are turned
            GridTools::invert_cells_with_negative_measure(mesh.vertices,
                                                          mesh.cells);
            try
              {
                triangulation.create_triangulation(mesh.vertices,
                                                   mesh.cells,
                                                   mesh.boundary);
              }
            catch (const ExceptionBase &exc)
              {
                std::ostringstream text;
                exc.print_info(text);
                throw InputError("Mesh/File name: cannot build a mesh from <" +
                                 path + ">: " + one_line_message(text.str()));
              }
          }
        else
          throw InputError("Mesh/Source = file is only implemented in 2D");
      }
    triangulation.refine_global(initial_refinements);
  }

  template class MeshInput<2>;
  template class MeshInput<3>;
} // namespace Signorini
