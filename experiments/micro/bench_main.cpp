// The microbenchmarks' main: BENCHMARK_MAIN's steps, after registering the benchmarks
// that depend on the plug-in registries (filled during static initialisation).
#include <benchmark/benchmark.h>

#include "experiments/micro/scheduler_bench.h"

int main(int argc, char** argv) {
  hrad::register_scheduler_benchmarks();
  hrad::register_stage_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
