// Fuzz corpus, part 1: every deck of parameters/ and tests/ (but the bad_
// ones), mutated in one of seven ways that each make it wrong, drawn from
// a fixed seed: a numeric value replaced by a token no numeric entry takes,
// an entry or subsection name misspelt, a subsection or end line deleted or
// duplicated, an entry set twice, a line truncated inside its name (the
// rest of the file lost), a byte that is not text inserted. Every mutated
// deck must end with exit status 1 and one line on stderr, at once (no
// solve): never a crash, an internal error, or a run.
#include "fuzz.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

namespace
{
  std::vector<std::string>
  split_lines(const std::string &text)
  {
    std::vector<std::string> lines;
    std::istringstream       in(text);
    for (std::string line; std::getline(in, line);)
      lines.push_back(line);
    return lines;
  }

  std::string
  join(const std::vector<std::string> &lines)
  {
    std::string text;
    for (const auto &line : lines)
      text += line + '\n';
    return text;
  }

  std::string
  trim(const std::string &s)
  {
    const auto a = s.find_first_not_of(" \t");
    return a == std::string::npos ? "" : s.substr(a, s.find_last_not_of(" \t") - a + 1);
  }

  bool
  starts_with(const std::string &line, const std::string &word)
  {
    return trim(line).rfind(word, 0) == 0;
  }

  /// The deck as dieflow reads it: without the test driver's "subsection
  /// Test", a relative Gmsh file made absolute, results in fuzz-mutated/.
  std::vector<std::string>
  prepared(const std::filesystem::path &deck)
  {
    std::ifstream      in(deck);
    std::ostringstream text;
    text << in.rdbuf();
    std::vector<std::string> kept;
    int                      depth = 0, skip_depth = -1;
    for (const auto &line : split_lines(text.str()))
      {
        const std::string t = trim(line.substr(0, line.find('#')));
        if (t.rfind("subsection ", 0) == 0)
          {
            if (depth == 0 && trim(t.substr(11)) == "Test")
              skip_depth = 0;
            ++depth;
          }
        else if (t == "end")
          {
            --depth;
            if (skip_depth == depth)
              {
                skip_depth = -1;
                continue;
              }
          }
        if (skip_depth >= 0)
          continue;
        // Results (of a mutation that the program might accept) away from
        // the test harness's own file named "output".
        if (depth == 0 && t.rfind("set Output directory", 0) == 0)
          {
            kept.push_back("set Output directory = fuzz-mutated");
            continue;
          }
        const auto at = line.find("Gmsh file");
        if (at != std::string::npos && line.find('=') != std::string::npos)
          {
            const std::string file = trim(line.substr(line.find('=') + 1));
            if (!file.empty() && file[0] != '/')
              {
                kept.push_back(line.substr(0, line.find('=') + 1) + " " + (deck.parent_path() / file).string());
                continue;
              }
          }
        kept.push_back(line);
      }
    return kept;
  }

  /// Indices of the lines for which @p take holds.
  template <typename Predicate>
  std::vector<unsigned int>
  lines_where(const std::vector<std::string> &lines, const Predicate &take)
  {
    std::vector<unsigned int> indices;
    for (unsigned int i = 0; i < lines.size(); ++i)
      if (take(lines[i]))
        indices.push_back(i);
    return indices;
  }

  bool
  is_set(const std::string &line)
  {
    return starts_with(line, "set ") && line.find('=') != std::string::npos && line.find('#') == std::string::npos &&
           line.back() != '\\';
  }

  /// The value of a set line parses whole as a number.
  bool
  numeric_value(const std::string &line)
  {
    if (!is_set(line))
      return false;
    const std::string value = trim(line.substr(line.find('=') + 1));
    char *            end   = nullptr;
    std::strtod(value.c_str(), &end);
    return !value.empty() && *end == '\0';
  }

  const std::vector<std::string> kinds = {"bad numeric value", "misspelt entry",  "misspelt subsection",
                                          "structure line deleted", "structure line duplicated",
                                          "entry set twice", "line truncated in its name", "byte not text"};

  /// The mutated deck, or "" when @p lines offers nothing to mutate this way.
  std::string
  mutate(std::vector<std::string> lines, const unsigned int kind, fuzz::Draw &draw)
  {
    const auto structure = [](const std::string &l) { return starts_with(l, "subsection ") || trim(l) == "end"; };
    std::vector<unsigned int> where;
    switch (kind)
      {
        case 0:
          where = lines_where(lines, numeric_value);
          break;
        case 1:
        case 5:
        case 6:
          where = lines_where(lines, is_set);
          break;
        case 2:
          where = lines_where(lines, [](const std::string &l) { return starts_with(l, "subsection "); });
          break;
        case 3:
        case 4:
          where = lines_where(lines, structure);
          break;
        default:
          where.resize(lines.size());
          for (unsigned int i = 0; i < lines.size(); ++i)
            where[i] = i;
      }
    if (where.empty())
      return "";
    const unsigned int i    = where[draw.integer(0, where.size() - 1)];
    std::string &      line = lines[i];
    const auto         equals = line.find('=');
    switch (kind)
      {
        case 0:
          {
            static const std::vector<std::string> tokens = {"abc", "1e999", "nan", "--1", "1..5", "0x1p", "1e", "inf"};
            line = line.substr(0, equals + 1) + " " + tokens[draw.integer(0, tokens.size() - 1)];
            break;
          }
        case 1:
          {
            // A letter of the name replaced by 'q' (no entry name has a q
            // after its first letter... the check below would show it).
            const auto first = line.find_first_not_of(' ', line.find("set") + 3);
            const auto last  = line.find_last_not_of(' ', equals - 1);
            const auto at    = draw.integer(first + 1, last);
            line[at]         = (line[at] == 'q') ? 'z' : 'q';
            break;
          }
        case 2:
          line += "x";
          break;
        case 3:
          lines.erase(lines.begin() + i);
          break;
        case 4:
        case 5:
          lines.insert(lines.begin() + i, line);
          break;
        case 6:
          {
            // Cut inside the name: no '=' left; the rest of the file is lost.
            const auto first = line.find_first_not_of(' ', line.find("set") + 3);
            line             = line.substr(0, draw.integer(first, equals - 1));
            lines.resize(i + 1);
            return join(lines).substr(0, join(lines).size() - 1);
          }
        default:
          {
            static const std::vector<unsigned char> bytes = {0x00, 0x01, 0x07, 0x08, 0x0b, 0x0c, 0x1b, 0x1f,
                                                             0x7f, 0x80, 0xa0, 0xbf, 0xc3, 0xe2, 0xf0, 0xff};
            line.insert(draw.integer(0, line.size()), 1, static_cast<char>(bytes[draw.integer(0, bytes.size() - 1)]));
          }
      }
    return join(lines);
  }
} // namespace



int
main()
{
  std::set<std::filesystem::path> decks;
  for (const std::string folder : {"/../parameters", ""})
    for (const auto &entry : std::filesystem::directory_iterator(std::string(SOURCE_DIR) + folder))
      if (entry.path().extension() == ".prm" && entry.path().stem().string().rfind("bad_", 0) != 0)
        decks.insert(entry.path());
  std::vector<std::vector<std::string>> sources;
  std::vector<std::string>              names;
  for (const auto &deck : decks)
    {
      sources.push_back(prepared(deck));
      names.push_back(deck.filename().string());
    }

  fuzz::Draw                      draw(20261123);
  constexpr unsigned int          per_kind = 60;
  std::map<unsigned int, unsigned> made, passed;
  std::vector<std::string>         failures;
  for (unsigned int kind = 0; kind < kinds.size(); ++kind)
    while (made[kind] < per_kind)
      {
        const unsigned int source = draw.integer(0, sources.size() - 1);
        const std::string  text   = mutate(sources[source], kind, draw);
        if (text.empty())
          continue;
        ++made[kind];
        const fuzz::Outcome outcome = fuzz::run("mutated.prm", text);
        // FUZZ_SHOW=1 lists every deck's message on stderr, for a reader.
        if (std::getenv("FUZZ_SHOW"))
          std::cerr << kinds[kind] << " | " << outcome.error;
        if (outcome.status == 1 && outcome.one_error_line())
          ++passed[kind];
        else
          failures.push_back(kinds[kind] + " of " + names[source] + ": exit status " +
                             std::to_string(outcome.status) + ", stderr: " + outcome.error);
      }

  unsigned int total = 0, total_passed = 0;
  for (unsigned int kind = 0; kind < kinds.size(); ++kind)
    {
      std::cout << kinds[kind] << ": " << made[kind] << " decks, exit status 1 with one line: " << passed[kind]
                << std::endl;
      total += made[kind];
      total_passed += passed[kind];
    }
  // (How many decks they came from is not printed: a new test deck would
  // change this output.)
  std::cout << "every one of the " << total << " mutated decks exits 1 with one line: " << (total_passed == total ? "yes" : "NO") << std::endl;
  for (const auto &failure : failures)
    std::cout << "  " << failure << std::endl;
}
