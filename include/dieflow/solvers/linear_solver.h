// The linear solves of the Newton systems: the Linear solver subsection, CHOLMOD or UMFPACK reused per mesh, the iterative path and its fallback.
#ifndef dieflow_linear_solver_h
#define dieflow_linear_solver_h

#include <dieflow/solvers/iterative_solver.h>
#include <dieflow/base/parameters.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dieflow
{
  class DistributedDirectSolver;

  /// The address space this process maps now (VmSize), in bytes; 0 if unknown.
  double
  mapped_memory();

  /**
   * What the memory control groups of this process still let it and its
   * group take, in bytes; 0 where none limits it. A batch scheduler's job
   * (Slurm's --mem) or a container is such a group, and its processes are
   * killed at its limit, whatever the machine has free. The tightest room
   * of the process's group and of every group above it: limit less usage,
   * the usage without the inactive file cache (which the kernel reclaims
   * before it kills; the figure `docker stats` shows). Control groups v2
   * (memory.max, memory.current, inactive_file of memory.stat) and v1 (the
   * memory controller's memory.limit_in_bytes, memory.usage_in_bytes,
   * total_inactive_file), the groups read from @p process_groups (the
   * kernel's /proc/self/cgroup), their files under @p groups_root (v1's
   * memory controller under its memory/); inside a container's namespace
   * the group is the root of its own tree.
   */
  double
  control_group_room(const std::string &process_groups = "/proc/self/cgroup",
                     const std::string &groups_root    = "/sys/fs/cgroup");

  /// A linear system that could not be solved (singular, or out of memory).
  class SolverFailure : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// A solve this machine cannot afford (its message is the whole story).
  class ResourceFailure : public SolverFailure
  {
  public:
    using SolverFailure::SolverFailure;
  };

  /// What the linear solvers did in one cycle.
  struct LinearSolverCounts
  {
    /// Iterative method: solves, their Krylov iterations, and the solves
    /// that did not converge and went to the direct solver.
    unsigned int iterative_solves  = 0;
    unsigned int krylov_iterations = 0;
    /// Degree 2 with an inner solve of the velocity block: its iterations.
    unsigned int inner_iterations = 0;
    /**
     * Degree 2: the decades by which the solves reduced their residuals,
     * sum of log10(1 / reduction). krylov_iterations / residual_decades is
     * the preconditioner's rate, free of the forcing term: finer meshes ask
     * Newton's later solves for more decades, which raises the iterations
     * per solve at an unchanged rate (doc/benchmarks.md).
     */
    double       residual_decades = 0;
    unsigned int direct_fallbacks  = 0;
    /// Degree 2: solves that stopped short of their tolerance (residual
    /// reduced at least tenfold) taken as inexact Newton steps, where the
    /// direct fallback would not have fitted in memory.
    unsigned int partial_steps = 0;
    /// Direct solver: orderings with symbolic factorisations (one per mesh
    /// and kind when the reuse works), and numeric factorisations by kind.
    unsigned int symbolic_analyses       = 0;
    unsigned int cholesky_factorisations = 0;
    unsigned int lu_factorisations       = 0;
    /// Direct solver, 'Reuse factorisation from dofs': Newton steps solved
    /// by GMRES on an earlier factorisation, their GMRES iterations, and
    /// the attempts that did not converge and were factorised after all.
    unsigned int reused_solves       = 0;
    unsigned int reuse_iterations    = 0;
    unsigned int reuse_refactorised  = 0;
    /// The solvers' set-ups, wall time within the linear solves: the
    /// direct solver's factorisations (ordering, symbolic and numeric), the
    /// iterative solvers' preconditioners (ML's hierarchies, p-multigrid's
    /// Galerkin operator and Chebyshev's eigenvalue estimate).
    double setup_seconds = 0;

    /// Counts one iterative solve of the mixed form: its outer and inner
    /// iterations, the decades its residual fell by (@p residual_reduction:
    /// the final over the initial residual), whether it was a partial step.
    void
    add_block_solve(const unsigned int iterations,
                    const unsigned int inner,
                    const double       residual_reduction,
                    const bool         partial_step);
  };

  /**
   * Solves the linearised systems J du = -R with SuiteSparse's sparse direct
   * solvers, called directly so that the fill-reducing ordering and symbolic
   * factorisation (which depend on the sparsity pattern only) are computed
   * once per mesh and reused by every nonlinear iteration:
   *  - CHOLMOD (supernodal Cholesky LL^T) for symmetric systems: the flow
   *    tangent, slip walls, contact without slipping friction. About twice
   *    as fast as LU, with half the fill.
   *  - UMFPACK (LU) for the others: the row transformations of slipping
   *    Coulomb friction make J non-symmetric.
   * A symmetric system CHOLMOD finds not positive definite goes to UMFPACK.
   *
   * Or, for large meshes, iteratively: IterativeSolver (AMG-preconditioned
   * CG or GMRES) on the augmented-Lagrangian form of the problem, whose
   * penalty is moderate (see DieFlowProblem::update_multiplier()). An
   * iterative solve that does not converge falls back to the direct
   * solvers, and is counted.
   */
  /// The deck's "Linear solver" subsection: which method, and its settings.
  struct LinearSolverParameters
  {
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Whether systems of @p n_dofs unknowns of velocity degree @p degree in
     * @p dim dimensions are solved iteratively: by the augmented Lagrangian for degree 1, by
     * the mixed form (SaddlePointSolver) for degree 2. With Method = auto,
     * from 'Iterative from dofs' on, or where that is 0 from
     * auto_threshold().
     */
    bool
    iterative_for(const unsigned int dim, const unsigned int degree, const std::size_t n_dofs) const;

    /// The size from which Method = auto solves iteratively when 'Iterative from dofs' is 0.
    static std::size_t
    auto_threshold(const unsigned int dim, const unsigned int degree);

    /**
     * 'Maximum iterations': the Krylov iterations after which a solve of
     * the mixed form (degree 2) is given up, as a partial step or for the
     * direct fallback; beyond 300 its preconditioner has failed (16-45 per
     * solve where it works, doc/benchmarks.md).
     */
    static constexpr unsigned int default_block_iterations = 300;
    unsigned int                  max_block_iterations     = default_block_iterations;
    /// The same for the augmented Lagrangian's CG / GMRES (degree 1): 120
    /// to 850 iterations over a run where AMG works; beyond 500 the direct
    /// solver is faster than more Krylov steps.
    static constexpr unsigned int default_augmented_iterations = 500;
    unsigned int                  max_augmented_iterations     = default_augmented_iterations;

    /// How the Newton systems are solved.
    enum class Method
    {
      direct,
      iterative,
      /// iterative from iterative_threshold dofs on (auto_threshold() where that is 0)
      automatic
    };
    Method      method = Method::direct;
    std::size_t iterative_threshold = 0;
    /// r/eta of the augmented-Lagrangian iteration.
    double augmentation = 1e3;
    /// Relative residual at which an iterative solve stops.
    double iterative_tolerance = 1e-6;
    bool inexact_newton = true;
    /// Degree 2: the velocity block's cycle is PMultigrid (else AMG on the Q2 block).
    bool p_multigrid = true;
    /// Degree 2: 0 for one V-cycle on the velocity block, else the inner solve's tolerance.
    double inner_tolerance = 0;
    /// Divergence ratio at which the multiplier iteration stops.
    double divergence_tolerance = 1e-7;

    /**
     * The relative tolerance of an iterative solve of the Newton system at
     * an iterate whose relative residual is @p relative_residual: with
     * 'Inexact Newton', 0.1 x that, between 'Iterative tolerance' and
     * 1e-2 (the inexact Newton method, Dembo, Eisenstat and Steihaug 1982:
     * a step solved to a fraction eta of the residual keeps Newton's
     * convergence superlinear when eta -> 0 with the residual, so the early
     * steps need not be solved to the last digits); else 'Iterative
     * tolerance'. Where @p penalty_factor exceeds 1e7, the factor 0.1 and
     * 'Iterative tolerance' are both multiplied by 1e7 / @p penalty_factor
     * (the carried pressure takes up lambda x the solve's residual).
     * Given the last solve of this mesh (its tolerance @p previous_tolerance
     * at the relative residual @p previous_residual; 0: none), a residual
     * that grew gets no looser an absolute accuracy: tolerance x residual
     * at most @p previous_tolerance x @p previous_residual (but never below
     * the tightest tolerance).
     */
    double
    forcing_tolerance(const double relative_residual,
                      const double penalty_factor,
                      const double previous_tolerance = 0,
                      const double previous_residual  = 0) const;
    /// Which direct solver factorises.
    enum class DirectSolver
    {
      /// CHOLMOD where the matrix is symmetric, UMFPACK elsewhere
      automatic,
      /// UMFPACK (LU) always
      umfpack
    };
    DirectSolver direct_solver = DirectSolver::automatic;
    /// 'Reuse factorisation from dofs' (0: every Newton step factorises).
    std::size_t reuse_threshold = 100000;
    /// GMRES iterations a reused factorisation may take before the step is
    /// factorised instead: past them the factorisation is the cheaper.
    static constexpr unsigned int reuse_iterations = 10;
  };



  class LinearSolver
  {
  public:
    explicit LinearSolver(const LinearSolverParameters &parameters);
    ~LinearSolver();

    /// The deck's settings (the problem's ProblemParameters keep them).
    const LinearSolverParameters &parameters;

    /**
     * The mesh changed: forget the sparsity pattern's analysis and the
     * factorisations, unless @p matrix has the very pattern analysed (the
     * mesh only moved, as the free surface moves it): then the ordering
     * and symbolic factorisation serve on (solve_step() takes no
     * factorisation of the mesh before it moved as its preconditioner).
     */
    void
    reset(const dealii::SparseMatrix<double> &matrix);

    /// What a factorisation is for: its refusal names that solve's remedies.
    enum class FactorisationFor
    {
      /// The direct method's Newton system (Linear solver/Method).
      direct_solve,
      /// The direct fallback of an iterative solve that did not converge.
      fallback
    };

    /// Factorises @p matrix (@p symmetric: J = J^T); throws SolverFailure if
    /// it cannot, and ResourceFailure (naming Linear solver/Method and the
    /// sizes) where its analysis's estimate of the factorisation's memory
    /// exceeds the memory free (available_memory()), or where the
    /// factorisation runs out of it: it runs with the address space capped
    /// at the memory free, so that it fails instead of the kernel killing
    /// the process. On more than one process, MUMPS's analysis of each new
    /// pattern weighs its factorisation before it allocates it: refused, on
    /// every process alike, where a machine's processes together, or one
    /// process alone, would need more than is free (the message names the
    /// remedies of the solve @p purpose says).
    void
    factorize(const dealii::SparseMatrix<double> &matrix,
              const bool                          symmetric,
              const FactorisationFor              purpose = FactorisationFor::direct_solve);

    /// Solves with the last factorisation (@p transpose: with J^T, for adjoints).
    void
    solve(const dealii::Vector<double> &rhs, dealii::Vector<double> &solution, const bool transpose = false);

    /**
     * A Newton step J du = @p rhs by the direct solver. From 'Reuse
     * factorisation from dofs' on, where this mesh's pattern has the
     * factorisation M of an earlier tangent on the mesh as it is (an
     * earlier Newton step's), GMRES on J right-preconditioned
     * by M^-1 first (so that it measures J's own residual), to
     * |rhs - J du| <= @p tolerance |rhs|: the tangents of successive Newton
     * steps differ by the viscosity's change, small near the solution, and
     * by the few contact nodes that changed state, of low rank, so a few
     * triangular solves replace a factorisation (Knoll and Keyes 2004, the
     * lagged preconditioner of Jacobian-free Newton-Krylov). Where GMRES
     * needs more than LinearSolverParameters::reuse_iterations, J is
     * factorised and solved directly, and serves the next steps.
     */
    void
    solve_step(const dealii::SparseMatrix<double> &matrix,
               const bool                          symmetric,
               const dealii::Vector<double> &      rhs,
               dealii::Vector<double> &            solution,
               const double                        tolerance);

    /// Whether the last Newton step's factorisation on this mesh as it is
    /// is at hand, for a solve with that tangent (an adjoint's): none after
    /// reset(), even to the same pattern, nor after a step solve_step()
    /// solved by GMRES on an earlier factorisation.
    bool
    has_factorisation() const;

    /// Which solver the last factorisation used ("CHOLMOD" or "UMFPACK").
    std::string
    last_solver() const;

    /// The velocity components' constant modes, for the AMG preconditioner.
    void
    set_constant_modes(const std::vector<std::vector<bool>> &modes);

    /**
     * The peak memory (bytes) expected of a direct solve of @p n_dofs
     * unknowns in @p dim dimensions, from this program's measured runs
     * (degree 2, AMD EPYC): 2D 2.3 GB at 458,000 unknowns, about linear
     * (N^0.93, doc/benchmarks.md); 3D 1.9 GB at 42,315 (the graded round
     * bar quarter, doc/three-dimensional.md), grown as N^(4/3), the fill of
     * a nested-dissection factorisation in 3D.
     */
    static double
    direct_memory_estimate(const unsigned int dim, const std::size_t n_dofs);

    /**
     * Throws ResourceFailure, with the sizes, where the direct fallback of a
     * failed iterative solve (of @p matrix, Cholesky where @p symmetric)
     * would need more memory than is free (direct_fallback_fits()): factorize()
     * would refuse it too, with advice for the direct method; this names the
     * iterative solve's remedies.
     */
    void
    require_direct_fallback_fits(const unsigned int dim, const dealii::SparseMatrix<double> &matrix, const bool symmetric);

    /**
     * Whether the direct solver's factorisations of @p matrix's pattern (a
     * mesh of dimension @p dim) take at most half the memory free now, from
     * CHOLMOD's analysis of the pattern, asked only where the measured
     * estimate (direct_memory_estimate()) exceeds a quarter of the free
     * memory (on more than one process, MUMPS's analysis, weighed as
     * DistributedDirectSolver::analyse() says). (Method = auto solves
     * iteratively where they do not.)
     */
    bool
    direct_fits(const unsigned int dim, const dealii::SparseMatrix<double> &matrix);

    /// Whether the direct fallback's factorisation of @p matrix (Cholesky
    /// where @p symmetric) fits in the memory free now, by factorize()'s
    /// rule (CHOLMOD's analysis of the pattern, asked only where the
    /// measured estimate exceeds a quarter of the free memory; true where
    /// the free memory is not known): one rule decides both.
    bool
    direct_fallback_fits(const unsigned int dim, const dealii::SparseMatrix<double> &matrix, const bool symmetric);

    /// The memory free now, in bytes: the kernel's MemAvailable, but no
    /// more than the address space the process may still take (ulimit -v)
    /// or its control group's limit leaves; 0 where there is no such figure.
    static double
    available_memory();

    /// What available_memory() takes from the machine, shared by its
    /// processes: MemAvailable, no more than the control groups leave
    /// (control_group_room(); 0 where unknown).
    static double
    machine_memory();

    /// What available_memory() takes from this process's limit: the address
    /// space it may still take (ulimit -v; 0 where unlimited).
    static double
    address_space_room();

    /// Solves @p matrix x = @p rhs iteratively, or, if that fails, directly
    /// (for a mesh of dimension @p dim, where that fits in memory).
    void
    solve_iteratively(const unsigned int                  dim,
                      const dealii::SparseMatrix<double> &matrix,
                      const bool                          symmetric,
                      const dealii::Vector<double> &      rhs,
                      dealii::Vector<double> &            solution);

    /// What the solves did (the problem resets them per cycle).
    LinearSolverCounts counts;

  private:
    /// Throws ResourceFailure where the next factorisation (@p cholesky or
    /// LU) would need more memory than is free (see factorize()).
    void
    require_factorisation_fits(const bool cholesky);
    /// The direct fallback's factorisation bytes from CHOLMOD's analysis; 0
    /// where the measured estimate is below a quarter of the free memory.
    double
    direct_fallback_bytes(const unsigned int dim, const dealii::SparseMatrix<double> &matrix, const bool symmetric);

    struct SuiteSparse;
    std::unique_ptr<SuiteSparse> suitesparse;
    /// Made on first use: Trilinos needs MPI initialised (the direct path does not).
    std::unique_ptr<IterativeSolver> iterative_solver;
    /// Made on first use on more than one process (processes.h).
    std::unique_ptr<DistributedDirectSolver> distributed;
  };
} // namespace dieflow

#endif
