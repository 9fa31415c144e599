// The scheduler and stage-driver benchmarks are registered at run time, one set per
// registered scheduler.
#pragma once

namespace hrad {

/// Registers BM_SchedulerCost/NAME for every name in scheduler_names(); call after
/// static initialisation (from main), before benchmark::Initialize.
void register_scheduler_benchmarks();

/// Registers BM_StageDriver/NAME (stage_bench.cpp), the stage driver with each
/// registered scheduler; the same conditions as register_scheduler_benchmarks.
void register_stage_benchmarks();

}  // namespace hrad
