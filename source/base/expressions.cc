// The deck's functions as muparser text: vector-valued expressions in x, y (and z) with named constants, errors naming the entry.
#include <dieflow/base/expressions.h>

#include <deal.II/base/utilities.h>
#include <deal.II/lac/vector.h>

#include <cmath>
#include <iostream>
#include <sstream>

namespace dieflow
{
  std::map<std::string, double>
  parse_constants(const std::string &entry, const std::string &text)
  {
    std::map<std::string, double> constants;
    for (const auto &item : dealii::Utilities::split_string_list(text, ','))
      {
        if (item.empty())
          continue;
        const auto parts = dealii::Utilities::split_string_list(item, '=');
        require(parts.size() == 2 && !parts[0].empty(),
                entry,
                "'" + item + "' is not of the form 'name=value'");
        char *       end   = nullptr;
        const double value = std::strtod(parts[1].c_str(), &end);
        require(end != parts[1].c_str() && *end == '\0' && std::isfinite(value),
                entry,
                "the value of constant '" + parts[0] + "' is not a finite number");
        constants[parts[0]] = value;
      }
    return constants;
  }



  namespace
  {
    /// The parser's own words from deal.II's ExcParseError.
    std::string
    muparser_reason(const std::exception &exc)
    {
      const std::string text = one_line_message(exc);
      const auto        said = text.find("The parser said: ");
      return said == std::string::npos ? text : text.substr(said + 17);
    }
  } // namespace



  template <int dim>
  std::unique_ptr<dealii::FunctionParser<dim>>
  parse_vector_expression(const std::string &entry,
                          const std::string &expression,
                          const std::string &constants_text,
                          const unsigned int n_components)
  {
    const unsigned int n          = n_components == 0 ? dim : n_components;
    const auto         components = dealii::Utilities::split_string_list(expression, ';');
    if (n == 1)
      require(components.size() == 1, entry, "'" + expression + "' must be one expression (no ';')");
    require(components.size() == n,
            entry,
            "'" + expression + "' has " + std::to_string(components.size()) +
              " components separated by ';', but Dimension = " +
              std::to_string(dim) + " needs " + std::to_string(dim));
    auto constants = parse_constants(entry, constants_text);
    constants.emplace("pi", dealii::numbers::PI);

    auto function = std::make_unique<dealii::FunctionParser<dim>>(n);
    // deal.II's muparser wrapper writes the parser's complaint to std::cerr
    // before throwing; the user gets the one-line message below instead.
    std::ostringstream muted;
    std::streambuf *   cerr_buffer = std::cerr.rdbuf(muted.rdbuf());
    try
      {
        function->initialize(dim == 2 ? "x,y" : "x,y,z", components, constants);
        // muparser compiles lazily: evaluate once so that syntax errors and
        // unknown names surface here, while the entry is known.
        dealii::Vector<double> probe(n);
        function->vector_value(dealii::Point<dim>(), probe);
      }
    catch (const std::exception &exc)
      {
        std::cerr.rdbuf(cerr_buffer);
        throw InputError(entry + ": cannot parse '" + expression + "': " + muparser_reason(exc));
      }
    std::cerr.rdbuf(cerr_buffer);
    return function;
  }

  template std::unique_ptr<dealii::FunctionParser<2>>
  parse_vector_expression<2>(const std::string &, const std::string &, const std::string &, const unsigned int);
  template std::unique_ptr<dealii::FunctionParser<3>>
  parse_vector_expression<3>(const std::string &, const std::string &, const std::string &, const unsigned int);
} // namespace dieflow
