// Spreading the independent runs of a study over the cores.
//
// A study is a list of runs that share nothing but a read-only Model (each Run owns its
// State and Workspace), so they parallelise trivially: N threads take the next index from
// an atomic counter until the list is done. Tasks are taken in index order, so a caller
// that puts its longest tasks first gets the usual longest-first schedule.
#pragma once

#include <cstddef>
#include <functional>

namespace clothsim::analysis {

// Calls task(i) once for every i in [0, n) on min(jobs, n) threads (jobs <= 0: as many as
// the hardware has). `stop` is polled before each task; once it returns true no further
// task starts (running ones finish or poll it themselves). The first exception a task
// throws stops the others from starting and is rethrown here after every thread joined.
void parallel_for(std::size_t n, int jobs, const std::function<void(std::size_t)>& task,
                  const std::function<bool()>& stop = {});

// The thread count parallel_for uses for `jobs` (hardware_concurrency for jobs <= 0, at least 1).
int resolve_jobs(int jobs);

}  // namespace clothsim::analysis
