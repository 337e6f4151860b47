#ifndef signorini_output_directory_h
#define signorini_output_directory_h

#include <deal.II/base/mpi.h>

#include <functional>
#include <ostream>
#include <set>
#include <string>

namespace Signorini
{
  /**
   * The directory of the results of one run. A run owns the files it writes
   * there and only those: each is listed in the manifest
   * `.signorini-manifest` before it is written, and the next run into the
   * same directory deletes exactly the files listed (plain names, never a
   * path leading elsewhere) before it writes anything. So a directory never
   * mixes two runs (a failing run with fewer cycles would otherwise leave
   * the later cycles of an earlier run beside its own), files the user keeps
   * there are left alone, and the outputs of the completed cycles of a run
   * that fails later stay. A directory holding a file with a name the run
   * writes that the manifest does not list (the user's own, or an older
   * version's, which kept no manifest), or such a name as a symbolic link,
   * or a manifest that is not a regular file, is refused: the run would
   * overwrite a file it does not own or write outside the directory.
   *
   * Under MPI, rank 0 keeps the manifest and writes the shared files; it
   * lists the pieces the other ranks write (see record()).
   */
  class OutputDirectory
  {
  public:
    /// The manifest's name inside the directory.
    static const std::string manifest_name;

    /**
     * Use the directory @p path: check, on rank 0 of @p comm with the
     * verdict shared by every rank, that it exists or can be created and
     * that a file can be created in it (a probe, removed again; directories
     * created for the check are removed too, so that --validate leaves the
     * disk as it was), and that it holds no file the run would overwrite
     * without owning it (see the class description). Throws an InputError
     * naming "Output directory" otherwise: an empty name, a regular file,
     * an unwritable parent or directory, a foreign file or link.
     */
    void
    initialize(const std::string &path, const MPI_Comm comm);

    /// Create the directory, delete the files of the previous run listed in
    /// its manifest and start an empty one (rank 0; no-op elsewhere).
    void
    start_run();

    /// List @p name in the manifest (rank 0; no-op elsewhere), for a file
    /// that is about to be written, possibly by another rank.
    void
    record(const std::string &name);

    /**
     * Write the file @p name: list it, open it, let @p write fill it and
     * close it. Throws std::runtime_error naming the file if it cannot be
     * opened or written (a full disk: a failed computation). Any rank may
     * write its own files; their names must have been recorded by rank 0.
     */
    void
    write(const std::string                         &name,
          const std::function<void(std::ostream &)> &write);

    /// The path of the file @p name of the directory.
    std::string
    path_of(const std::string &name) const;

  private:
    std::string           directory;
    bool                  root = true;
    std::set<std::string> listed; // names in the manifest
  };
} // namespace Signorini

#endif
