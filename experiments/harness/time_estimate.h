// How long an experiment will take on this machine, for `hrad experiment --dry-run`.
//
// A run's time depends mostly on its scene and eps, and on how many cores its threads
// get. So the estimate solves short pilots on this machine: for each group of points
// that differ only in eps and in how they run in parallel (threads, scheduler, block
// size, pinning, placement, pool order, seed, trace), two one-thread solves of the
// group's scene at 16 and 4 times the group's smallest eps (at most 1). Their times give
// the scene's own rate t ~ eps^-beta (beta = log(t4 / t16) / log 4, within [0, 1.5]; 0.8
// when the pilots are too short to time), which carries t4 to each point's eps. (Fixed
// costs, the scene's setup, open fractions and propagation, make beta small where they
// dominate: 0.06, 0.07 and 0.01 for the office, lab and cabin between 4e-4 and 1.6e-3.) A point on N
// threads is taken to run min(N, cores) x kParallelEfficiency times faster (N > 1),
// and no faster beyond the machine's cores. Accuracy references, which a result folder
// caches, are not counted.
//
// How far to trust it: on a 2-core machine, fig5-speedup.json was estimated at about
// 3 min and took 2.8 min, fig7-block-size.json 15 s and took 19 s; the parallel part is
// the ideal's, which a many-core machine may not reach. The pilots cost up to one
// one-thread run per group where eps hardly changes the time (fig5: 65 s; --no-estimate
// skips them).
#pragma once

#include "experiments/harness/experiment_config.h"
#include "experiments/harness/sweep.h"

#include <cstdio>
#include <string>
#include <vector>

namespace hrad::experiment {

inline constexpr double kParallelEfficiency = 0.9;
/// eps of the two pilots, in multiples of the group's smallest eps.
inline constexpr double kPilotNear = 4, kPilotFar = 16;

struct TimeEstimate {
  std::vector<double> point_seconds;  ///< one run of each point, in points' order
  double total_seconds = 0;           ///< every run, repetitions included
  double pilot_seconds = 0;           ///< what the pilots took
  int pilots = 0;
};

/// Runs the pilots (a line on `log` per group unless quiet) and estimates each point.
/// Throws what the scene loader or the solver throws (hrad::Interrupted included).
[[nodiscard]] TimeEstimate estimate_time(const ExperimentConfig& config,
                                         const std::vector<SweepPoint>& points, int cores,
                                         std::FILE* log, bool quiet);

/// The point's estimate from its group's pilots: `near` seconds at eps_near, `far` at
/// kPilotFar / kPilotNear times that; the point's eps and threads (see the file's comment).
[[nodiscard]] double scaled_estimate(double near, double far, double eps_near, double eps,
                                     int threads, int cores);

/// "about 2 min 30 s" style, rounded to what such an estimate is worth.
[[nodiscard]] std::string rough_duration(double seconds);

}  // namespace hrad::experiment
