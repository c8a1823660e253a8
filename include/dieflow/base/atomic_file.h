// An output file that a reader sees whole or not at all: written under PATH.partial and renamed to PATH when complete.
#ifndef dieflow_atomic_file_h
#define dieflow_atomic_file_h

#include <fstream>
#include <string>

namespace dieflow
{
  /**
   * A stream to @p path for a file written whole at once whose reader is
   * told of it later (a .vtu piece, listed by the .pvtu and .pvd written
   * after it); an InputError naming Output directory and the file where it
   * cannot be opened (on several processes each writes its own piece).
   */
  std::ofstream
  output_stream(const std::string &path);



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
