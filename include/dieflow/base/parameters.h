// Reading a deck: InputError, the checks of entries and of the output directory, the parsers of id lists and maps, numbers for messages.
#ifndef dieflow_parameters_h
#define dieflow_parameters_h


#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/types.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace dieflow
{
  using dealii::ParameterHandler;
  using BoundaryId = dealii::types::boundary_id;

  /**
   * Bad user input: a deck entry, a mesh, or data that contradict each other.
   * The message is one line that names the entry and says what is wrong; the
   * program prints it and exits with status 1.
   */
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// Creates @p directory if need be and checks that a file can be
  /// written in it; an InputError naming Output directory if not.
  void
  check_output_directory(const std::string &directory);

  /// "A, or B, or C" of the deck changes a message offers; @p otherwise
  /// when there is none.
  std::string
  one_of_changes(const std::vector<std::string> &changes, const std::string &otherwise);

  /// A number as a deck would write it: 1e7 for a power of ten from 1e3
  /// (or 1e-3) on, else three significant digits (for messages that name a
  /// setting).
  std::string
  deck_number(const double x);

  /**
   * Parses a comma-separated list of boundary ids ("3, 4"); the entry name
   * goes into the error message.
   */
  std::set<BoundaryId>
  parse_id_list(const std::string &entry, const std::string &text);

  /// 'id: text, id: text' (Contact/Die surfaces: a file per die id), each
  /// id once; what follows the colon is kept as written.
  std::vector<std::pair<BoundaryId, std::string>>
  parse_id_text_map(const std::string &entry, const std::string &text);

  /**
   * Parses a comma-separated list "id: value, id: value" of numbers per
   * boundary id, as used for friction coefficients.
   */
  std::vector<std::pair<BoundaryId, double>>
  parse_id_value_map(const std::string &entry, const std::string &text);

  /**
   * Turns any exception raised while reading a deck (deal.II's
   * ParameterHandler exceptions included) into one line of text.
   */
  std::string
  one_line_message(const std::exception &exc);

  /**
   * Throws InputError("ENTRY: REASON") unless @p condition holds.
   */
  inline void
  require(const bool condition, const std::string &entry, const std::string &reason)
  {
    if (!condition)
      throw InputError(entry + ": " + reason);
  }

  /**
   * The entry @p entry of the current subsection, which must be a finite
   * positive number; @p subsection ("Material/") names it in the error.
   */
  double
  get_positive(const ParameterHandler &prm, const std::string &subsection, const std::string &entry);
} // namespace dieflow

#endif
