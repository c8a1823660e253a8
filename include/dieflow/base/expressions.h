// The deck's functions as muparser text: vector-valued expressions in x, y (and z) with named constants, errors naming the entry.
#ifndef dieflow_expressions_h
#define dieflow_expressions_h

#include <dieflow/base/parameters.h>

#include <deal.II/base/function_parser.h>

#include <map>
#include <memory>
#include <string>

namespace dieflow
{
  /**
   * A vector-valued function the deck gives as muparser text: components
   * separated by ';' ("190; 0"), in the variables x, y (and z in 3D), with
   * named constants "a=1, b=2". Errors name the deck entry. @p n_components:
   * 0 for dim (a velocity), 1 for a scalar (a temperature).
   */
  template <int dim>
  std::unique_ptr<dealii::FunctionParser<dim>>
  parse_vector_expression(const std::string &entry,
                          const std::string &expression,
                          const std::string &constants,
                          const unsigned int n_components = 0);

  /// Parses "name=value, name=value" into a map; errors name the entry.
  std::map<std::string, double>
  parse_constants(const std::string &entry, const std::string &text);
} // namespace dieflow

#endif
