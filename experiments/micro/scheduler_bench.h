// The scheduler benchmarks are registered at run time, one set per registered scheduler.
#pragma once

namespace hrad {

/// Registers BM_SchedulerCost/NAME for every name in scheduler_names(); call after
/// static initialisation (from main), before benchmark::Initialize.
void register_scheduler_benchmarks();

}  // namespace hrad
