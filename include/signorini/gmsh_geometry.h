#ifndef signorini_gmsh_geometry_h
#define signorini_gmsh_geometry_h

#include <string>

namespace Signorini
{
  /**
   * Mesh the Gmsh geometry file @p path (.geo) in dimension @p dim with the
   * Gmsh C++ API, as `gmsh -dim path` would (the file's own size fields and
   * options), on one thread so that every run and every rank gets the same
   * mesh, and return that mesh as the text of an ASCII msh 4.1 file, for
   * read_gmsh_text(). Throws InputError naming @p path if Gmsh cannot read
   * or mesh it.
   */
  std::string
  mesh_geometry_file(const std::string &path, const unsigned int dim);

  /**
   * While an object of this class lives, an exit of the program is an
   * error: a .geo file can end the program through Gmsh (its Exit command
   * calls exit(0)), which would pass for a successful run without results.
   * Such an exit prints "signorini: error: <what>: Gmsh ended the program
   * ..." and returns 1 instead. Create one around every call of Gmsh on a
   * user's file.
   */
  class GmshExitGuard
  {
  public:
    explicit GmshExitGuard(const std::string &what);
    ~GmshExitGuard();
  };
} // namespace Signorini

#endif
