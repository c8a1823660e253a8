// The MPI processes of a run: who this one is, which cells it assembles, and the sums that keep the replicated state the same bits on every process.
#ifndef dieflow_processes_h
#define dieflow_processes_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/types.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <mpi.h>

#include <ostream>
#include <utility>
#include <vector>

namespace dieflow
{
  /**
   * A run on P processes (doc/parallel.md). Every process holds the whole
   * mesh and the whole state (the velocity, the contact set, the free
   * surface, the report's fields), and runs the same algorithm on it; what
   * is divided is the expensive part of a Newton iteration:
   *  - the flow's cell terms (FlowAssembler): each process assembles the
   *    cells of its METIS part (partition()), and the partial systems are
   *    summed: the right-hand side whole on every process (sum()), the
   *    matrix only in each process's own rows (sum_own_rows()), the only
   *    ones its readers (the products, the direct and iterative solvers'
   *    copies, the round-off bound) read;
   *  - the linear solve: the direct solver factorises across processes
   *    (MUMPS, DistributedDirectSolver), each owning a block of rows; the
   *    iterative solvers multiply by blocks of rows (RowBlockMatrix, ML
   *    across processes), the results gathered.
   * Every sum is formed once, each entry on one process (a P-th of them
   * on each), and gathered from there (but the matrix's), so every process
   * holds the same bits and takes the same decisions (a contact state, a
   * line-search step, the end of a cycle) without further communication.
   * Only the first process writes files and the log.
   *
   * With one process (the default, no launcher) none of this runs, and MPI
   * is not initialised (the iterative solver's Trilinos initialises it on
   * first use).
   */
  namespace processes
  {
    /// How many processes a launcher started, and this one's rank, from its
    /// environment (Open MPI's mpirun, MPICH's Hydra, Slurm's srun); {1, 0} when none did.
    std::pair<unsigned int, unsigned int>
    launched();

    /// The processes on this machine (Open MPI's or MPICH's local size; else launched()'s).
    unsigned int
    on_this_machine();

    /**
     * MPI and PETSc for the lifetime of a run on more than one process:
     * MPI_Init_thread (threads call no MPI: funnelled), PETSc without its
     * signal handlers (the program's own SIGINT/SIGTERM handling stays);
     * finalised in reverse order. With one process it does nothing.
     */
    class Session
    {
    public:
      Session();
      ~Session();
      Session(const Session &) = delete;
      Session &
      operator=(const Session &) = delete;

    private:
      bool started = false;
    };

    /// The processes of this run (1 without a Session), and this one's rank.
    unsigned int
    n();
    unsigned int
    rank();

    /// Whether this process writes the files and the log (the first).
    bool
    writes_output();

    /// A stream that takes everything and writes nothing, its state good
    /// (what the other processes write their files and log to).
    std::ostream &
    null_stream();

    /// The run's communicator (MPI_COMM_WORLD).
    MPI_Comm
    communicator();

    /// Sums over the processes, the result the same bits on every process.
    void
    sum(dealii::Vector<double> &v);
    void
    sum(dealii::SparseMatrix<double> &matrix);
    void
    sum(std::vector<double> &v);

    /**
     * Sums @p matrix over the processes in this process's rows
     * (owned_rows(matrix.m())), each row's sum formed on its owner alone;
     * the other rows are set to NaN, so that a reader of rows not its own
     * fails at once instead of computing with partial sums. Half the
     * traffic of sum(), and no process receives the whole matrix.
     */
    void
    sum_own_rows(dealii::SparseMatrix<double> &matrix);

    /// The values of @p matrix as one array in its pattern's order (the
    /// entry of linear index k at [k]); null for a matrix without entries.
    const double *
    matrix_values(const dealii::SparseMatrix<double> &matrix);

    /**
     * Throws std::logic_error naming @p where unless every process holds
     * the same bits of @p v (a hash of them compared across processes).
     * The replicated state must be the same everywhere: processes that
     * disagreed would take different decisions and wait in different
     * collectives for ever; this ends the run instead (run.cc aborts it).
     */
    void
    require_same(const dealii::Vector<double> &v, const char *where);

    /// The rows of an @p n x @p n system this process owns in a distributed
    /// solve: a contiguous block, [n r / P, n (r + 1) / P) on process r,
    /// its ends rounded down to multiples of @p block (@p n one itself).
    dealii::IndexSet
    owned_rows(const dealii::types::global_dof_index n, const unsigned int block = 1);

    /// Where each process holds the entries of its owned_rows(v.size(),
    /// @p block) in @p v, gives every process all of them (the same bits
    /// everywhere).
    void
    gather(dealii::Vector<double> &v, const unsigned int block = 1);

    /**
     * Divides the active cells among the processes with METIS (on the
     * first process, broadcast, so the parts agree), as their subdomain
     * ids. With one process, every cell is in part 0.
     */
    template <int dim>
    void
    partition(dealii::Triangulation<dim> &triangulation);

    /// Whether this process assembles @p cell (its part).
    template <typename CellIterator>
    bool
    owns(const CellIterator &cell)
    {
      return n() == 1 || cell->subdomain_id() == rank();
    }
  } // namespace processes
} // namespace dieflow

#endif
