// The MPI processes of a run: who this one is, which cells it assembles, and the sums that keep the replicated state the same bits on every process.
#include <dieflow/base/processes.h>

#include <deal.II/grid/grid_tools.h>

#include <petscsys.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace dieflow
{
  namespace processes
  {
    namespace
    {
      unsigned int n_processes = 1;
      unsigned int this_rank   = 0;

      /**
       * Sums @p data over the processes, the same bits everywhere: each
       * process reduces a P-th of the entries (MPI_Reduce_scatter), then
       * every process gathers them (MPI_Allgatherv). Each sum is thus
       * formed once, on one process (an all-reduce may add in a different
       * order on different processes), and the additions and the traffic
       * are divided: reducing everything on the first process and
       * broadcasting it sent each process the whole array and left the
       * first process all the additions.
       */
      void
      sum_doubles(double *data, const std::size_t count)
      {
        // MPI counts are int: large arrays go in slices (of 1 GiB: some
        // transports fail on messages of 2^31 bytes).
        constexpr std::size_t slice = std::size_t(1) << 27;
        std::vector<int>      counts(n_processes), offsets(n_processes);
        for (std::size_t start = 0; start < count; start += slice)
          {
            const std::size_t length = std::min(slice, count - start);
            for (unsigned int r = 0; r < n_processes; ++r)
              {
                offsets[r] = static_cast<int>(length * r / n_processes);
                counts[r]  = static_cast<int>(length * (r + 1) / n_processes) - offsets[r];
              }
            MPI_Reduce_scatter(MPI_IN_PLACE, data + start, counts.data(), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
            // In place, the reduced part arrives at the start of the slice.
            std::memmove(data + start + offsets[this_rank], data + start, counts[this_rank] * sizeof(double));
            MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, data + start, counts.data(), offsets.data(), MPI_DOUBLE,
                           MPI_COMM_WORLD);
          }
      }

      unsigned int
      from_environment(const char *name, const unsigned int otherwise)
      {
        const char *value = std::getenv(name);
        return value != nullptr ? static_cast<unsigned int>(std::strtoul(value, nullptr, 10)) : otherwise;
      }
    } // namespace



    std::pair<unsigned int, unsigned int>
    launched()
    {
      // Open MPI's mpirun; MPICH's Hydra; Slurm's srun (a job step's tasks).
      for (const auto &[size, rank] : {std::pair{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"},
                                       {"PMI_SIZE", "PMI_RANK"},
                                       {"SLURM_STEP_NUM_TASKS", "SLURM_PROCID"}})
        if (std::getenv(size) != nullptr)
          return {from_environment(size, 1), from_environment(rank, 0)};
      return {1, 0};
    }



    unsigned int
    on_this_machine()
    {
      return from_environment("OMPI_COMM_WORLD_LOCAL_SIZE", from_environment("MPI_LOCALNRANKS", launched().first));
    }



    Session::Session()
    {
      if (launched().first <= 1)
        return;
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
      int size = 1, rank = 0;
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      n_processes = static_cast<unsigned int>(size);
      this_rank   = static_cast<unsigned int>(rank);
      // PETSc's own handlers would take SIGINT and SIGTERM from the
      // program's (interrupt.h), and its error handler would print a
      // traceback where the program reports one line.
      PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
      PetscInitializeNoArguments();
      PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
      started = true;
    }



    Session::~Session()
    {
      if (!started)
        return;
      PetscFinalize();
      MPI_Finalize();
      n_processes = 1;
      this_rank   = 0;
    }



    unsigned int
    n()
    {
      return n_processes;
    }



    unsigned int
    rank()
    {
      return this_rank;
    }



    bool
    writes_output()
    {
      return this_rank == 0;
    }



    std::ostream &
    null_stream()
    {
      struct NullBuffer : std::streambuf
      {
        int
        overflow(const int c) override
        {
          return c == traits_type::eof() ? 0 : c;
        }
      };
      static NullBuffer   buffer;
      static std::ostream stream(&buffer);
      return stream;
    }



    MPI_Comm
    communicator()
    {
      return MPI_COMM_WORLD;
    }



    void
    sum(dealii::Vector<double> &v)
    {
      if (n_processes > 1 && v.size() > 0)
        sum_doubles(v.data(), v.size());
    }



    void
    sum(std::vector<double> &v)
    {
      if (n_processes > 1 && !v.empty())
        sum_doubles(v.data(), v.size());
    }



    const double *
    matrix_values(const dealii::SparseMatrix<double> &matrix)
    {
      // Any entry's address, less its linear index in the pattern (rows are
      // stored one after the other): the matrix's iterators, which look up
      // the value and the column at every entry, made the product 1.8 times
      // slower per entry than deal.II's own loop (perf, the 3D bar quarter
      // at 8 x 4 cells on 2 processes).
      const dealii::SparsityPattern &pattern = matrix.get_sparsity_pattern();
      for (dealii::types::global_dof_index i = 0; i < matrix.m(); ++i)
        if (pattern.row_length(i) > 0)
          return &matrix(i, pattern.column_number(i, 0)) - pattern.begin(i)->global_index();
      return nullptr;
    }



    void
    sum(dealii::SparseMatrix<double> &matrix)
    {
      if (n_processes == 1)
        return;
      // The matrix is not const: its value array may be written.
      if (double *const values = const_cast<double *>(matrix_values(matrix)))
        sum_doubles(values, matrix.n_nonzero_elements());
    }



    namespace
    {
      /// The first row of process @p r's block (owned_rows()).
      dealii::types::global_dof_index
      first_row(const dealii::types::global_dof_index n, const unsigned int block, const unsigned int r)
      {
        // In 64 bits: (n / block) r overflows a 32-bit index from n r = 2^32 on.
        const std::uint64_t blocks = n / block;
        return r == n_processes ? n :
                                  static_cast<dealii::types::global_dof_index>(block * ((blocks * r) / n_processes));
      }
    } // namespace



    dealii::IndexSet
    owned_rows(const dealii::types::global_dof_index n, const unsigned int block)
    {
      dealii::IndexSet rows(n);
      rows.add_range(first_row(n, block, rank()), first_row(n, block, rank() + 1));
      return rows;
    }



    void
    sum_own_rows(dealii::SparseMatrix<double> &matrix)
    {
      if (n_processes == 1)
        return;
      double *const values = const_cast<double *>(matrix_values(matrix));
      if (values == nullptr)
        return;
      // The entries of process r's rows are [start[r], start[r + 1]) of
      // the value array (rows stored one after the other).
      const dealii::SparsityPattern &pattern = matrix.get_sparsity_pattern();
      const auto first_entry = [&](dealii::types::global_dof_index row) -> std::size_t {
        for (; row < matrix.m(); ++row)
          if (pattern.row_length(row) > 0)
            return pattern.begin(row)->global_index();
        return matrix.n_nonzero_elements();
      };
      std::vector<std::size_t> start(n_processes + 1);
      for (unsigned int r = 0; r <= n_processes; ++r)
        start[r] = first_entry(first_row(matrix.m(), 1, r));
      // Each block reduced on its owner (MPI_Reduce), all blocks at once
      // (non-blocking), in chunks of 2^22 entries: MPI counts are int, and
      // the reductions' buffers stay at P chunks of 32 MB.
      constexpr std::size_t      chunk = std::size_t(1) << 22;
      std::vector<MPI_Request>   requests;
      requests.reserve(n_processes);
      for (std::size_t offset = 0;; offset += chunk)
        {
          requests.clear();
          for (unsigned int r = 0; r < n_processes; ++r)
            if (start[r] + offset < start[r + 1])
              {
                double *const part   = values + start[r] + offset;
                const int     length = static_cast<int>(std::min(chunk, start[r + 1] - start[r] - offset));
                requests.emplace_back();
                MPI_Ireduce(r == this_rank ? MPI_IN_PLACE : part, r == this_rank ? part : nullptr, length, MPI_DOUBLE,
                            MPI_SUM, static_cast<int>(r), MPI_COMM_WORLD, &requests.back());
              }
          if (requests.empty())
            break;
          MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
        }
      // The other rows hold partial sums: NaN, so that a reader of rows not
      // its own fails at once instead of computing with them.
      std::fill(values, values + start[this_rank], std::numeric_limits<double>::quiet_NaN());
      std::fill(values + start[this_rank + 1], values + start[n_processes], std::numeric_limits<double>::quiet_NaN());
    }



    void
    gather(dealii::Vector<double> &v, const unsigned int block)
    {
      if (n_processes == 1)
        return;
      std::vector<int> counts(n_processes), offsets(n_processes);
      for (unsigned int r = 0; r < n_processes; ++r)
        {
          offsets[r] = static_cast<int>(first_row(v.size(), block, r));
          counts[r]  = static_cast<int>(first_row(v.size(), block, r + 1)) - offsets[r];
        }
      MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, v.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                     communicator());
    }



    void
    require_same(const dealii::Vector<double> &v, const char *where)
    {
      if (n_processes == 1)
        return;
      // FNV-1a over the bytes, its size folded in.
      std::uint64_t hash = 1469598103934665603ULL ^ v.size();
      const auto *  byte = reinterpret_cast<const unsigned char *>(v.begin());
      for (std::size_t i = 0; i < v.size() * sizeof(double); ++i)
        hash = (hash ^ byte[i]) * 1099511628211ULL;
      std::uint64_t low = hash, high = hash;
      MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
      MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
      if (low != high)
        throw std::logic_error(std::string("the MPI processes' states differ at ") + where);
    }



    template <int dim>
    void
    partition(dealii::Triangulation<dim> &triangulation)
    {
      if (n_processes == 1)
        return;
      std::vector<unsigned int> parts(triangulation.n_active_cells());
      if (this_rank == 0)
        {
          dealii::GridTools::partition_triangulation(n_processes, triangulation);
          for (const auto &cell : triangulation.active_cell_iterators())
            parts[cell->active_cell_index()] = cell->subdomain_id();
        }
      MPI_Bcast(parts.data(), static_cast<int>(parts.size()), MPI_UNSIGNED, 0, MPI_COMM_WORLD);
      for (const auto &cell : triangulation.active_cell_iterators())
        cell->set_subdomain_id(parts[cell->active_cell_index()]);
    }

    template void
    partition(dealii::Triangulation<2> &);
    template void
    partition(dealii::Triangulation<3> &);
  } // namespace processes
} // namespace dieflow
