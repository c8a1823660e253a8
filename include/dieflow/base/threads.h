// How many threads the assembly runs on, with deal.II's arithmetic fixed to one width so that the results do not depend on it.
#ifndef dieflow_threads_h
#define dieflow_threads_h

namespace dieflow
{
  /**
   * How many threads the assembly (deal.II's WorkStream: flow cells,
   * residuals, the mixed form's blocks, Kelly) runs on, such that the
   * results do not depend on it, bit for bit.
   *
   * deal.II 9.4 lets its thread count change the arithmetic in two places:
   * FEValues reuses the previous cell's Jacobians for a translated cell
   * only when it runs on one thread (FEValuesBase::check_cell_similarity),
   * and vector reductions of more than 16,384 entries sum 4 x n_threads()
   * partial sums. With WorkStream's copier adding the cells' contributions
   * in cell order, those are the only dependences. So deal.II is told a
   * fixed count (arithmetic_width: its reductions and FEValues behave as
   * for that many threads whatever runs), and TBB's own limit
   * (tbb::global_control) sets how many threads actually run.
   */
  namespace threads
  {
    /// The thread count deal.II's arithmetic is fixed to.
    constexpr unsigned int arithmetic_width = 64;

    /// The threads requested: DEAL_II_NUM_THREADS if set (a positive integer), else every core.
    unsigned int
    requested();

    /**
     * Runs the following work on @p n threads (at most arithmetic_width),
     * with the arithmetic of arithmetic_width threads. Removes
     * DEAL_II_NUM_THREADS from the environment, which deal.II would
     * otherwise apply to its count.
     */
    void
    use(const unsigned int n);

    /// The threads that actually run (the last use()).
    unsigned int
    running();
  } // namespace threads
} // namespace dieflow

#endif
