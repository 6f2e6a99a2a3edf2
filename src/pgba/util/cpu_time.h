// CPU time of the process and of one thread, and the machine's load: what the benchmarks
// divide by the work to state a cost that holds on a shared machine, where the wall time
// stretches with the other users' load and the CPU time far less (what remains is cache
// and memory-bandwidth contention).
#pragma once

namespace pgba {

// CPU time (user + system) consumed so far by the whole process (every thread), seconds
// (getrusage RUSAGE_SELF).
double ProcessCpuSeconds();

// CPU time (user + system) of the calling thread so far, seconds (CLOCK_THREAD_CPUTIME_ID):
// the cost of a task that runs on one thread from start to end.
double ThreadCpuSeconds();

// Process CPU time from construction to Seconds().
class CpuTimer {
 public:
  CpuTimer() : start_(ProcessCpuSeconds()) {}
  double Seconds() const { return ProcessCpuSeconds() - start_; }

 private:
  double start_;
};

// The 1-minute load average (/proc/loadavg), NaN where it cannot be read.
double LoadAverage1Min();

}  // namespace pgba
