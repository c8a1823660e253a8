// An output file that a reader sees whole or not at all: written under PATH.partial and renamed to PATH when complete.
#ifndef dieflow_atomic_file_h
#define dieflow_atomic_file_h

#include <fstream>
#include <string>

namespace dieflow
{
  /**
   * An output file that a reader sees whole or not at all: written under
   * the name PATH.partial and renamed to PATH by commit() (rename is atomic
   * within a directory), so a run killed while writing leaves the previous
   * complete file, never a truncated one. Without commit() (an exception on
   * the way) the partial file is removed.
   */
  class AtomicFile
  {
  public:
    explicit AtomicFile(const std::string &path);
    ~AtomicFile();
    AtomicFile(const AtomicFile &) = delete;
    AtomicFile &
    operator=(const AtomicFile &) = delete;

    /// The file's stream; on an MPI process other than the first, one that writes nothing (processes.h).
    std::ostream &
    stream();

    /// Closes the file and renames it into place; a std::runtime_error
    /// naming the file if it could not be written.
    void
    commit();

  private:
    std::string   path;
    std::string   partial;
    std::ofstream out;
    bool          committed = false;
  };
} // namespace dieflow

#endif
