// The Linear solver subsection: its entries, their parsing, and the choices that follow from them (the auto threshold, the forcing tolerance).
#include <dieflow/solvers/linear_solver.h>

#include <algorithm>
#include <string>

namespace dieflow
{
  void
  LinearSolverParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    prm.declare_entry("Method",
                      "direct",
                      dealii::Patterns::Selection("direct|iterative|auto"),
                      "direct: sparse factorisation (SuiteSparse) of the penalty "
                      "problem, robust for any penalty and any friction state; its "
                      "ordering and symbolic factorisation are reused by every "
                      "iteration on a mesh. iterative, velocity degree 2: the same "
                      "penalty problem in mixed form (velocity and P1disc pressure), "
                      "each Newton system solved by GMRES with a block-triangular "
                      "preconditioner (a multigrid cycle on the velocity block, "
                      "'Velocity multigrid'; the pressure mass scaled by the inverse "
                      "viscosity): the direct solver's answer, in a third of its "
                      "memory and, from about 700,000 unknowns, as little time. "
                      "iterative, degree 1: the augmented-Lagrangian form (penalty "
                      "'Augmentation factor' x eta, the pressure carried as a cell "
                      "multiplier updated every nonlinear iteration until the "
                      "divergence ratio is below 'Divergence tolerance'), each system "
                      "solved by AMG-preconditioned CG, or GMRES when friction slips. "
                      "A system the iterative method cannot solve goes to the direct "
                      "solver. auto: iterative from 'Iterative from dofs' unknowns on.");
    prm.declare_entry("Iterative from dofs",
                      "0",
                      dealii::Patterns::Integer(0),
                      "With Method = auto: the number of unknowns from which the "
                      "iterative solver is used; 0: 700,000 for velocity degree 2 "
                      "(where the mixed form's solver overtakes the direct one on "
                      "die2d, doc/benchmarks.md; 20,000 in 3D, "
                      "doc/three-dimensional.md), 3,000,000 for degree 1 (the "
                      "direct solver was faster at every size measured; this is "
                      "where its factorisation would outgrow some 13 GB).");
    prm.declare_entry("Augmentation factor",
                      "1e3",
                      dealii::Patterns::Double(0),
                      "Iterative method: the penalty r/eta of the augmented "
                      "Lagrangian. Larger: fewer multiplier updates, harder systems "
                      "for AMG (1e2 to 1e4).");
    prm.declare_entry("Iterative tolerance",
                      "1e-6",
                      dealii::Patterns::Double(0),
                      "Iterative method: a linear solve stops when its residual is "
                      "below this fraction of its right-hand side (degree 2: the "
                      "mixed system's, its pressure rows scaled by eta/h to force "
                      "units); degree 2 with 'Inexact Newton': the tightest "
                      "tolerance a solve is given. Degree 2 with a Penalty factor "
                      "above 1e7: multiplied by 1e7 / Penalty factor. Newton's own "
                      "tests decide the answer's accuracy.");
    prm.declare_entry("Maximum iterations",
                      "0",
                      dealii::Patterns::Integer(0),
                      "Iterative method: the Krylov iterations a linear solve may "
                      "take. A solve not done by then is solved again by the direct "
                      "solver, or, for velocity degree 2 where that would not fit in "
                      "the free memory and the solve cut its residual tenfold, taken "
                      "as a partial Newton step (summary.json counts both). 0: " +
                        std::to_string(default_block_iterations) +
                        " for velocity degree 2 (the mixed form's GMRES takes 16-45 per "
                        "solve where its preconditioner works), " +
                        std::to_string(default_augmented_iterations) +
                        " for degree 1 (the augmented Lagrangian's CG or GMRES).");
    prm.declare_entry("Divergence tolerance",
                      "1e-7",
                      dealii::Patterns::Double(0),
                      "Iterative method: the nonlinear iteration also requires the "
                      "divergence ratio ||div v|| / ||grad v|| to be below this.");
    prm.declare_entry("Velocity multigrid",
                      "p-multigrid",
                      dealii::Patterns::Selection("p-multigrid|AMG"),
                      "Iterative method, velocity degree 2: the multigrid cycle that "
                      "approximates the inverse of the velocity block. p-multigrid: "
                      "Chebyshev smoothing of the Q2 block and one AMG V-cycle on its "
                      "Galerkin projection onto Q1 velocities of the same mesh "
                      "(faster at every size measured, and memory about half). AMG: "
                      "one AMG V-cycle on the Q2 block itself.");
    prm.declare_entry("Velocity block",
                      "one cycle",
                      dealii::Patterns::Selection("one cycle|inner solve"),
                      "Iterative method, velocity degree 2: how the preconditioner "
                      "applies the inverse of the velocity block. one cycle: one "
                      "cycle of 'Velocity multigrid' (GMRES outside). inner solve: CG "
                      "(GMRES where friction slips) on the velocity block, "
                      "preconditioned by that cycle, to 'Inner tolerance' (flexible "
                      "GMRES outside): outer iterations that do not grow with the "
                      "mesh, each dearer.");
    prm.declare_entry("Inner tolerance",
                      "1e-2",
                      dealii::Patterns::Double(0),
                      "Velocity block = inner solve: the relative residual to which "
                      "each inner solve reduces its right-hand side.");
    prm.declare_entry("Inexact Newton",
                      "true",
                      dealii::Patterns::Bool(),
                      "Iterative method, velocity degree 2: solve each Newton system "
                      "to 0.1 x the relative residual of the iterate (both 0.1 and "
                      "the floor times 1e7 / Penalty factor where that is above "
                      "1e7), between 'Iterative tolerance' and 1e-2, instead of "
                      "always to 'Iterative tolerance' (Newton's own tolerances "
                      "still decide when the answer is converged).");
    prm.declare_entry("Direct solver",
                      "auto",
                      dealii::Patterns::Selection("auto|UMFPACK"),
                      "auto: CHOLMOD's Cholesky factorisation for symmetric systems "
                      "(no slipping Coulomb friction), UMFPACK's LU otherwise. "
                      "UMFPACK: LU always.");
    prm.declare_entry("Reuse factorisation from dofs",
                      "100000",
                      dealii::Patterns::Integer(0),
                      "Direct method: from this many unknowns, a Newton step on a "
                      "mesh that already has a factorisation (an earlier step's) is "
                      "first solved by GMRES preconditioned by that factorisation, "
                      "to the accuracy the step needs (a tenth of the residual's "
                      "round-off floor, relative to the iterate's residual, at most "
                      "1e-6); a step GMRES does not solve in 10 iterations is "
                      "factorised. The answer is the same; large meshes that take "
                      "several steps run faster (doc/benchmarks.md). 0: every step "
                      "factorises.");
    prm.leave_subsection();
  }


  void
  LinearSolverParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    method              = prm.get("Method") == "iterative" ? Method::iterative :
                          prm.get("Method") == "auto"      ? Method::automatic :
                                                             Method::direct;
    direct_solver       = prm.get("Direct solver") == "UMFPACK" ? DirectSolver::umfpack : DirectSolver::automatic;
    iterative_threshold = prm.get_integer("Iterative from dofs");
    reuse_threshold     = prm.get_integer("Reuse factorisation from dofs");
    augmentation        = get_positive(prm, "Linear solver/", "Augmentation factor");
    iterative_tolerance  = prm.get_double("Iterative tolerance");
    divergence_tolerance = get_positive(prm, "Linear solver/", "Divergence tolerance");
    inexact_newton       = prm.get_bool("Inexact Newton");
    const unsigned int limit = prm.get_integer("Maximum iterations");
    max_block_iterations     = limit > 0 ? limit : default_block_iterations;
    max_augmented_iterations = limit > 0 ? limit : default_augmented_iterations;
    p_multigrid          = prm.get("Velocity multigrid") == "p-multigrid";
    inner_tolerance      = prm.get("Velocity block") == "inner solve" ? prm.get_double("Inner tolerance") : 0.;
    require(prm.get_double("Inner tolerance") > 0 && prm.get_double("Inner tolerance") < 1,
            "Linear solver/Inner tolerance",
            "must lie in (0, 1), got " + prm.get("Inner tolerance"));
    require(iterative_tolerance > 0 && iterative_tolerance < 1,
            "Linear solver/Iterative tolerance",
            "must lie in (0, 1), got " + prm.get("Iterative tolerance"));
    prm.leave_subsection();
  }


  double
  LinearSolverParameters::forcing_tolerance(const double relative_residual,
                                  const double penalty_factor,
                                  const double previous_tolerance,
                                  const double previous_residual) const
  {
    // The carried pressure q takes up lambda times the pressure rows' residual
    // of a solve, and Newton needs ||q / lambda|| below 1e-10 ||grad v||:
    // above the default penalty factor of 1e7 every tolerance shrinks with
    // it, or the ratio stalls above that bound (doc/benchmarks.md).
    const double penalty_scale = std::min(1., 1e7 / penalty_factor);
    const double tightest      = iterative_tolerance * penalty_scale;
    if (!inexact_newton || !(relative_residual > 0))
      return tightest;
    const double forcing = std::max(tightest, std::min(1e-2, 0.1 * penalty_scale * relative_residual));
    // A residual that jumps when contact states change (the friction forces
    // of nodes that start or stop slipping) is mostly local, and a solve to
    // a fraction of it stops after a few Krylov iterations, the rest of the
    // flow as inaccurate as that fraction: the next states are decided on
    // that flow, and on a fine mesh nodes of the die cone then trade stick
    // and slip at every iteration. A residual that grew is therefore solved
    // to no looser an absolute accuracy than the last solve's
    // (doc/benchmarks.md, "Figures behind the code's rules").
    if (previous_tolerance > 0 && relative_residual > previous_residual)
      return std::max(tightest, std::min(forcing, previous_tolerance * previous_residual / relative_residual));
    return forcing;
  }


  bool
  LinearSolverParameters::iterative_for(const unsigned int dim, const unsigned int degree, const std::size_t n_dofs) const
  {
    const std::size_t threshold = iterative_threshold > 0 ? iterative_threshold : auto_threshold(dim, degree);
    return method == Method::iterative || (method == Method::automatic && n_dofs >= threshold);
  }


  std::size_t
  LinearSolverParameters::auto_threshold(const unsigned int dim, const unsigned int degree)
  {
    // 3D, degree 2: 3D factorisations fill in far more than 2D ones; on the
    // round bar quarter the crossover lies between two sizes measured, the
    // mixed form above it the faster and in much less memory
    // (doc/three-dimensional.md; doc/benchmarks.md, "Figures behind the code's rules").
    if (dim == 3 && degree >= 2)
      return 20000;
    // Degree 2: the measured crossover of die2d N1 (doc/benchmarks.md,
    // "p-multigrid"): from about this size the mixed form with the
    // p-multigrid cycle takes as long as the direct solver, in much less
    // memory, and runs on where the factorisation no longer fits. Degree 1:
    // no crossover (the augmented Lagrangian was slower at every size
    // measured); this is where its factorisation outgrows some 13 GB
    // (extrapolated).
    return degree >= 2 ? 700000 : 3000000;
  }
} // namespace dieflow
