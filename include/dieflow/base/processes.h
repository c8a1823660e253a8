// The MPI processes of a run: who this one is, which cells it assembles, and the sums that keep the replicated state the same bits on every process.
#ifndef dieflow_processes_h
#define dieflow_processes_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/types.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <mpi.h>

#include <cstdint>

#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace dieflow
{
  /**
   * A run on P processes (doc/parallel.md). Every process holds the whole
   * mesh (a parallel::shared::Triangulation, new_triangulation()) and the
   * whole state (the velocity, the contact set, the free surface, the
   * report's fields), and runs the same algorithm on it; what is divided
   * is the expensive part of a Newton iteration:
   *  - the flow's cell terms (FlowAssembler): each process assembles the
   *    cells of its METIS part (its cells on the shared mesh), whose dofs
   *    are numbered as one block, the rows it owns (own_rows_by_part()),
   *    and the partial systems
   *    are summed: the right-hand side whole on every process (sum()), the
   *    matrix only in each process's own rows (RowSums), the only ones its
   *    readers (the products, the direct and iterative solvers' copies, the
   *    round-off bound) read, and the only ones it stores whole;
   *  - the linear solve: the direct solver factorises across processes
   *    (MUMPS, DistributedDirectSolver), each owning a block of rows; the
   *    iterative solvers run on vectors divided among the processes
   *    (Trilinos's for degree 1; for the mixed form RowLayout, each product
   *    by each process's rows with the border's entries exchanged,
   *    RowBlockMatrix; ML across processes), the solution gathered.
   * Every sum is formed once, each entry on one process (a P-th of them
   * on each), and gathered from there (but the matrix's), so every process
   * holds the same bits and takes the same decisions (a contact state, a
   * line-search step, the end of a cycle) without further communication.
   * The exception: a distributed Krylov solve stops on norms all-reduced,
   * which MPI gives every process to the same bit; its solution is then
   * gathered, so the state stays the same bits.
   * Only the first process writes files and the log.
   *
   * deal.II's helpers that see only a process's own cells on a shared mesh
   * (cell->is_locally_owned()) would make the replicated state differ:
   * what needs the whole mesh goes through whole_mesh.h instead.
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
     * finalised in reverse order. Either, started before, is left to its
     * starter. With one process it does nothing.
     */
    class Session
    {
    public:
      Session();
      ~Session();
      Session(const Session &) = delete;
      Session &
      operator=(const Session &) = delete;

      /**
       * Empty where MPI sees the processes the launcher started; else the
       * one line that says they differ: a launcher of another MPI than the
       * one this program was built with (MPICH's mpiexec for a build with
       * Open MPI, say) starts P processes that each see themselves as the
       * only one, and would each run the whole deck into the same files.
       */
      const std::string &
      launch_error() const;

    private:
      bool started = false;
      /// Whether this Session started MPI and PETSc (and so ends them).
      bool        owns_mpi = false, owns_petsc = false;
      std::string mismatch;
    };

    /**
     * Called where a process caught an error that ends the run: whether
     * every process reached this call within @p seconds (an MPI_Ibarrier on
     * a communicator kept for it alone, so that it cannot meet a collective
     * of the run). An error every process raises alike (the deck's, or one
     * of the replicated state) ends the run on all of them with one line,
     * from the first; an error of this process alone (a file it could not
     * write, say), the others waiting for it in a collective of the run,
     * does not, and this process must end them (MPI_Abort) or they wait
     * for ever. True on one process.
     */
    bool
    failed_together(double seconds = 10);

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
     * A matrix that each process assembles in part (its cells), summed into
     * each process's own rows (owned_rows(m, block)) and stored there whole:
     * a process's pattern holds its own rows with every process's entries
     * in them and, of the other rows, only the entries it adds itself (at
     * its part's border). sum() sends those to their owners, which add what
     * they receive in the order of the ranks, so a row's sum does not depend
     * on the order of arrival. The matrix is not stored whole anywhere:
     * with the dofs numbered by parts (own_rows_by_part()), a process holds
     * about a P-th of it.
     */
    class RowSums
    {
    public:
      /**
       * Collective. @p entries: those this process will add (any rows). On
       * return its own rows also hold the other processes' entries in them,
       * @p pattern is made from it, and sum() is ready for matrices of
       * @p pattern. With one process only the pattern is made.
       */
      void
      reinit(dealii::DynamicSparsityPattern &entries, dealii::SparsityPattern &pattern, const unsigned int block = 1);

      /// Collective. @p matrix (of reinit()'s pattern) summed over the
      /// processes in this process's own rows; the other rows set to NaN, so
      /// that a reader of rows not its own fails at once.
      void
      sum(dealii::SparseMatrix<double> &matrix) const;

    private:
      /// Process q's rows are the entries [first_entry[q], first_entry[q + 1]) of the value array.
      std::vector<std::size_t> first_entry;
      /// For each process, where the entries it sends add in this one's value array.
      std::vector<std::vector<std::size_t>> received;
    };

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
    /// its ends rounded down to multiples of @p block (@p n one itself);
    /// for a size own_rows_by_part() was given, the blocks it last gave.
    dealii::IndexSet
    owned_rows(const dealii::types::global_dof_index n, const unsigned int block = 1);

    /// The first of owned_rows(n, block) on process @p r (on r = P: n),
    /// where its block starts even if it is empty; no communication.
    dealii::types::global_dof_index
    first_owned_row(const dealii::types::global_dof_index n, const unsigned int block, const unsigned int r);

    /**
     * Collective. From now on, the rows of an n x n system with n the sum
     * of @p rows_of_part are owned in the order of the ranks, process r the
     * next rows_of_part[r] (the flow's dofs numbered by the cells' parts,
     * as the shared mesh's DoFHandler numbers them: the rows of a process's cells then
     * are its own, but at its part's border); other sizes as before, and
     * as any other size given (one partition per size: the flow's dofs,
     * p-multigrid's Q1 dofs; distribute_dofs() forgets the last mesh's).
     * Every process must give the same.
     */
    void
    own_rows_by_part(const std::vector<dealii::types::global_dof_index> &rows_of_part);

    /**
     * Collective. Sends @p outgoing[q] to each process q (this one's own
     * entry is not sent) and returns what each sent to this one: the
     * lengths first, then the messages, all in flight at once.
     */
    std::vector<std::vector<std::uint64_t>>
    exchange(const std::vector<std::vector<std::uint64_t>> &outgoing);

    /// Where each process holds the entries of its owned_rows(v.size(),
    /// @p block) in @p v, gives every process all of them (the same bits
    /// everywhere).
    void
    gather(dealii::Vector<double> &v, const unsigned int block = 1);

    /**
     * The run's mesh, empty: on P > 1 a parallel::shared::Triangulation
     * (every process holds all of it, no cell artificial; deal.II divides
     * the active cells among the processes with METIS, as their subdomain
     * ids, whenever the mesh is made or refined), on one process a plain
     * Triangulation (MPI is not initialised then). Both without smoothing.
     */
    template <int dim>
    std::unique_ptr<dealii::Triangulation<dim>>
    new_triangulation();

    /**
     * Collective. @p dof_handler's dofs of @p fe; on P > 1 (the mesh of
     * new_triangulation()) checks that every process has the same parts,
     * and owns each part's block of rows by its process
     * (own_rows_by_part()): deal.II's DoFHandler on the shared mesh
     * numbers the dofs part by part (as DoFRenumbering::subdomain_wise
     * does: an interface dof goes with the part of smaller id), so its
     * cells add to its own rows but at its part's border, and it stores
     * its rows of a matrix alone (RowSums). The same mesh gets the same
     * numbering again (METIS is deterministic), so a vector carried over a
     * call (a refinement's transfer, a free surface's move) keeps its
     * meaning.
     */
    template <int dim>
    void
    distribute_dofs(dealii::DoFHandler<dim> &dof_handler, const dealii::FiniteElement<dim> &fe);

    /**
     * Collective. On P > 1, owns each part's block of @p dof_handler's dofs
     * (distributed on the shared mesh, so numbered part by part) by its
     * process, as distribute_dofs() does: for a second space on the same
     * mesh (p-multigrid's Q1 level, whose rows and transfers then stay
     * within the parts but at their border).
     */
    template <int dim>
    void
    number_dofs_by_part(dealii::DoFHandler<dim> &dof_handler);

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
