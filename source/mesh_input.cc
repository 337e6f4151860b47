#include <deal.II/grid/grid_generator.h>

#include <signorini/gmsh_mesh.h>
#include <signorini/input_error.h>
#include <signorini/mesh_input.h>
#include <signorini/registry.h>

#include <array>
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
      prm.declare_entry(
        "File name",
        "",
        Patterns::Anything(),
        dim == 2 ? "Gmsh mesh (.msh, any format Gmsh reads) of triangles, or "
                   "a .geo that Gmsh meshes when it is read; "
                   "physical curve tags are boundary ids (do not use "
                   "0); a relative path is taken from the directory "
                   "of the parameter file." :
                   "Gmsh mesh (.msh, any format Gmsh reads) of tetrahedra, "
                   "or a .geo that Gmsh meshes when it is read; "
                   "physical surface tags are boundary ids (do not "
                   "use 0); a relative path is taken from the "
                   "directory of the parameter file.");
      prm.declare_entry("Geometry file",
                        "",
                        Patterns::Anything(),
                        "Gmsh .geo file of the domain of 'File name' (its "
                        "physical curves the same boundary ids; no size "
                        "fields, transfinite, recombined or boundary-layer "
                        "entities): what Mesh adaptation/Realisation = "
                        "remeshing meshes anew; a relative path is taken "
                        "from the directory of the parameter file.");
      prm.declare_entry("Block subdivisions",
                        dim == 2 ? "4, 3" : "4, 3, 4",
                        Patterns::List(Patterns::Integer(1), dim, dim),
                        dim == 2 ?
                          "Rectangles per direction of the generated block; "
                          "each is cut into 8 triangles (4 x 3 gives the "
                          "paper's 96)." :
                          "Rectangles in x and y of the block's cross "
                          "section (each cut into 8 triangles, as in 2D), "
                          "then layers in z: each triangular prism of a "
                          "layer is cut into 3 tetrahedra.");
      prm.declare_entry("Initial refinements",
                        "0",
                        Patterns::Integer(0, 12),
                        "Uniform refinements of the initial mesh (each "
                        "multiplies the number of cells by 2^dim).");
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
    file_mesh_read.reset();
    if (source == Source::file && file_name.empty())
      throw InputError("Mesh/File name is empty but Mesh/Source = file");
    // a file given for the block is a mistake the run would not show
    if (source == Source::block)
      for (const auto &[entry, value] :
           {std::make_pair("File name", file_name),
            std::make_pair("Geometry file", geometry_file_name)})
        if (!value.empty())
          warn_once(std::string("mesh ") + entry,
                    std::string("Mesh/") + entry + " = " + value +
                      " is not used: Mesh/Source = block generates the "
                      "mesh and its geometry",
                    MPI_COMM_WORLD);
  }



  template <int dim>
  void
  MeshInput<dim>::set_input_directory(const std::string &directory)
  {
    input_directory = directory.empty() ? "." : directory;
  }



  template <int dim>
  void
  MeshInput<dim>::set_maximum_cells(const double max_cells)
  {
    this->max_cells = max_cells;
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
    /// The boundary ids of the generated block, by the position of each
    /// boundary face (see the class documentation).
    template <int dim>
    void
    set_block_boundary_ids(Triangulation<dim> &triangulation)
    {
      const double tol = 1e-10;
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const Point<dim> c = face->center();
              if (dim == 3 && (std::abs(c[dim - 1]) < tol ||
                               std::abs(c[dim - 1] - 1.) < tol))
                face->set_boundary_id(7);
              else if (std::abs(c[0]) < tol)
                face->set_boundary_id(1);
              else if (std::abs(c[1]) < tol)
                face->set_boundary_id(2);
              else if (std::abs(c[1] - 1.) < tol)
                face->set_boundary_id(c[0] < 0.5 ? 3 : 5);
              else
                face->set_boundary_id(c[1] > 0.5 ? 4 : 6);
            }
    }



    /// The unit square of the paper's block, 8 triangles per rectangle.
    void
    create_block(const std::vector<unsigned int> &subdivisions,
                 Triangulation<2>                &triangulation)
    {
      Triangulation<2> quads;
      GridGenerator::subdivided_hyper_rectangle(quads,
                                                {subdivisions[0],
                                                 subdivisions[1]},
                                                Point<2>(),
                                                Point<2>(1., 1.));
      GridGenerator::convert_hypercube_to_simplex_mesh(quads, triangulation);
      set_block_boundary_ids(triangulation);
    }



    /**
     * The block extruded: the unit cube, whose cross section z = const is
     * the 2D block's mesh refined @p refinements times, in subdivisions[2]
     * 2^refinements layers. Each triangular prism is cut into 3 tetrahedra
     * by the diagonals of its quadrilateral faces that run from the
     * lower-numbered vertex at the bottom to the other at the top, the same
     * rule on both sides of a face: the mesh is conforming. Refined this way
     * (not by deal.II's refinement of tetrahedra, whose smallest dihedral
     * angle decays from level to level) every level has the shapes of the
     * first.
     */
    void
    create_block(const std::vector<unsigned int> &subdivisions,
                 const unsigned int               refinements,
                 Triangulation<3>                &triangulation)
    {
      Triangulation<2> section;
      create_block(subdivisions, section);
      section.refine_global(refinements);
      const unsigned int    layers = subdivisions[2] << refinements;
      const unsigned int    n      = section.n_vertices();
      std::vector<Point<3>> vertices;
      for (unsigned int k = 0; k <= layers; ++k)
        for (const auto &v : section.get_vertices())
          vertices.emplace_back(v[0], v[1], double(k) / layers);
      std::vector<CellData<3>> cells;
      for (const auto &triangle : section.active_cell_iterators())
        {
          std::array<unsigned int, 3> v = {{triangle->vertex_index(0),
                                            triangle->vertex_index(1),
                                            triangle->vertex_index(2)}};
          std::sort(v.begin(), v.end());
          const auto [a, b, c] = v;
          for (unsigned int k = 0; k < layers; ++k)
            {
              const unsigned int bottom = k * n, top = (k + 1) * n;
              const unsigned int tets[3][4] = {
                {a + bottom, b + bottom, c + bottom, c + top},
                {a + bottom, b + bottom, b + top, c + top},
                {a + bottom, a + top, b + top, c + top}};
              for (const auto &tet : tets)
                {
                  CellData<3> cell(4);
                  for (unsigned int i = 0; i < 4; ++i)
                    cell.vertices[i] = tet[i];
                  // deal.II's reference tetrahedron is positively oriented
                  const Tensor<1, 3> e1 = vertices[tet[1]] - vertices[tet[0]],
                                     e2 = vertices[tet[2]] - vertices[tet[0]],
                                     e3 = vertices[tet[3]] - vertices[tet[0]];
                  if (e1 * cross_product_3d(e2, e3) < 0.)
                    std::swap(cell.vertices[1], cell.vertices[2]);
                  cells.push_back(cell);
                }
            }
        }
      triangulation.create_triangulation(vertices, cells, SubCellData());
      set_block_boundary_ids(triangulation);
    }
  } // namespace



  template <int dim>
  std::string
  MeshInput<dim>::block_subdivisions_text() const
  {
    std::string text;
    for (const unsigned int s : block_subdivisions)
      text += (text.empty() ? "" : " x ") + std::to_string(s);
    return text + (dim == 2 ? " rectangles" : " rectangles x layers");
  }



  template <int dim>
  double
  MeshInput<dim>::n_block_cells() const
  {
    // convert_hypercube_to_simplex_mesh() cuts each rectangle into 8, the
    // extrusion each triangle of a layer into 3
    double n = (dim == 2 ? 8. : 24.);
    for (const unsigned int s : block_subdivisions)
      n *= s;
    return n;
  }



  template <int dim>
  const GmshMesh<dim> &
  MeshInput<dim>::file_mesh() const
  {
    if (!file_mesh_read)
      {
        // Gmsh reads the file (or meshes the geometry) and the mesh is
        // checked before anything is built from it: deal.II would accept
        // degenerate cells and nodes at the same point, which only fail in
        // the solver.
        const std::string path = path_of(file_name);
        try
          {
            file_mesh_read = std::make_shared<GmshMesh<dim>>(
              read_gmsh_mesh<dim>(path, max_cells));
          }
        catch (const InputError &exc)
          {
            throw InputError(std::string("Mesh/File name: ") + exc.what());
          }
      }
    return *file_mesh_read;
  }



  template <int dim>
  double
  MeshInput<dim>::n_coarse_cells() const
  {
    return source == Source::block ?
             n_block_cells() :
             static_cast<double>(file_mesh().cells.size());
  }



  template <int dim>
  void
  MeshInput<dim>::create(Triangulation<dim> &triangulation) const
  {
    if (source == Source::block)
      {
        // deal.II numbers vertices and cells with 32-bit integers
        if (n_block_cells() * std::pow(2., dim * initial_refinements) > 2e9)
          throw InputError(
            "Mesh/Block subdivisions: " + block_subdivisions_text() + " and " +
            std::to_string(initial_refinements) +
            " initial refinements give more than 2e9 " +
            (dim == 2 ? "triangles" : "tetrahedra") +
            " (deal.II numbers them with 32-bit integers)");
        // Whatever the subdivisions, x = 1/2 and y = 1/2 are nodes (vertices
        // for even counts, edge midpoints added by the conversion for odd
        // ones), so the load boundaries are resolved exactly.
        if constexpr (dim == 3)
          {
            create_block(block_subdivisions,
                         initial_refinements,
                         triangulation);
            return;
          }
        else
          create_block(block_subdivisions, triangulation);
      }
    else
      {
        const GmshMesh<dim> &mesh = file_mesh();
        const std::string    path = path_of(file_name);
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
    triangulation.refine_global(initial_refinements);
  }

  template class MeshInput<2>;
  template class MeshInput<3>;
} // namespace Signorini
