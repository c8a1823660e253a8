// The MPI processes of a run: who this one is, which cells it assembles, and the sums that keep the replicated state the same bits on every process.
#include <dieflow/base/processes.h>

#include <deal.II/distributed/shared_tria.h>
#include <deal.II/dofs/dof_tools.h>

#include <petscsys.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace dieflow
{
  namespace processes
  {
    namespace
    {
      unsigned int n_processes = 1;
      unsigned int this_rank   = 0;
      /// failed_together()'s communicator: a copy of MPI_COMM_WORLD that no collective of the run uses.
      MPI_Comm failure_communicator = MPI_COMM_NULL;

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
      // A program that embeds the run may have started MPI (a test that
      // limits its memory once MPI has mapped its segments): it ends it.
      int initialised = 0;
      MPI_Initialized(&initialised);
      if (initialised == 0)
        {
          int provided = 0;
          MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
          owns_mpi = true;
        }
      int size = 1, rank = 0;
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      n_processes = static_cast<unsigned int>(size);
      this_rank   = static_cast<unsigned int>(rank);
      if (n_processes != launched().first)
        {
          // MPI_Get_library_version names the build's MPI ("Open MPI v4.1.4, ...").
          char library[MPI_MAX_LIBRARY_VERSION_STRING] = {};
          int  length                                   = 0;
          MPI_Get_library_version(library, &length);
          const std::string name(library, std::find(library, library + length, ','));
          mismatch = "the launcher started " + std::to_string(launched().first) + " processes, but MPI (" + name +
                     ") sees " + std::to_string(n_processes) +
                     ": this program was built with another MPI than the launcher's; launch it with the mpirun of " +
                     name + " (Debian: openmpi-bin)";
        }
      // PETSc's own handlers would take SIGINT and SIGTERM from the
      // program's (interrupt.h), and its error handler would print a
      // traceback where the program reports one line.
      PetscBool petsc_initialised = PETSC_FALSE;
      PetscInitialized(&petsc_initialised);
      if (petsc_initialised == PETSC_FALSE)
        {
          PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
          PetscInitializeNoArguments();
          owns_petsc = true;
        }
      PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
      MPI_Comm_dup(MPI_COMM_WORLD, &failure_communicator);
      started = true;
    }



    const std::string &
    Session::launch_error() const
    {
      return mismatch;
    }



    Session::~Session()
    {
      if (!started)
        return;
      PetscPopErrorHandler();
      MPI_Comm_free(&failure_communicator);
      if (owns_petsc)
        PetscFinalize();
      if (owns_mpi)
        MPI_Finalize();
      n_processes = 1;
      this_rank   = 0;
    }



    bool
    failed_together(const double seconds)
    {
      if (failure_communicator == MPI_COMM_NULL)
        return true;
      MPI_Request request = MPI_REQUEST_NULL;
      MPI_Ibarrier(failure_communicator, &request);
      const double start = MPI_Wtime();
      int          done  = 0;
      while (MPI_Test(&request, &done, MPI_STATUS_IGNORE) == MPI_SUCCESS && done == 0 &&
             MPI_Wtime() - start < seconds)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      // Left pending where not done: the process is about to abort.
      return done != 0;
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
      /// The rows own_rows_by_part() gave, one partition per size (the
      /// flow's dofs, p-multigrid's Q1 dofs): process r's from first[r].
      std::vector<std::vector<dealii::types::global_dof_index>> parts_by_size;
    } // namespace



    std::vector<std::vector<std::uint64_t>>
    exchange(const std::vector<std::vector<std::uint64_t>> &outgoing)
    {
      std::vector<std::uint64_t> sending(n_processes), receiving(n_processes);
      for (unsigned int q = 0; q < n_processes; ++q)
        sending[q] = outgoing[q].size();
      MPI_Alltoall(sending.data(), 1, MPI_UINT64_T, receiving.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
      // Agreed by every process before any message is posted: one that
      // stopped alone would leave the others waiting.
      int too_long = 0;
      for (unsigned int q = 0; q < n_processes; ++q)
        if (receiving[q] > std::uint64_t(std::numeric_limits<int>::max()) ||
            sending[q] > std::uint64_t(std::numeric_limits<int>::max()))
          too_long = 1;
      MPI_Allreduce(MPI_IN_PLACE, &too_long, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
      if (too_long != 0)
        throw std::runtime_error("processes::exchange: a message of more than 2^31 entries between two processes");
      std::vector<std::vector<std::uint64_t>> incoming(n_processes);
      std::vector<MPI_Request>                requests;
      for (unsigned int q = 0; q < n_processes; ++q)
        {
          if (q == this_rank)
            continue;
          incoming[q].resize(receiving[q]);
          if (receiving[q] > 0)
            {
              requests.emplace_back();
              MPI_Irecv(incoming[q].data(), static_cast<int>(receiving[q]), MPI_UINT64_T, static_cast<int>(q), 0,
                        MPI_COMM_WORLD, &requests.back());
            }
          if (sending[q] > 0)
            {
              requests.emplace_back();
              MPI_Isend(outgoing[q].data(), static_cast<int>(sending[q]), MPI_UINT64_T, static_cast<int>(q), 0,
                        MPI_COMM_WORLD, &requests.back());
            }
        }
      MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
      return incoming;
    }



    dealii::types::global_dof_index
    first_owned_row(const dealii::types::global_dof_index n, const unsigned int block, const unsigned int r)
    {
      for (const auto &first_of_part : parts_by_size)
        if (first_of_part.back() == n)
          {
            if (first_of_part[r] % block != 0)
              throw std::logic_error("processes::owned_rows: the parts' rows are not in blocks of " +
                                     std::to_string(block));
            return first_of_part[r];
          }
      // In 64 bits: (n / block) r overflows a 32-bit index from n r = 2^32 on.
      const std::uint64_t blocks = n / block;
      return r == n_processes ? n : static_cast<dealii::types::global_dof_index>(block * ((blocks * r) / n_processes));
    }



    dealii::IndexSet
    owned_rows(const dealii::types::global_dof_index n, const unsigned int block)
    {
      dealii::IndexSet rows(n);
      rows.add_range(first_owned_row(n, block, rank()), first_owned_row(n, block, rank() + 1));
      return rows;
    }



    void
    own_rows_by_part(const std::vector<dealii::types::global_dof_index> &rows_of_part)
    {
      if (n_processes == 1)
        return;
      if (rows_of_part.size() != n_processes)
        throw std::logic_error("processes::own_rows_by_part: one count per process");
      std::vector<dealii::types::global_dof_index> first_of_part(1, 0);
      for (const auto rows : rows_of_part)
        first_of_part.push_back(first_of_part.back() + rows);
      const auto same_size = [&](const auto &other) { return other.back() == first_of_part.back(); };
      parts_by_size.erase(std::remove_if(parts_by_size.begin(), parts_by_size.end(), same_size), parts_by_size.end());
      parts_by_size.push_back(std::move(first_of_part));
    }



    void
    RowSums::reinit(dealii::DynamicSparsityPattern &entries, dealii::SparsityPattern &pattern, const unsigned int block)
    {
      const auto m = entries.n_rows();
      if (n_processes == 1)
        {
          pattern.copy_from(entries);
          return;
        }
      std::vector<dealii::types::global_dof_index> first(n_processes + 1);
      for (unsigned int q = 0; q <= n_processes; ++q)
        first[q] = first_owned_row(m, block, q);

      // 1. This process's entries in each other process's rows to their
      // owner (row, length, columns for each row with entries), which adds
      // them to its own rows.
      std::vector<std::vector<std::uint64_t>> outgoing(n_processes);
      for (unsigned int q = 0; q < n_processes; ++q)
        if (q != this_rank)
          for (auto row = first[q]; row < first[q + 1]; ++row)
            if (const auto length = entries.row_length(row); length > 0)
              {
                outgoing[q].push_back(row);
                outgoing[q].push_back(length);
                for (auto entry = entries.begin(row); entry != entries.end(row); ++entry)
                  outgoing[q].push_back(entry->column());
              }
      {
        const auto incoming = exchange(outgoing);
        std::vector<dealii::types::global_dof_index> columns;
        for (const auto &message : incoming)
          for (std::size_t k = 0; k < message.size();)
            {
              const auto row = message[k], length = message[k + 1];
              columns.assign(message.begin() + k + 2, message.begin() + k + 2 + length);
              entries.add_entries(row, columns.begin(), columns.end(), true);
              k += 2 + length;
            }
      }
      pattern.copy_from(entries);

      // 2. The pattern's rows of each other process as stored (its diagonal
      // first where square), one length per row, then the columns: the
      // owner finds where each value sum() sends adds in its own array.
      // (Counted by rows: an empty row's iterator is no valid entry, which
      // a Debug build stops at, and a rectangular pattern's others' rows
      // are mostly empty.)
      first_entry.assign(n_processes + 1, 0);
      std::size_t                     counted = 0;
      dealii::types::global_dof_index row     = 0;
      for (unsigned int q = 0; q <= n_processes; ++q)
        {
          for (; row < first[q]; ++row)
            counted += pattern.row_length(row);
          first_entry[q] = counted;
        }
      for (unsigned int q = 0; q < n_processes; ++q)
        {
          outgoing[q].clear();
          if (q == this_rank || first_entry[q + 1] == first_entry[q])
            continue;
          for (auto row = first[q]; row < first[q + 1]; ++row)
            outgoing[q].push_back(pattern.row_length(row));
          for (auto row = first[q]; row < first[q + 1]; ++row)
            for (unsigned int k = 0; k < pattern.row_length(row); ++k)
              outgoing[q].push_back(pattern.column_number(row, k));
        }
      const auto incoming = exchange(outgoing);
      received.assign(n_processes, {});
      const auto own_rows = first[this_rank + 1] - first[this_rank];
      for (unsigned int q = 0; q < n_processes; ++q)
        if (!incoming[q].empty())
          {
            std::size_t column = own_rows;
            for (dealii::types::global_dof_index k = 0; k < own_rows; ++k)
              {
                const auto row = first[this_rank] + k;
                for (std::uint64_t e = 0; e < incoming[q][k]; ++e, ++column)
                  {
                    const auto index = pattern(row, incoming[q][column]);
                    if (index == dealii::SparsityPattern::invalid_entry)
                      throw std::logic_error("processes::RowSums: an entry another process adds is not in the pattern");
                    received[q].push_back(index);
                  }
              }
          }
    }



    void
    RowSums::sum(dealii::SparseMatrix<double> &matrix) const
    {
      if (n_processes == 1)
        return;
      double *const values = const_cast<double *>(matrix_values(matrix));
      // The entries of each other process's rows to it, in slices of 2^27
      // (MPI counts are int; messages of one pair and tag arrive in order).
      constexpr std::size_t            slice = std::size_t(1) << 27;
      std::vector<std::vector<double>> incoming(n_processes);
      std::vector<MPI_Request>         requests;
      for (unsigned int q = 0; q < n_processes; ++q)
        {
          if (q == this_rank)
            continue;
          incoming[q].resize(received[q].size());
          for (std::size_t start = 0; start < incoming[q].size(); start += slice)
            {
              requests.emplace_back();
              MPI_Irecv(incoming[q].data() + start, static_cast<int>(std::min(slice, incoming[q].size() - start)),
                        MPI_DOUBLE, static_cast<int>(q), 1, MPI_COMM_WORLD, &requests.back());
            }
          for (std::size_t start = first_entry[q]; start < first_entry[q + 1]; start += slice)
            {
              requests.emplace_back();
              MPI_Isend(values + start, static_cast<int>(std::min(slice, first_entry[q + 1] - start)), MPI_DOUBLE,
                        static_cast<int>(q), 1, MPI_COMM_WORLD, &requests.back());
            }
        }
      MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
      for (unsigned int q = 0; q < n_processes; ++q)
        for (std::size_t k = 0; k < incoming[q].size(); ++k)
          values[received[q][k]] += incoming[q][k];
      // The other rows hold partial sums: NaN, so that a reader of rows not
      // its own fails at once instead of computing with them.
      if (values != nullptr)
        {
          std::fill(values, values + first_entry[this_rank], std::numeric_limits<double>::quiet_NaN());
          std::fill(values + first_entry[this_rank + 1], values + first_entry[n_processes],
                    std::numeric_limits<double>::quiet_NaN());
        }
    }



    void
    gather(dealii::Vector<double> &v, const unsigned int block)
    {
      if (n_processes == 1)
        return;
      std::vector<int> counts(n_processes), offsets(n_processes);
      for (unsigned int r = 0; r < n_processes; ++r)
        {
          offsets[r] = static_cast<int>(first_owned_row(v.size(), block, r));
          counts[r]  = static_cast<int>(first_owned_row(v.size(), block, r + 1)) - offsets[r];
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
    std::unique_ptr<dealii::Triangulation<dim>>
    new_triangulation()
    {
      if (n_processes == 1)
        return std::make_unique<dealii::Triangulation<dim>>();
      // The plain mesh's smoothing (none); every cell a process's own or a
      // ghost, none artificial, so that every process holds the whole mesh
      // and each cell's subdomain id is its owner.
      return std::make_unique<dealii::parallel::shared::Triangulation<dim>>(
        communicator(), dealii::Triangulation<dim>::none, false,
        dealii::parallel::shared::Triangulation<dim>::partition_metis);
    }

    template <int dim>
    void
    distribute_dofs(dealii::DoFHandler<dim> &dof_handler, const dealii::FiniteElement<dim> &fe)
    {
      dof_handler.distribute_dofs(fe);
      // A new mesh: the partitions of the last one's spaces are gone.
      parts_by_size.clear();
      if (n_processes == 1)
        return;
      // deal.II runs METIS on every process (not on one, broadcast): the
      // parts must agree, else the processes would assemble overlapping or
      // missing cells and wait for each other in different collectives.
      const auto &          triangulation = dof_handler.get_triangulation();
      dealii::Vector<double> parts(triangulation.n_active_cells());
      for (const auto &cell : triangulation.active_cell_iterators())
        parts[cell->active_cell_index()] = cell->subdomain_id();
      require_same(parts, "the mesh's parts (METIS)");
      number_dofs_by_part(dof_handler);
    }

    template <int dim>
    void
    number_dofs_by_part(dealii::DoFHandler<dim> &dof_handler)
    {
      if (n_processes == 1)
        return;
      // The shared mesh's DoFHandler numbered the dofs part by part already
      // (an interface dof with the part of smaller id, the order within a
      // part the serial one's: DoFRenumbering::subdomain_wise's numbering).
      std::vector<dealii::types::subdomain_id> part(dof_handler.n_dofs());
      dealii::DoFTools::get_subdomain_association(dof_handler, part);
      std::vector<dealii::types::global_dof_index> rows_of_part(n_processes, 0);
      for (const auto p : part)
        ++rows_of_part[p];
      own_rows_by_part(rows_of_part);
      // The rows this process owns are deal.II's own dofs of the handler (what
      // extract_constant_modes and the like read on a shared mesh).
      const dealii::IndexSet &own   = dof_handler.locally_owned_dofs();
      const auto              first = first_owned_row(dof_handler.n_dofs(), 1, this_rank);
      if (own.n_elements() != rows_of_part[this_rank] || !own.is_contiguous() ||
          (own.n_elements() > 0 && own.nth_index_in_set(0) != first))
        throw std::logic_error("processes::number_dofs_by_part: the dofs are not numbered by parts");
    }

    template std::unique_ptr<dealii::Triangulation<2>>
    new_triangulation();
    template std::unique_ptr<dealii::Triangulation<3>>
    new_triangulation();
    template void
    distribute_dofs(dealii::DoFHandler<2> &, const dealii::FiniteElement<2> &);
    template void
    distribute_dofs(dealii::DoFHandler<3> &, const dealii::FiniteElement<3> &);
    template void
    number_dofs_by_part(dealii::DoFHandler<2> &);
    template void
    number_dofs_by_part(dealii::DoFHandler<3> &);
  } // namespace processes
} // namespace dieflow
