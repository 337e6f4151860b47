#include <deal.II/base/utilities.h>

#include <signorini/gmsh_geometry.h>
#include <signorini/input_error.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gmsh.h>
#include <iostream>
#include <iterator>
#include <stdexcept>
#include <unistd.h>

namespace Signorini
{
  namespace
  {
    /// What the live GmshExitGuard protects, empty if none (guards do not
    /// nest).
    std::string guarded_activity;

    void
    refuse_exit_in_gmsh()
    {
      if (guarded_activity.empty())
        return;
      std::cerr << "signorini: error: " << guarded_activity
                << ": Gmsh ended the program (an Exit command in the file?)"
                << std::endl;
      std::_Exit(1);
    }
  } // namespace



  GmshExitGuard::GmshExitGuard(const std::string &what)
  {
    static const bool registered = std::atexit(refuse_exit_in_gmsh) == 0;
    (void)registered;
    guarded_activity = what;
  }



  GmshExitGuard::~GmshExitGuard()
  {
    guarded_activity.clear();
  }



  std::string
  mesh_geometry_file(const std::string &path, const unsigned int dim)
  {
    if (!std::filesystem::is_regular_file(path))
      throw InputError("cannot open geometry file <" + path + ">");
    // Gmsh writes meshes to files only: a private temporary one
    static unsigned int count     = 0;
    const std::string   mesh_file = (std::filesystem::temp_directory_path() /
                                   ("signorini-" + std::to_string(::getpid()) +
                                    "-" + std::to_string(count++) + ".msh"))
                                    .string();
    std::string         error, text;
    const GmshExitGuard guard("Mesh/File name: geometry file <" + path + ">");
    // (not the user's Gmsh configuration files: the same mesh everywhere)
    gmsh::initialize(0, nullptr, false);
    try
      {
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::option::setNumber("General.Verbosity", 0);
        gmsh::open(path);
        gmsh::option::setNumber("General.NumThreads", 1);
        gmsh::model::mesh::generate(dim);
        gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
        gmsh::option::setNumber("Mesh.Binary", 0);
        gmsh::option::setNumber("Mesh.SaveAll", 0);
        gmsh::option::setNumber("Mesh.SaveParametric", 0);
        gmsh::write(mesh_file);
      }
    catch (const std::string &message)
      {
        error = message.empty() ? "Gmsh cannot mesh it" : message;
      }
    catch (const std::exception &exc)
      {
        error = exc.what();
      }
    gmsh::finalize();
    if (error.empty())
      {
        std::ifstream in(mesh_file, std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in),
                    std::istreambuf_iterator<char>());
        if (!in.good() && !in.eof())
          error = "cannot read the mesh Gmsh wrote to <" + mesh_file + ">";
      }
    std::remove(mesh_file.c_str());
    if (!error.empty())
      throw InputError("geometry file <" + path +
                       ">: Gmsh failed: " + one_line_message(error));
    return text;
  }
} // namespace Signorini
