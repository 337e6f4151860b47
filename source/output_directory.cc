#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <signorini/input_error.h>
#include <signorini/output_directory.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace Signorini
{
  namespace fs = std::filesystem;

  const std::string OutputDirectory::manifest_name = ".signorini-manifest";



  namespace
  {
    /// Why @p path cannot hold the results ("" if it can).
    std::string
    directory_problem(const std::string &path)
    {
      const std::string name = "Output directory: ";
      if (path.empty())
        return name + "empty; name the directory of the results";
      std::error_code ec;
      const auto      status = fs::status(path, ec);
      if (fs::exists(status) && !fs::is_directory(status))
        return name + "<" + path + "> exists and is not a directory";
      // The directories missing now, deepest first, are removed again after
      // the check: checking (--validate) leaves the disk as it was.
      std::vector<fs::path> missing;
      fs::path              dir = fs::absolute(path, ec).lexically_normal();
      if (dir.filename().empty())
        dir = dir.parent_path();
      for (; !ec && dir.has_relative_path() && !fs::exists(dir, ec);
           dir = dir.parent_path())
        missing.push_back(dir);
      std::string problem;
      fs::create_directories(path, ec);
      if (ec)
        problem = name + "cannot create <" + path + ">: " + ec.message();
      else
        {
          // access() tells what the permission bits say, not whether a file
          // can be created (root, read-only file systems): try it. "x":
          // never overwrite a file of the user's.
          const std::string probe =
            path + "/.signorini-probe-" + std::to_string(::getpid());
          std::FILE *file = std::fopen(probe.c_str(), "wx");
          if (file == nullptr)
            problem = name + "<" + path +
                      "> is not writable (cannot create a file in it: " +
                      std::strerror(errno) + ")";
          else
            {
              std::fclose(file);
              fs::remove(probe, ec);
            }
        }
      for (const auto &created : missing)
        fs::remove(created, ec); // empty directories only
      return problem;
    }



    /// ": " and the system's reason for the last failure, if it gave one.
    std::string
    reason()
    {
      return errno != 0 ? std::string(": ") + std::strerror(errno) : "";
    }
  } // namespace



  void
  OutputDirectory::initialize(const std::string &path, const MPI_Comm comm)
  {
    directory = path;
    root      = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
    listed.clear();
    // every rank throws the same error (rank 0 alone touches the disk)
    std::string problem = root ? directory_problem(path) : std::string();
    if (dealii::Utilities::MPI::n_mpi_processes(comm) > 1)
      problem = dealii::Utilities::MPI::broadcast(comm, problem, 0);
    if (!problem.empty())
      throw InputError(problem);
  }



  void
  OutputDirectory::start_run()
  {
    listed.clear();
    if (!root)
      return;
    std::error_code ec;
    fs::create_directories(directory, ec);
    if (ec)
      throw InputError("Output directory: cannot create <" + directory +
                       ">: " + ec.message());
    const std::string manifest = path_of(manifest_name);
    {
      std::ifstream in(manifest);
      std::string   name;
      while (std::getline(in, name))
        {
          // plain names only: the manifest never leads out of the directory
          if (name.empty() || name[0] == '#' ||
              name.find('/') != std::string::npos || name == "." ||
              name == "..")
            continue;
          const std::string file   = path_of(name);
          const auto        status = fs::symlink_status(file, ec);
          if ((fs::is_regular_file(status) || fs::is_symlink(status)) &&
              !fs::remove(file, ec))
            throw InputError("Output directory: cannot delete <" + file +
                             "> of the previous run: " + ec.message());
        }
    }
    errno = 0;
    std::ofstream out(manifest);
    out << "# Files written by the last signorini run in this directory; the "
           "next run deletes\n# them (and only them) before writing its own.\n";
    out.close();
    if (!out)
      throw std::runtime_error("cannot write <" + manifest + ">" + reason());
  }



  void
  OutputDirectory::record(const std::string &name)
  {
    if (!root || !listed.insert(name).second)
      return;
    const std::string manifest = path_of(manifest_name);
    errno                      = 0;
    std::ofstream out(manifest, std::ios::app);
    out << name << '\n';
    out.close();
    if (!out)
      throw std::runtime_error("cannot write <" + manifest + ">" + reason());
  }



  void
  OutputDirectory::write(const std::string                         &name,
                         const std::function<void(std::ostream &)> &write)
  {
    record(name);
    const std::string path = path_of(name);
    errno                  = 0;
    std::ofstream out(path);
    if (!out)
      throw std::runtime_error("cannot open <" + path + "> for writing" +
                               reason());
    try
      {
        write(out);
        out.close();
      }
    catch (const dealii::ExceptionBase &)
      {
        // deal.II's writers check the stream, with a text naming no file
        if (out)
          throw;
      }
    if (!out)
      throw std::runtime_error("cannot write <" + path + ">" + reason());
  }



  std::string
  OutputDirectory::path_of(const std::string &name) const
  {
    return directory + "/" + name;
  }
} // namespace Signorini
