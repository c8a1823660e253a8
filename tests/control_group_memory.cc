// The memory a batch job's or a container's control group leaves (control_group_room()), which the direct solvers' memory checks take where it is less than the machine's free memory.
//
// A job's processes are killed at its group's limit (Slurm's --mem, a
// container's memory limit) whatever the machine has free: a factorisation
// weighed against MemAvailable alone would be started, then killed. The
// kernel's files are written here as trees of their own (the same names and
// formats as /proc/self/cgroup and /sys/fs/cgroup on a machine), with
// limits, usages and inactive file caches chosen so that each room is
// known by hand:
//  - v1 (the memory controller's own tree, as on this AMD EPYC VM and on
//    clusters with Slurm's cgroup v1 plugin), a job step in a job: the
//    step unlimited (v1's 2^63 - 4096), the job 2.0 GB with 1.2 GB used of
//    which 0.2 GB inactive file cache: 1.0 GB;
//  - the same with the step limited to 1.5 GB, 0.8 GB used: 0.7 GB, the
//    tighter of the two;
//  - v2 (one tree, as on Debian bookworm with systemd), a scope in a slice:
//    the scope "max", the slice 3.0 GB with 2.5 GB used of which 0.5 GB
//    inactive file cache: 1.0 GB;
//  - a group used beyond its limit by cache alone (usage 1.1 GB of 1.0 GB,
//    0.3 GB inactive file): 0.2 GB;
//  - hybrid (a v2 tree without the memory controller, the memory
//    controller's v1 tree unlimited), no file at all: 0, no limit.
// Checked that it fails: the code before (which read /sys/fs/cgroup/
// memory.max and memory.current alone, the root of a v2 tree) made every
// limited case NO; the inactive cache not subtracted made the first v1,
// the v2 and the cache cases NO (the second v1 case, whose tighter group
// has no cache, stayed yes).
// By hand (2026-12-07, this VM's cgroup v1): die2d N1 degree 2 at 96
// cells across (384,842 unknowns), Method = direct, one process in a v1
// group of 1.2 GB: the code before was killed by the kernel (exit 137, not
// a word) in its first factorisation; now the run ends with exit 2 and
// "Linear solver/Method: the direct solver's factorisation of 384842
// unknowns needs about 0.52 GB (from CHOLMOD's analysis), more than the
// 0.39 GB free", summary.json written.
#include <dieflow/solvers/linear_solver.h>

#include "report.h"

#include <filesystem>
#include <fstream>
#include <string>

using namespace dieflow;

namespace
{
  const std::string root = "groups";

  void
  write(const std::string &file, const std::string &text)
  {
    std::filesystem::create_directories(std::filesystem::path(root + "/" + file).parent_path());
    std::ofstream(root + "/" + file) << text;
  }

  /// The room read from the tree under root with @p process_groups as /proc/self/cgroup.
  double
  room(const std::string &process_groups)
  {
    write("proc-self-cgroup", process_groups);
    return control_group_room(root + "/proc-self-cgroup", root + "/sys");
  }
} // namespace



int
main()
{
  std::filesystem::remove_all(root);
  const std::string unlimited_v1 = "9223372036854771712\n";
  // v1: the memory controller's tree, with another controller's line and an empty v2 line around it.
  write("sys/memory/memory.limit_in_bytes", unlimited_v1);
  write("sys/memory/memory.usage_in_bytes", "20000000000\n");
  write("sys/memory/job/memory.limit_in_bytes", "2000000000\n");
  write("sys/memory/job/memory.usage_in_bytes", "1200000000\n");
  write("sys/memory/job/memory.stat",
        "cache 300000000\nrss 900000000\ninactive_file 100000000\ntotal_cache 300000000\n"
        "total_inactive_file 200000000\n");
  write("sys/memory/job/step/memory.limit_in_bytes", unlimited_v1);
  write("sys/memory/job/step/memory.usage_in_bytes", "800000000\n");
  write("sys/memory/job/step/memory.stat", "total_inactive_file 0\n");
  const std::string v1_groups = "12:cpu,cpuacct:/job\n4:memory:/job/step\n0::/\n";
  report("v1, the job's group 2.0 GB, 1.2 GB used, 0.2 GB inactive cache, the step's unlimited: 1.0 GB",
         near(room(v1_groups), 1.0e9, 1));
  write("sys/memory/job/step/memory.limit_in_bytes", "1500000000\n");
  report("v1, the step's group also limited (1.5 GB, 0.8 GB used): 0.7 GB, the tighter",
         near(room(v1_groups), 0.7e9, 1));

  // v2: one tree; the root has no memory.max.
  write("sys/system.slice/memory.max", "3000000000\n");
  write("sys/system.slice/memory.current", "2500000000\n");
  write("sys/system.slice/memory.stat", "anon 1500000000\nfile 1000000000\nactive_file 500000000\ninactive_file 500000000\n");
  write("sys/system.slice/job.scope/memory.max", "max\n");
  write("sys/system.slice/job.scope/memory.current", "2000000000\n");
  report("v2, the slice 3.0 GB, 2.5 GB used, 0.5 GB inactive cache, the scope's max: 1.0 GB",
         near(room("0::/system.slice/job.scope\n"), 1.0e9, 1));

  write("sys/full/memory.max", "1000000000\n");
  write("sys/full/memory.current", "1100000000\n");
  write("sys/full/memory.stat", "inactive_file 300000000\n");
  report("v2, used beyond the limit by cache (1.1 GB of 1.0 GB, 0.3 GB inactive): 0.2 GB",
         near(room("0::/full\n"), 0.2e9, 1));

  report("hybrid: the v2 tree without the memory controller, v1's unlimited: no limit (0)",
         room("4:memory:/\n0::/user.slice/session-1.scope\n") == 0);
  report("no control group file: no limit (0)",
         control_group_room(root + "/no-such-file", root + "/sys") == 0);
  std::filesystem::remove_all(root);
}
