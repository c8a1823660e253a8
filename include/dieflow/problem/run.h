// The program's command line: reading and checking a deck, running it, the one-line error messages, and the exit statuses.
#ifndef dieflow_run_h
#define dieflow_run_h

#include <dieflow/base/parameters.h>
#include <dieflow/postprocess/summary.h>

#include <functional>
#include <ostream>
#include <string>

namespace dieflow
{
  /// Exit statuses of the program (interface.md).
  enum ExitStatus
  {
    exit_converged     = 0,
    exit_bad_input     = 1,
    exit_not_converged = 2,
    exit_internal      = 3
  };

  /**
   * Reads a deck in two passes: the first (tolerating undeclared entries)
   * finds the dimension and the boundary ids that get subsections of their
   * own, the second declares those and reads the deck strictly. @p extra
   * declares further entries (the test driver's "Test" subsection).
   */
  void
  read_deck(const std::string &                            file_name,
            ParameterHandler &                             prm,
            const std::function<void(ParameterHandler &)> &extra = {});

  /**
   * What ParameterHandler does not check in a deck: that it is text (no
   * control byte, valid UTF-8, so a binary or truncated-by-corruption file
   * is named as such), and that no entry is set twice in the same
   * subsection (ParameterHandler would keep the last silently). An
   * InputError naming the line if not.
   */
  void
  check_deck_text(const std::string &file_name);

  /// Declares the default deck (die2d) for printing.
  void
  declare_default_deck(ParameterHandler &prm);

  /// Runs the deck read into @p prm (relative mesh files are relative to
  /// @p deck_directory), logging to @p log.
  RunSummary
  run_deck(ParameterHandler &prm, const std::string &deck_directory, std::ostream &log);

  /// The one-line message of an error met while reading the deck
  /// @p file_name, naming the deck by its file name.
  std::string
  deck_error_message(const std::exception &exc, const std::string &file_name);

  /// The command line of the program: returns the exit status.
  int
  run_command_line(int argc, char **argv);
} // namespace dieflow

#endif
