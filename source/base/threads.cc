// How many threads the assembly runs on, with deal.II's arithmetic fixed to one width so that the results do not depend on it.
#include <dieflow/base/processes.h>
#include <dieflow/base/threads.h>

#include <deal.II/base/multithread_info.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <string>

namespace dieflow
{
  namespace threads
  {
    namespace
    {
      std::unique_ptr<tbb::global_control> limit;
      unsigned int                         count = 1;
    } // namespace



    unsigned int
    requested()
    {
      if (const char *value = std::getenv("DEAL_II_NUM_THREADS"))
        {
          char *     end = nullptr;
          const long n   = std::strtol(value, &end, 10);
          if (end != value && *end == '\0' && n > 0)
            return static_cast<unsigned int>(n);
        }
      // The processes of an MPI run on this machine share its cores.
      return std::max(1u, dealii::MultithreadInfo::n_cores() / processes::on_this_machine());
    }



    void
    use(const unsigned int n)
    {
      count = std::clamp(n, 1u, arithmetic_width);
      limit.reset();
      unsetenv("DEAL_II_NUM_THREADS");
      dealii::MultithreadInfo::set_thread_limit(arithmetic_width);
      // With several global_control objects TBB obeys the smallest.
      limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, count);
    }



    unsigned int
    running()
    {
      return count;
    }
  } // namespace threads
} // namespace dieflow
