// The mesh study of a run: a row per cycle, and the Richardson extrapolation and error estimates of the quantities of interest.
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
    /**
     * The estimated error of the last value Q_k (not of Q*), meant to bound
     * the true error: the last change continued as a sequence converging
     * like N^-p would continue it,
     *   |Q_k - Q_{k-1}| / ((N_k / N_{k-1})^p - 1),  p = min(1/2, observed p),
     * and with the larger of the last two changes when the last three values
     * do not converge monotonically. Why 1/2: the observed order of an
     * adaptive sequence jumps from cycle to cycle (doc/benchmarks.md), so
     * Q* may sit on either side of the truth, whereas the error
     * of a functional such as a boundary force falls at least as fast as the
     * energy-norm error, N^-1/2 for optimal Q1 meshes in 2D (uniform
     * refinement of a smooth solution: the estimate is three times the
     * true error). Measured honest for the die2d N1 and P1 forces from
     * settled starts (doc/benchmarks.md); not for point values, which need
     * not converge monotonically (doc/user-guide.md). Zero with fewer than
     * two cycles.
     */
    double estimate = 0;
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
