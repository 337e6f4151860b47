#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <signorini/input_error.h>
#include <signorini/output_directory.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
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
      // the kernel's own trees (as root, /dev took the tables and files)
      {
        const fs::path real = fs::weakly_canonical(fs::absolute(path, ec), ec);
        for (const char *system : {"/dev", "/proc", "/sys"})
          {
            const fs::path tree(system);
            const auto     mismatch =
              std::mismatch(tree.begin(), tree.end(), real.begin(), real.end());
            if (!ec && mismatch.first == tree.end())
              return name + "<" + path + "> is in " + system +
                     ", the system's device and kernel files; name a "
                     "directory for the results";
          }
      }
      // The directories missing now, deepest first, are removed again after
      // the check: checking (--validate) leaves the disk as it was. A
      // symbolic link is not missing, even one that leads nowhere (it is
      // the user's: never removed).
      std::vector<fs::path> missing;
      fs::path              dir = fs::absolute(path, ec).lexically_normal();
      if (dir.filename().empty())
        dir = dir.parent_path();
      for (; !ec && dir.has_relative_path(); dir = dir.parent_path())
        {
          std::error_code not_found; // (set for a missing path: not an error)
          if (fs::exists(fs::symlink_status(dir, not_found)))
            break;
          missing.push_back(dir);
        }
      for (fs::path link = fs::absolute(path, ec).lexically_normal();
           !ec && link.has_relative_path();
           link = link.parent_path())
        {
          std::error_code link_ec, target_ec;
          if (fs::is_symlink(fs::symlink_status(link, link_ec)) &&
              !fs::exists(fs::status(link, target_ec)))
            return name + "<" + link.string() +
                   "> is a symbolic link to nothing (its target is missing, "
                   "or the links loop): " +
                   (target_ec ? target_ec.message() : "not found") +
                   "; fix the link or choose another directory";
        }
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



    /// "" if the manifest @p manifest is absent or a regular file, else why
    /// not: a run writes it, and must not write through a link or into a
    /// directory.
    std::string
    manifest_problem(const std::string &manifest)
    {
      std::error_code ec;
      const auto      status = fs::symlink_status(manifest, ec);
      if (!fs::exists(status) || fs::is_regular_file(status))
        return "";
      return "Output directory: <" + manifest + "> is " +
             (fs::is_symlink(status)   ? "a symbolic link" :
              fs::is_directory(status) ? "a directory" :
                                         "not a regular file") +
             ", not a manifest a run wrote; remove it or choose another "
             "directory";
    }



    /// The plain names the manifest @p manifest lists: never a path leading
    /// out of the directory (CRLF line ends tolerated).
    std::vector<std::string>
    listed_names(const std::string &manifest)
    {
      std::vector<std::string> names;
      std::ifstream            in(manifest);
      std::string              name;
      while (std::getline(in, name))
        {
          if (!name.empty() && name.back() == '\r')
            name.pop_back();
          if (name.empty() || name[0] == '#' ||
              name.find('/') != std::string::npos || name == "." ||
              name == "..")
            continue;
          names.push_back(name);
        }
      return names;
    }



    /**
     * Why the run cannot write into the existing directory @p path ("" if
     * it can): a file with a name the run writes that no earlier run listed
     * in the manifest is the user's and would be overwritten; one that is a
     * symbolic link would be written through, outside the directory.
     */
    std::string
    foreign_file_problem(const std::string &path, const std::string &manifest)
    {
      std::string     problem = manifest_problem(manifest);
      std::error_code ec;
      if (!problem.empty() || !fs::is_directory(path, ec))
        return problem;
      // parameters.prm, statistics.csv, solution.pvd, contact-CC.csv,
      // solution-CC.vtu, solution-CC.pvtu, solution-CC.RRR.vtu, and those
      // of the load steps: load-steps.csv, steps-CC.pvd, contact-CC-SS.csv,
      // solution-CC-SS.vtu, solution-CC-SS.pvtu, solution-CC-SS.RRR.vtu
      static const std::regex output_name(
        "parameters\\.prm|statistics\\.csv|solution\\.pvd|"
        "load-steps\\.csv|steps-[0-9]{2,}\\.pvd|"
        "contact-[0-9]{2,}(-[0-9]+)?\\.csv|"
        "solution-[0-9]{2,}(-[0-9]+)?(\\.pvtu|(\\.[0-9]{3,})?\\.vtu)");
      const auto            names = listed_names(manifest);
      std::set<std::string> listed(names.begin(), names.end());
      std::set<std::string> links, foreign; // sorted: the first is named
      for (fs::directory_iterator entry(path, ec), end; !ec && entry != end;
           entry.increment(ec))
        {
          const std::string name = entry->path().filename().string();
          if (!std::regex_match(name, output_name))
            continue;
          if (entry->is_symlink(ec))
            links.insert(name);
          else if (listed.count(name) == 0)
            foreign.insert(name);
        }
      const auto others = [](const std::set<std::string> &names) {
        return names.size() > 1 ?
                 " (and " + std::to_string(names.size() - 1) + " more)" :
                 std::string();
      };
      const std::string name = "Output directory: <" + path + "> holds ";
      if (!links.empty())
        return name + *links.begin() + others(links) +
               ", a symbolic link the run would write through; choose another "
               "directory or remove it";
      if (!foreign.empty())
        return name + *foreign.begin() + others(foreign) +
               ", which no earlier run listed in " +
               OutputDirectory::manifest_name +
               "; choose another directory or remove it";
      return "";
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
    std::string problem;
    if (root)
      {
        problem = directory_problem(path);
        if (problem.empty())
          problem = foreign_file_problem(path, path_of(manifest_name));
      }
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
    // (checked at initialize(); again here, right before it is written)
    if (const std::string problem = manifest_problem(manifest);
        !problem.empty())
      throw InputError(problem);
    for (const auto &name : listed_names(manifest))
      {
        const std::string file   = path_of(name);
        const auto        status = fs::symlink_status(file, ec);
        if ((fs::is_regular_file(status) || fs::is_symlink(status)) &&
            !fs::remove(file, ec))
          throw InputError("Output directory: cannot delete <" + file +
                           "> of the previous run: " + ec.message());
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
