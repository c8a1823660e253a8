#ifndef dieflow_study_h
#define dieflow_study_h

#include <dieflow/postprocess/summary.h>

#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace dieflow
{
  /**
   * Richardson-type extrapolation of a quantity Q from its values on a
   * sequence of meshes with N_k unknowns, assuming Q_k = Q* + C N_k^(-p):
   * the last three cycles fix p (by bisection on the ratio of the last two
   * differences, which need not come from a constant refinement ratio, as
   * adaptive meshes do not), C and Q*. The error of Q* is estimated as the
   * change of Q* from the previous triple of cycles where there is one, else
   * as |Q* - Q_k|. Without three monotonically converging values (an
   * oscillating or diverging sequence) there is no extrapolation: Q* is the
   * last value and its error the last change.
   */
  struct Extrapolation
  {
    double value = 0;
    double error = 0;
    double order = 0;
    bool   valid = false;
  };

  Extrapolation
  extrapolate(const std::vector<double> &unknowns, const std::vector<double> &values);

  /**
   * The mesh study of a run: a row per cycle (cells, dofs, nonlinear
   * iterations, wall time, the quantities of interest, the error estimate,
   * and the errors with their observed rates when the deck gives an exact
   * velocity), written with deal.II's ConvergenceTable, and the Richardson
   * estimates of the quantities of interest.
   */
  class StudyTable
  {
  public:
    void
    add(const CycleSummary &cycle);

    /// The table, then the extrapolated quantities.
    void
    write(std::ostream &out) const;

    /// The extrapolation of every quantity of interest.
    std::vector<std::pair<std::string, Extrapolation>>
    extrapolations() const;

  private:
    std::vector<CycleSummary> cycles;
  };
} // namespace dieflow

#endif
