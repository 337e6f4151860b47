#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>

#include <signorini/input_error.h>
#include <signorini/mesh_input.h>

#include <fstream>
#include <sstream>

namespace Signorini
{
  template <int dim>
  void
  MeshInput<dim>::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    {
      prm.declare_entry("Source",
                        "block",
                        Patterns::Selection("block|file"),
                        "'block': the unit square of the paper's example, "
                        "generated; 'file': read 'File name'.");
      prm.declare_entry("File name",
                        "",
                        Patterns::Anything(),
                        "ASCII Gmsh mesh (msh 2.2 or 4.x) of triangles; "
                        "physical curve tags are boundary ids (do not use "
                        "0); a relative path is taken from the directory of "
                        "the parameter file.");
      prm.declare_entry("Block subdivisions",
                        "4, 3",
                        Patterns::List(Patterns::Integer(1), dim, dim),
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
      source    = prm.get("Source");
      file_name = prm.get("File name");
      block_subdivisions.clear();
      for (const auto &s :
           Utilities::split_string_list(prm.get("Block subdivisions")))
        block_subdivisions.push_back(Utilities::string_to_int(s));
      initial_refinements = prm.get_integer("Initial refinements");
    }
    prm.leave_subsection();
    if (source == "file" && file_name.empty())
      throw InputError("Mesh/File name is empty but Mesh/Source = file");
  }



  template <int dim>
  void
  MeshInput<dim>::set_input_directory(const std::string &directory)
  {
    input_directory = directory.empty() ? "." : directory;
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
  void
  MeshInput<dim>::create(Triangulation<dim> &triangulation) const
  {
    if (source == "block")
      {
        if (dim != 2)
          throw InputError("Mesh/Source = block is only defined in 2D");
        // Whatever the subdivisions, x = 1/2 and y = 1/2 are nodes (vertices
        // for even counts, edge midpoints added by the conversion for odd
        // ones), so the load boundaries are resolved exactly.
        create_block(block_subdivisions, triangulation);
      }
    else
      {
        const std::string path =
          (file_name[0] == '/') ? file_name : input_directory + "/" + file_name;
        std::ifstream in(path);
        if (!in)
          throw InputError("Mesh/File name: cannot open mesh file <" + path +
                           ">");
        GridIn<dim> grid_in;
        grid_in.attach_triangulation(triangulation);
        try
          {
            grid_in.read_msh(in);
          }
        catch (const ExceptionBase &exc)
          {
            std::ostringstream text;
            exc.print_info(text);
            throw InputError("Mesh/File name: cannot read mesh file <" + path +
                             ">: " + one_line_message(text.str()));
          }
        if (triangulation.n_active_cells() == 0 ||
            !triangulation.all_reference_cells_are_simplex())
          throw InputError("Mesh/File name: <" + path +
                           "> must contain triangles only");
      }
    triangulation.refine_global(initial_refinements);
  }

  template class MeshInput<2>;
} // namespace Signorini
