// Reading a deck: InputError, the checks of entries and of the output directory, the parsers of id lists and maps, numbers for messages.
#include <dieflow/base/processes.h>
#include <dieflow/base/parameters.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace dieflow
{
  void
  check_output_directory(const std::string &directory)
  {
    // Found now, not when the first result is written after a long solve.
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    require(!error,
            "Output directory",
            "cannot create '" + directory + "': " + error.message());
    require(std::filesystem::is_directory(directory, error),
            "Output directory",
            "'" + directory + "' is not a directory");
    // One probe per process: processes started together test the same directory.
    const std::filesystem::path probe =
      std::filesystem::path(directory) / (".dieflow-write-check" + std::to_string(processes::rank()));
    const bool                  writable = static_cast<bool>(std::ofstream(probe));
    std::filesystem::remove(probe, error);
    require(writable, "Output directory", "cannot write in '" + directory + "' (read-only or no permission)");
  }



  std::string
  one_of_changes(const std::vector<std::string> &changes, const std::string &otherwise)
  {
    if (changes.empty())
      return otherwise;
    std::string text = changes.front();
    for (unsigned int i = 1; i < changes.size(); ++i)
      text += ", or " + changes[i];
    return text;
  }



  std::string
  deck_number(const double x)
  {
    const double exponent = std::round(std::log10(x));
    if (x > 0 && std::abs(exponent) >= 3 && std::abs(x - std::pow(10., exponent)) <= 1e-12 * x)
      return "1e" + std::to_string(static_cast<int>(exponent));
    std::ostringstream s;
    s << std::setprecision(3) << x;
    return s.str();
  }



  std::set<BoundaryId>
  parse_id_list(const std::string &entry, const std::string &text)
  {
    std::set<BoundaryId> ids;
    for (const std::string &item : dealii::Utilities::split_string_list(text, ','))
      {
        if (item.empty())
          continue;
        char *     end   = nullptr;
        const long value = std::strtol(item.c_str(), &end, 10);
        require(end != item.c_str() && *end == '\0' && value >= 0 &&
                  value < static_cast<long>(dealii::numbers::internal_face_boundary_id),
                entry,
                "'" + item + "' is not a boundary id (a whole number from 0 to 254)");
        require(ids.insert(static_cast<BoundaryId>(value)).second,
                entry,
                "boundary id " + item + " is listed twice");
      }
    return ids;
  }



  std::vector<std::pair<BoundaryId, std::string>>
  parse_id_text_map(const std::string &entry, const std::string &text)
  {
    std::vector<std::pair<BoundaryId, std::string>> result;
    for (const std::string &item : dealii::Utilities::split_string_list(text, ','))
      {
        if (item.empty())
          continue;
        const auto parts = dealii::Utilities::split_string_list(item, ':');
        require(parts.size() == 2 && !parts[1].empty(),
                entry,
                "'" + item + "' is not of the form 'id: value'");
        const auto id = parse_id_list(entry, parts[0]);
        require(id.size() == 1, entry, "'" + item + "' names no boundary id");
        for (const auto &p : result)
          require(p.first != *id.begin(),
                  entry,
                  "boundary id " + parts[0] + " is listed twice");
        result.emplace_back(*id.begin(), parts[1]);
      }
    return result;
  }



  std::vector<std::pair<BoundaryId, double>>
  parse_id_value_map(const std::string &entry, const std::string &text)
  {
    std::vector<std::pair<BoundaryId, double>> result;
    for (const auto &[id, text_value] : parse_id_text_map(entry, text))
      {
        char *       end   = nullptr;
        const double value = std::strtod(text_value.c_str(), &end);
        require(end != text_value.c_str() && *end == '\0' && std::isfinite(value),
                entry,
                "'" + text_value + "' is not a number");
        result.emplace_back(id, value);
      }
    return result;
  }



  double
  get_positive(const ParameterHandler &prm, const std::string &subsection, const std::string &entry)
  {
    const double value = prm.get_double(entry);
    require(std::isfinite(value) && value > 0, subsection + entry, "must be positive, got " + prm.get(entry));
    return value;
  }



  std::string
  one_line_message(const std::exception &exc)
  {
    std::string text;
    if (const auto *deal_exc = dynamic_cast<const dealii::ExceptionBase *>(&exc))
      {
        // print_info() gives the reason without deal.II's stack trace and
        // source location, which mean nothing to a user of the program.
        std::ostringstream reason;
        deal_exc->print_info(reason);
        text = reason.str();
      }
    else
      text = exc.what();

    // One line: fold white space, drop deal.II's decorations.
    std::string folded;
    bool        in_space = true;
    for (const char c : text)
      if (std::isspace(static_cast<unsigned char>(c)))
        {
          if (!in_space)
            folded += ' ';
          in_space = true;
        }
      else
        {
          folded += c;
          in_space = false;
        }
    while (!folded.empty() && folded.back() == ' ')
      folded.pop_back();
    for (const std::string prefix : {"Additional information: ", "Additional information:"})
      if (folded.rfind(prefix, 0) == 0)
        folded.erase(0, prefix.size());
    return folded;
  }
} // namespace dieflow
