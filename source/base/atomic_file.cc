// An output file that a reader sees whole or not at all: written under PATH.partial and renamed to PATH when complete.
#include <dieflow/base/atomic_file.h>
#include <dieflow/base/parameters.h>
#include <dieflow/base/processes.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace dieflow
{
  std::ofstream
  output_stream(const std::string &path)
  {
    std::ofstream out(path);
    require(static_cast<bool>(out), "Output directory", "cannot write '" + path + "' (a folder of that name, or no room)");
    return out;
  }



  AtomicFile::AtomicFile(const std::string &path)
    : path(path)
    , partial(path + ".partial")
  {
    // On more than one process the first writes the files; the others'
    // streams take nothing (processes.h).
    if (processes::writes_output())
      out.open(partial);
    else
      committed = true;
  }



  std::ostream &
  AtomicFile::stream()
  {
    return processes::writes_output() ? static_cast<std::ostream &>(out) : processes::null_stream();
  }



  AtomicFile::~AtomicFile()
  {
    if (!committed)
      {
        out.close();
        std::error_code ignored;
        std::filesystem::remove(partial, ignored);
      }
  }



  void
  AtomicFile::commit()
  {
    if (!processes::writes_output())
      return;
    out.close();
    std::error_code error;
    if (!out)
      throw std::runtime_error("cannot write '" + path + "' (disk full, or the directory went away)");
    std::filesystem::rename(partial, path, error);
    if (error)
      throw std::runtime_error("cannot rename '" + partial + "' to '" + path + "': " + error.message());
    committed = true;
  }
} // namespace dieflow
