// The fuzz corpus of the suite: decks drawn from fixed seeds, run through
// the command line in this process, judged by what a user's script sees
// (the exit status, the lines on stderr, summary.json).
#ifndef dieflow_tests_fuzz_h
#define dieflow_tests_fuzz_h

#include <dieflow/problem/run.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fuzz
{
  /**
   * Draws from std::mt19937, whose sequence the C++ standard fixes (its
   * distributions it does not), so every machine draws the same corpus.
   */
  class Draw
  {
  public:
    explicit Draw(const unsigned int seed)
      : generator(seed)
    {}

    /// Uniform in [a, b).
    double
    uniform(const double a, const double b)
    {
      return a + (b - a) * (generator() / 4294967296.);
    }

    /// Log-uniform in [a, b).
    double
    log_uniform(const double a, const double b)
    {
      return std::exp(uniform(std::log(a), std::log(b)));
    }

    /// Uniform in {a, ..., b}.
    unsigned int
    integer(const unsigned int a, const unsigned int b)
    {
      return a + generator() % (b - a + 1);
    }

    bool
    chance(const double p)
    {
      return uniform(0, 1) < p;
    }

  private:
    std::mt19937 generator;
  };

  /// What the command line did with a deck: exit status, stderr.
  struct Outcome
  {
    int         status = -1;
    std::string error;

    /// Exactly one line on stderr, the program's error line.
    bool
    one_error_line() const
    {
      return error.rfind("dieflow: error: ", 0) == 0 && error.find('\n') == error.size() - 1;
    }
  };

  /// Writes @p text to @p file and runs `dieflow file`, stdout swallowed.
  inline Outcome
  run(const std::string &file, const std::string &text)
  {
    std::ofstream(file, std::ios::binary) << text;
    std::string        name = "dieflow", argument = file;
    char *             argv[] = {name.data(), argument.data()};
    std::ostringstream out, err;
    std::streambuf *   cout_buffer = std::cout.rdbuf(out.rdbuf());
    std::streambuf *   cerr_buffer = std::cerr.rdbuf(err.rdbuf());
    Outcome            outcome;
    outcome.status = dieflow::run_command_line(2, argv);
    std::cout.rdbuf(cout_buffer);
    std::cerr.rdbuf(cerr_buffer);
    outcome.error = err.str();
    return outcome;
  }

  /// summary.json of @p directory read as JSON (throws if it is not JSON).
  inline boost::property_tree::ptree
  summary(const std::string &directory)
  {
    boost::property_tree::ptree tree;
    boost::property_tree::read_json(directory + "/summary.json", tree);
    return tree;
  }

  /// A finite number from a JSON value ("null", a non-finite value, is NaN).
  inline double
  number(const boost::property_tree::ptree &tree, const std::string &path)
  {
    const std::string text = tree.get<std::string>(boost::property_tree::ptree::path_type(path, '|'), "null");
    char *            end  = nullptr;
    const double      x    = std::strtod(text.c_str(), &end);
    return (end != text.c_str() && *end == '\0') ? x : std::nan("");
  }
  /// The rows of numbers of the text file @p file (a die profile, a table),
  /// its '#' comment lines skipped; none if there is no file.
  inline std::vector<std::vector<double>>
  numeric_rows(const std::string &file)
  {
    std::vector<std::vector<double>> rows;
    std::ifstream                    in(file);
    for (std::string line; std::getline(in, line);)
      if (!line.empty() && line[0] != '#')
        {
          std::istringstream  fields(line);
          std::vector<double> row;
          for (double x; fields >> x;)
            row.push_back(x);
          rows.push_back(row);
        }
    return rows;
  }
  /**
   * The largest breach of Coulomb's law with coefficient @p mu (relative
   * to the largest pressure or speed) in a die profile file written by a
   * run (columns 4-8: p, tau, v_n, v_t, status 0 separated, 1 stick, 2
   * slip): no penetration; in contact no pull and |tau| <= mu p; sticking
   * nodes at rest; slipping ones on the cone against their slip. 1 for a
   * file without rows.
   */
  inline double
  coulomb_breach(const std::string &file, const double mu)
  {
    std::vector<std::vector<double>> rows;
    for (const auto &row : numeric_rows(file))
      if (row.size() >= 8)
        rows.push_back(row);
    if (rows.empty())
      return 1;
    double p_max = 0, v_max = 0;
    for (const auto &r : rows)
      {
        p_max = std::max(p_max, std::abs(r[3]));
        v_max = std::max({v_max, std::abs(r[5]), std::abs(r[6])});
      }
    double breach = 0;
    for (const auto &r : rows)
      {
        const double p = r[3], tau = r[4], v_n = r[5], v_t = r[6];
        const int    status = static_cast<int>(r[7]);
        breach              = std::max(breach, v_n / v_max); // no penetration
        if (status == 0)
          continue;
        breach = std::max(breach, -p / p_max);                       // no pull
        breach = std::max(breach, (std::abs(tau) - mu * p) / p_max); // within the cone
        if (status == 1)
          breach = std::max(breach, std::abs(v_t) / v_max); // sticking at rest
        else
          {
            breach = std::max(breach, std::abs(std::abs(tau) - mu * p) / p_max); // on the cone
            breach = std::max(breach, tau * v_t > 0 ? 1. : 0.);                   // against the slip
          }
      }
    return breach;
  }
} // namespace fuzz

#endif
