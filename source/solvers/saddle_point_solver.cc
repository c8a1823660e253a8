// The mixed form's update equation by block-preconditioned GMRES: a multigrid cycle for the velocity block, a scaled mass for the Schur complement.
#include <dieflow/solvers/saddle_point_solver.h>

#include <deal.II/base/timer.h>
#include <deal.II/lac/la_parallel_block_vector.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/vector_memory.h>

#include <dieflow/base/processes.h>
#include <dieflow/solvers/linear_solver.h>

#include <deal.II/base/mpi.h>

#include <algorithm>

namespace dieflow
{
  namespace
  {
    /// The Krylov vectors a solve goes on with (a restart every 98 iterations) after as many iterations with 32.
    constexpr unsigned int long_restart = 100;

    using BlockVector = dealii::LinearAlgebra::distributed::BlockVector<double>;

    /// The scaled mixed operator [A, B^T S; S B, -S C S] (S = diag(s_K)),
    /// on vectors divided among the processes (the velocity as A's rows,
    /// the pressure by the cells' parts).
    template <int dim>
    class MixedOperator
    {
    public:
      MixedOperator(const RowBlockMatrix &          A,
                    const RowBlockMatrix &          gradient,
                    const RowBlockMatrix &          divergence,
                    const MixedPenalty<dim> &       blocks,
                    const RowLayout &               pressure_layout,
                    const dealii::Vector<double> &  scale)
        : A(A)
        , gradient(gradient)
        , divergence(divergence)
        , blocks(blocks)
        , pressure_layout(pressure_layout)
        , scale(scale)
        , scale_squared_over_penalty(scale.size())
      {
        for (unsigned int c = 0; c < scale.size(); ++c)
          scale_squared_over_penalty[c] = scale[c] * scale[c] / blocks.penalty[c];
      }

      void
      vmult(BlockVector &dst, const BlockVector &src) const
      {
        A.vmult(dst.block(0), src.block(0));
        scale_pressure(pressure, src.block(1));
        gradient.vmult_add(dst.block(0), pressure);
        divergence.vmult(dst.block(1), src.block(0));
        scale_pressure(dst.block(1), dst.block(1));
        blocks.cell_vmult(MixedPenalty<dim>::CellBlock::mass, pressure, src.block(1), scale_squared_over_penalty,
                          pressure_layout);
        dst.block(1) -= pressure;
      }

      /// dst_K = s_K src_K on this process's cells (in place allowed).
      void
      scale_pressure(DistributedVector &dst, const DistributedVector &src) const
      {
        if (dst.size() != src.size())
          pressure_layout.reinit(dst);
        const auto &       cells   = pressure_layout.groups();
        const unsigned int n_modes = blocks.n_modes;
        for (std::size_t k = 0; k < cells.size(); ++k)
          for (unsigned int m = 0; m < n_modes; ++m)
            dst.local_element(k * n_modes + m) = scale[cells[k]] * src.local_element(k * n_modes + m);
      }

      /// A, B^T and B, their products divided among the MPI processes.
      const RowBlockMatrix &              A;
      const RowBlockMatrix &              gradient;
      const RowBlockMatrix &              divergence;
      const MixedPenalty<dim> &           blocks;
      const RowLayout &                   pressure_layout;
      const dealii::Vector<double> &      scale;
      dealii::Vector<double>              scale_squared_over_penalty;
      mutable DistributedVector           pressure;
    };

    /**
     * A^-1: one V-cycle, or an inner Krylov solve of A to a relative
     * tolerance preconditioned by it (counting its iterations).
     */
    template <int dim>
    class VelocityBlockInverse
    {
    public:
      VelocityBlockInverse(const RowBlockMatrix &                           A,
                           const RowBlockAMG &                              amg,
                           const PMultigrid<dim> *                          p_multigrid,
                           const bool                                       symmetric,
                           const double                                     tolerance,
                           const unsigned int                               max_iterations)
        : A(A)
        , amg(amg)
        , p_multigrid(p_multigrid)
        , symmetric(symmetric)
        , tolerance(tolerance)
        , max_iterations(max_iterations)
      {}

      void
      vmult(DistributedVector &dst, const DistributedVector &src) const
      {
        if (tolerance == 0)
          {
            cycle(dst, src);
            return;
          }
        dst = 0;
        dealii::SolverControl control(max_iterations, tolerance * src.l2_norm(), false, false);
        const OneCycle        one_cycle{*this};
        try
          {
            if (symmetric)
              dealii::SolverCG<DistributedVector>(control).solve(A, dst, src, one_cycle);
            else
              dealii::SolverGMRES<DistributedVector>(control,
                                                    dealii::SolverGMRES<DistributedVector>::AdditionalData(32, true))
                .solve(A, dst, src, one_cycle);
          }
        catch (const dealii::SolverControl::NoConvergence &)
          {
            // The outer FGMRES takes whatever the inner solve reached.
          }
        iterations += control.last_step();
      }

      /// The cycle as the inner solve's preconditioner.
      struct OneCycle
      {
        const VelocityBlockInverse &inverse;
        void
        vmult(DistributedVector &dst, const DistributedVector &src) const
        {
          inverse.cycle(dst, src);
        }
      };

      /// One multigrid cycle: the AMG V-cycle, or the p-multigrid cycle.
      void
      cycle(DistributedVector &dst, const DistributedVector &src) const
      {
        if (p_multigrid != nullptr)
          p_multigrid->vmult(dst, src);
        else
          amg.vmult(dst, src);
      }

      const RowBlockMatrix &                           A;
      const RowBlockAMG &                              amg;
      const PMultigrid<dim> *                          p_multigrid;
      const bool                                       symmetric;
      const double                                     tolerance;
      const unsigned int                               max_iterations;
      mutable unsigned int                             iterations = 0;
    };

    /// P^-1 for P = [A^, B^T S; 0, -S S^ S]: p = -(S S^ S)^-1 r_p, v = A^-1 (r_v - B^T S p).
    template <int dim>
    class BlockTriangularPreconditioner
    {
    public:
      BlockTriangularPreconditioner(const MixedOperator<dim> &       op,
                                    const VelocityBlockInverse<dim> &velocity_inverse)
        : op(op)
        , velocity_inverse(velocity_inverse)
        , schur_factor(op.scale.size())
      {
        const auto &b = op.blocks;
        for (unsigned int c = 0; c < schur_factor.size(); ++c)
          schur_factor[c] =
            -1. / ((1. / b.viscosity[c] + 1. / b.penalty[c]) * op.scale[c] * op.scale[c]);
        op.A.row_layout().reinit(residual);
      }

      void
      vmult(BlockVector &dst, const BlockVector &src) const
      {
        op.blocks.cell_vmult(MixedPenalty<dim>::CellBlock::inverse_mass, dst.block(1), src.block(1), schur_factor,
                             op.pressure_layout);
        op.scale_pressure(pressure, dst.block(1));
        op.gradient.vmult(residual, pressure);
        residual.sadd(-1., 1., src.block(0));
        velocity_inverse.vmult(dst.block(0), residual);
      }

      const MixedOperator<dim> &                       op;
      const VelocityBlockInverse<dim> &                velocity_inverse;
      dealii::Vector<double>                           schur_factor;
      mutable DistributedVector                        pressure;
      mutable DistributedVector                        residual;
    };
    /**
     * The restart length, up to long_restart, whose Krylov vectors (of the
     * size of @p x, @p vectors_per_iteration of them per iteration: one for
     * GMRES, two for FGMRES, which also keeps each preconditioned vector)
     * fit in half the memory free now; at least @p shortest.
     */
    unsigned int
    affordable_restart(const BlockVector &               x,
                       const unsigned int                 shortest,
                       const unsigned int                 vectors_per_iteration)
    {
      // The least any process has: every process must choose the same length.
      const double available = processes::n() > 1 ?
                                 dealii::Utilities::MPI::min(LinearSolver::available_memory(), processes::communicator()) :
                                 LinearSolver::available_memory();
      if (available == 0)
        return long_restart;
      // Each process holds its part of every vector: the largest part.
      const double largest_part =
        dealii::Utilities::MPI::max(static_cast<double>(x.block(0).locally_owned_size() + x.block(1).locally_owned_size()),
                                    processes::communicator());
      const double per_iteration = vectors_per_iteration * sizeof(double) * largest_part;
      const double fitting       = (0.5 * available - 2 * per_iteration) / per_iteration;
      return std::max(shortest, static_cast<unsigned int>(std::min<double>(long_restart, std::max(0., fitting))));
    }
  } // namespace



  template <int dim>
  void
  SaddlePointSolver<dim>::reinit()
  {
    mesh_agreed = false;
  }



  template <int dim>
  void
  SaddlePointSolver<dim>::set_rigid_body_modes(std::vector<double> rigid_body_modes)
  {
    modes = std::move(rigid_body_modes);
  }



  template <int dim>
  void
  SaddlePointSolver<dim>::use_p_multigrid(const dealii::DoFHandler<dim> &dof_handler)
  {
    p_multigrid = std::make_unique<PMultigrid<dim>>();
    p_multigrid->reinit(dof_handler);
  }



  template <int dim>
  typename SaddlePointSolver<dim>::Info
  SaddlePointSolver<dim>::solve(const dealii::SparseMatrix<double> &     A,
                                const dealii::AffineConstraints<double> &constraints,
                                const dealii::Vector<double> *           flow,
                                const MixedPenalty<dim> &           blocks,
                                const dealii::Vector<double> &      rhs_velocity,
                                const dealii::Vector<double> &      rhs_pressure,
                                dealii::Vector<double> &            du,
                                dealii::Vector<double> &            dp,
                                const bool                          symmetric,
                                const double                        tolerance,
                                const unsigned int                  max_iterations)
  {
    Info                   info;
    dealii::Vector<double> scale(blocks.n_cells);
    for (unsigned int c = 0; c < blocks.n_cells; ++c)
      scale[c] = blocks.viscosity[c] / blocks.size[c];

    // The velocity as the matrix's rows, the pressure by the cells' parts,
    // and the products' exchanges: they depend on the mesh alone, so they
    // are agreed at its first solve (a pass over each process's rows of
    // A's pattern, some 10^8 entries at 10^6 unknowns), then only the
    // values are taken anew. reinit() marks a new mesh; the patterns'
    // shapes are checked too, should a caller forget it. The agreement is
    // collective and A's and B^T's patterns hold other rows' entries only
    // at each process's border (RowSums), so a process may see a change
    // the others do not: any one's verdict is every one's.
    bool agree = !mesh_agreed || !velocity_block.has_pattern_of(A) || !gradient_block.has_pattern_of(blocks.gradient) ||
                 !divergence_block.has_pattern_of(blocks.divergence) || pressure_layout.size() != blocks.n_pressure();
    if (processes::n() > 1)
      agree = dealii::Utilities::MPI::max(agree ? 1 : 0, processes::communicator()) == 1;
    if (agree)
      {
        velocity_layout.reinit_rows(A.m());
        pressure_layout.reinit_groups(blocks.part, blocks.n_modes);
        velocity_block.reinit(A, velocity_layout, velocity_layout);
        gradient_block.reinit(blocks.gradient, velocity_layout, pressure_layout);
        divergence_block.reinit(blocks.divergence, pressure_layout, velocity_layout);
        mesh_agreed = true;
      }
    else
      {
        velocity_block.reinit_values(A);
        gradient_block.reinit_values(blocks.gradient);
        divergence_block.reinit_values(blocks.divergence);
      }
    const MixedOperator<dim> op(velocity_block, gradient_block, divergence_block, blocks, pressure_layout, scale);
    BlockVector              x(2);
    velocity_layout.reinit(x.block(0));
    pressure_layout.reinit(x.block(1));
    x.collect_sizes();
    BlockVector b(x);
    velocity_layout.extract(rhs_velocity, b.block(0));
    pressure_layout.extract(rhs_pressure, b.block(1));
    op.scale_pressure(b.block(1), b.block(1));
    const double target = tolerance * b.l2_norm();
    if (target == 0)
      {
        du.reinit(A.m());
        dp.reinit(blocks.n_pressure());
        info.converged = true;
        return info;
      }

    // One V-cycle: two cut the outer iterations but cost more time than
    // they save (doc/benchmarks.md, "Figures behind the code's rules").
    PMultigrid<dim> *const cycle = p_multigrid.get();
    const dealii::Timer    setup;
    if (cycle != nullptr)
      cycle->initialize(velocity_block, constraints, flow);
    else
      velocity_preconditioner.initialize<dim>(A, modes, velocity_amg_data({}, true));
    info.setup_seconds = setup.wall_time();
    const VelocityBlockInverse<dim> velocity_inverse(op.A, velocity_preconditioner, cycle, symmetric, inner_tolerance,
                                                     max_inner_iterations);
    const BlockTriangularPreconditioner<dim> preconditioner(op, velocity_inverse);

    // GMRES with 32 vectors first (deal.II restarts when they are used up,
    // every 30 iterations): each holds a velocity and a pressure vector,
    // the largest share of the solver's memory, and more of them cost
    // memory and save no time. A solve that is not done after long_restart
    // iterations goes on from where it stands with long_restart vectors, or
    // as many as fit in half the free memory: short restarts stagnate where
    // the velocity cycle is weak, and long ones from the start would add
    // to the memory of every large Newtonian run, whose solves take fewer
    // than long_restart iterations
    // (doc/benchmarks.md, "Figures behind the code's rules").
    double last_residual = b.l2_norm();
    const auto gmres     = [&](const unsigned int restart, const unsigned int limit) {
      dealii::SolverControl control(limit, target, false, false);
      bool                  converged = true;
      try
        {
          if (inner_tolerance == 0)
            {
              typename dealii::SolverGMRES<BlockVector>::AdditionalData data(restart, true);
              dealii::SolverGMRES<BlockVector>(control, data).solve(op, x, b, preconditioner);
            }
          else
            {
              typename dealii::SolverFGMRES<BlockVector>::AdditionalData data(restart);
              dealii::SolverFGMRES<BlockVector>(control, data).solve(op, x, b, preconditioner);
            }
        }
      catch (const dealii::SolverControl::NoConvergence &)
        {
          converged = false;
        }
      info.iterations += control.last_step();
      last_residual = control.last_value();
      return converged;
    };
    const unsigned int short_restart = inner_tolerance == 0 ? 32 : 50;
    info.converged = gmres(short_restart, std::min(max_iterations, long_restart));
    if (!info.converged && info.iterations < max_iterations)
      info.converged =
        gmres(affordable_restart(x, short_restart, inner_tolerance == 0 ? 1 : 2), max_iterations - info.iterations);
    info.residual_reduction = last_residual / b.l2_norm();
    info.inner_iterations   = velocity_inverse.iterations;
    // Every process the whole update (the same bits everywhere).
    velocity_layout.gather(x.block(0), du);
    op.scale_pressure(x.block(1), x.block(1));
    pressure_layout.gather(x.block(1), dp);
    // deal.II's solvers take their Krylov vectors from a pool that keeps
    // them, once returned, until the program ends: 32 block vectors, a
    // large share of the peak heap, held while the next Newton step
    // assembles and sets up its multigrid.
    dealii::GrowingVectorMemory<BlockVector>::release_unused_memory();
    dealii::GrowingVectorMemory<DistributedVector>::release_unused_memory();
    return info;
  }

  template class SaddlePointSolver<2>;
  template class SaddlePointSolver<3>;
} // namespace dieflow
