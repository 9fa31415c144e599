// mpi_sweep.h with MPI: the only file of hrad that includes <mpi.h>.
//
// Messages (MPI_COMM_WORLD, bytes of JSON text, the tag says which):
//   hello      worker -> 0   host, pid, CPUs, core policy, OpenMP threads, environment,
//                            topology; the worker is ready
//   assign     0 -> worker   {point, repetition, number, dir, immediate}
//   heartbeat  both ways     empty: a solving worker every interval; rank 0 to each
//                            waiting worker every interval
//   result     worker -> 0   the run's rows (CSV text), its time, the wait before it;
//                            the worker is ready again
//   failed     worker -> 0   the run's error (or the signal that stopped it)
//   stop       0 -> worker   {finalize}: leave; without MPI_Finalize when a rank was lost
// Every wait is a poll (MPI_Iprobe / MPI_Test) with a short sleep, so no rank ever
// blocks on a dead peer or spins a core while it waits.
#include "experiments/harness/mpi_sweep.h"

#include "core/base/clock.h"
#include "core/base/interrupt.h"
#include "core/parallel/pin_plan.h"
#include "core/parallel/topology.h"
#include "core/scene/scene_loader.h"
#include "experiments/harness/accuracy.h"
#include "experiments/harness/core_share.h"
#include "experiments/harness/csv.h"
#include "experiments/harness/run_dispatch.h"
#include "experiments/harness/run_executor.h"
#include "experiments/harness/task_cost.h"

#include <fmt/format.h>
// MPI's C interface only: OpenMPI's (and MPICH's) mpi.h otherwise pulls in the
// deprecated C++ bindings, which live in a library hrad does not link.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <mutex>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

namespace hrad::experiment::mpi {
namespace {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

enum Tag : int { kHello = 1, kAssign, kHeartbeat, kResult, kFailed, kStop };

const auto g_epoch = Clock::now();
double now_s() { return seconds_since(g_epoch); }

bool g_initialized = false;
bool g_skip_finalize = false;  // a rank was lost, or this rank stops on an error

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw std::runtime_error(fmt::format("{}: {}", what, std::string(text, len)));
}

int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int world_size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

std::string host_name() {
  char host[256] = {};
  return ::gethostname(host, sizeof host - 1) == 0 ? host : "unknown";
}

// Sleeps between polls: 50 us, doubling up to `cap_s` while nothing comes. The cap
// trades hand-off latency against the CPU a waiting rank burns (rank 0's is in the
// manifest: mpi[].overhead.coordinator_cpu_s): rank 0 waits most of the time, so 1 ms;
// a worker between two runs polls every 0.1 ms (its polls also move its result
// message, which MPI sends only as both sides poll), then every 1 ms once it has
// waited 0.1 s (no run left for it).
constexpr double kCoordinatorNapS = 1e-3, kHandoffNapS = 1e-4, kWaitingNapS = 1e-3;
void nap(double& backoff_s, double cap_s = kCoordinatorNapS) {
  std::this_thread::sleep_for(std::chrono::duration<double>(backoff_s));
  backoff_s = std::min(backoff_s * 2, cap_s);
}

double process_cpu_s() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// A message that has arrived, or nothing (never blocks).
struct Message {
  int source = 0, tag = 0;
  std::string body;
};
std::optional<Message> poll(int source) {
  int flag = 0;
  MPI_Status st;
  check(MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st), "MPI_Iprobe");
  if (!flag) return std::nullopt;
  int count = 0;
  MPI_Get_count(&st, MPI_CHAR, &count);
  Message m{st.MPI_SOURCE, st.MPI_TAG, std::string(static_cast<std::size_t>(count), '\0')};
  check(MPI_Recv(m.body.data(), count, MPI_CHAR, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE),
        "MPI_Recv");
  return m;
}

// Sends in flight: the buffer lives until the send completes. A send to a rank that
// died may never complete; it is dropped after `give_up_s`.
class Outbox {
 public:
  void send(int dest, int tag, std::string body) {
    items_.push_back({std::move(body), MPI_REQUEST_NULL, now_s()});
    Item& it = items_.back();
    check(MPI_Isend(it.body.data(), static_cast<int>(it.body.size()), MPI_CHAR, dest, tag,
                    MPI_COMM_WORLD, &it.request),
          "MPI_Isend");
  }
  // Completes what it can; true when nothing is in flight.
  bool reap(double give_up_s) {
    for (auto it = items_.begin(); it != items_.end();) {
      int done = 0;
      if (MPI_Test(&it->request, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) done = 1;
      if (!done && now_s() - it->since > give_up_s) {
        // Left in flight on purpose: cancelling a send to a lost rank can hang.
        MPI_Request_free(&it->request);
        done = 1;
      }
      it = done ? items_.erase(it) : std::next(it);
    }
    return items_.empty();
  }
  // Waits (polling) until every send completed or `give_up_s` passed for it.
  void drain(double give_up_s) {
    double backoff = 5e-5;
    while (!reap(give_up_s)) nap(backoff);
  }

 private:
  struct Item {
    std::string body;
    MPI_Request request;
    double since;
  };
  std::list<Item> items_;  // stable addresses for the buffers
};

double heartbeat_interval(const Options& o) { return std::min(1.0, o.worker_timeout_s / 4); }

// ---------------------------------------------------------------------------------
// Worker ranks

// Which CPUs this worker runs on: its slice of the host's when it shares, else the
// launcher's. Collective over MPI_COMM_WORLD (every rank calls it once).
struct Placement {
  std::vector<int> cpus;
  std::string policy;   // "share k/m of CPUS", "inherit", or why sharing was not possible
  bool shares = false;  // bound to a slice of a host other workers share
};
Placement place_ranks(RankCores cores) {
  MPI_Comm local;
  check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local),
        "MPI_Comm_split_type");
  int local_size = 1;
  MPI_Comm_size(local, &local_size);
  // Each rank's world rank and CPU mask, gathered on every rank of the host.
  constexpr int kWords = CPU_SETSIZE / 64;
  std::vector<std::uint64_t> mine(kWords + 1, 0), all;
  const std::vector<int> cpus = allowed_cpus();
  mine[0] = static_cast<std::uint64_t>(world_rank());
  for (int c : cpus) mine[1 + c / 64] |= std::uint64_t{1} << (c % 64);
  all.resize(mine.size() * static_cast<std::size_t>(local_size));
  check(MPI_Allgather(mine.data(), kWords + 1, MPI_UINT64_T, all.data(), kWords + 1, MPI_UINT64_T,
                      local),
        "MPI_Allgather");
  MPI_Comm_free(&local);
  Placement p{cpus, "inherit"};
  if (world_rank() == 0 || cores == RankCores::Inherit) return p;
  int k = 0, m = 0;
  bool same = true;
  for (int i = 0; i < local_size; ++i) {
    const std::uint64_t* row = &all[static_cast<std::size_t>(i) * (kWords + 1)];
    if (row[0] == 0) continue;  // the coordinator takes no share
    if (row[0] < static_cast<std::uint64_t>(world_rank())) ++k;
    ++m;
    same = same && std::equal(row + 1, row + 1 + kWords, mine.begin() + 1);
  }
  if (m == 1) {
    p.policy = "share 1/1 (the only worker on its host)";
    return p;
  }
  if (!same) {
    p.policy = "inherit (the launcher bound the ranks of this host differently: left as bound)";
    return p;
  }
  if (static_cast<int>(cpus.size()) < m) {
    p.policy =
        fmt::format("inherit ({} workers on this host, {} CPUs: too few to share)", m, cpus.size());
    return p;
  }
  p.cpus = cpu_slice(cpus, k, m);
  bind_to_cpus(p.cpus);
  p.shares = true;
  p.policy = fmt::format("share {}/{} of {}", k + 1, m, format_pu_list(cpus));
  return p;
}

ojson rank_info(const Placement& place, const char* role) {
  ojson topo = ojson::object();
  try {
    const TopologyInfo t = discover_topology();
    topo = {{"packages", t.packages}, {"numa_nodes", t.numa_nodes},   {"cores", t.cores},
            {"pus", t.pus},           {"description", t.description}, {"synthetic", t.synthetic}};
  } catch (const std::exception& e) {
    topo = {{"error", e.what()}};
  }
  return {{"rank", world_rank()},
          {"role", role},
          {"host", host_name()},
          {"pid", ::getpid()},
          {"cpus", format_pu_list(place.cpus)},
          {"cpu_count", place.cpus.size()},
          {"cores", place.policy},
          {"shares_host", place.shares},
          {"omp_max_threads", omp_get_max_threads()},
          {"environment", relevant_environment()},
          {"topology", topo}};
}

// While a run solves on the main thread, this thread sends rank 0 a heartbeat every
// interval. Only it calls MPI meanwhile (MPI_THREAD_SERIALIZED: the main thread makes
// no MPI call until it has joined this one).
class Heartbeat {
 public:
  explicit Heartbeat(double interval_s) : thread_([this, interval_s] { beat(interval_s); }) {}
  ~Heartbeat() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

 private:
  void beat(double interval_s) {
    Outbox out;
    std::unique_lock lock(mutex_);
    while (!cv_.wait_for(lock, std::chrono::duration<double>(interval_s), [&] { return stop_; })) {
      lock.unlock();
      try {
        out.send(0, kHeartbeat, {});
        out.reap(10 * interval_s);
      } catch (const std::exception&) {
        // A heartbeat that cannot be sent: rank 0 will take this rank for lost.
      }
      lock.lock();
    }
    lock.unlock();
    try {
      out.drain(interval_s);
    } catch (const std::exception&) {
    }
  }
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

// A message from rank 0, polling; rank 0 silent for longer than the timeout (it sends
// waiting workers heartbeats) means it is gone.
Message from_coordinator(const Options& o) {
  const double start = now_s();
  double backoff = 5e-5;
  for (;;) {
    if (auto m = poll(0)) return *m;
    if (interrupted()) throw_if_interrupted();
    const double waited = now_s() - start;
    if (waited > o.worker_timeout_s)
      throw std::runtime_error(
          fmt::format("rank {}: rank 0 not heard from for {:g} s: taking it for lost and stopping",
                      world_rank(), o.worker_timeout_s));
    nap(backoff, waited < 0.1 ? kHandoffNapS : kWaitingNapS);
  }
}

// What every rank must agree on: the resolved configuration (so the same points).
std::string sweep_digest(const ManifestInputs& inputs, const std::vector<SweepPoint>& points) {
  return fmt::format("{:016x}/{}",
                     std::hash<std::string>{}(experiment_config_to_json(inputs.config).dump()),
                     points.size());
}

ExperimentSummary work(const ManifestInputs& inputs, const std::vector<SweepPoint>& points,
                       const RunnerSettings& settings, const Options& o, const Placement& place) {
  ExperimentSummary summary;
  Outbox out;
  ojson hello = rank_info(place, "worker");
  hello["sweep"] = sweep_digest(inputs, points);
  out.send(0, kHello, hello.dump());
  std::optional<RunExecutor> executor;
  double idle_since = now_s();
  for (;;) {
    const Message m = from_coordinator(o);
    out.reap(o.worker_timeout_s);
    if (m.tag == kHeartbeat) continue;
    if (m.tag == kStop) {
      if (!nlohmann::json::parse(m.body).value("finalize", true)) g_skip_finalize = true;
      out.drain(o.worker_timeout_s);
      return summary;
    }
    if (m.tag != kAssign)
      throw std::runtime_error(
          fmt::format("rank {}: unexpected message (tag {})", world_rank(), m.tag));
    const auto a = nlohmann::json::parse(m.body);
    const RunId id{a.at("point").get<int>(), a.at("repetition").get<int>()};
    const double wait_s = now_s() - idle_since;
    if (id.point < 0 || id.point >= static_cast<int>(points.size()))
      throw std::runtime_error(
          fmt::format("rank {}: point {} is not in the sweep", world_rank(), id.point));
    if (!executor)
      executor.emplace(inputs.config, fs::path(a.at("dir").get<std::string>()), settings.log,
                       /*quiet=*/true, inputs.git_revision, /*cached_references_only=*/true);
    const SweepPoint& p = points[static_cast<std::size_t>(id.point)];
    std::optional<RunOutcome> outcome;
    std::string error;
    int signal = 0;
    {
      Heartbeat beat(heartbeat_interval(o));
      try {
        outcome = executor->run(p, id.repetition, "");
      } catch (const Interrupted& e) {
        signal = e.signal();
        error = e.what();
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    if (!outcome) {
      out.send(0, kFailed,
               ojson{{"point", id.point},
                     {"repetition", id.repetition},
                     {"error", error},
                     {"signal", signal}}
                   .dump());
      out.drain(o.worker_timeout_s);
      if (signal) throw Interrupted(signal);
      idle_since = now_s();
      continue;  // rank 0 stops the sweep
    }
    std::string iterations;
    for (const Row& r : outcome->rows.iterations) iterations += csv_line(r);
    ojson result = {{"point", id.point},
                    {"repetition", id.repetition},
                    {"seconds", outcome->seconds},
                    {"task_cpu_ns", outcome->task_cpu_ns},
                    {"wait_s", wait_s},
                    {"immediate", a.value("immediate", false)},
                    {"run", csv_line(outcome->rows.run)},
                    {"iterations", iterations},
                    {"accuracy", nullptr}};
    if (outcome->accuracy)
      result["accuracy"] = {{"mean", outcome->accuracy->mean}, {"max", outcome->accuracy->max}};
    out.send(0, kResult, result.dump());
    idle_since = now_s();
    ++summary.ran;
  }
}

// ---------------------------------------------------------------------------------
// Rank 0

RunRows parse_rows(const nlohmann::json& r) {
  const CsvText run = parse_csv(r.at("run").get<std::string>());
  const CsvText its = parse_csv(r.at("iterations").get<std::string>());
  if (run.rows.size() != 1 || run.truncated || its.truncated ||
      run.rows[0].size() != run_columns().size())
    throw std::runtime_error("a worker's rows do not parse (another hrad version on that rank?)");
  for (const Row& row : its.rows)
    if (row.size() != iteration_columns().size())
      throw std::runtime_error("a worker's iteration rows do not parse");
  return {run.rows[0], its.rows};
}

ojson run_json(const RunId& id) { return {{"point", id.point}, {"repetition", id.repetition}}; }

class Coordinator {
 public:
  Coordinator(const ManifestInputs& inputs, const std::vector<SweepPoint>& points,
              const RunnerSettings& settings, const Options& o, const Placement& place)
      : inputs_(inputs), points_(points), settings_(settings), o_(o) {
    for (int w = 1; w < world_size(); ++w) workers_.push_back(w);
    session_ = {{"started_at", now_iso8601()},
                {"ranks", world_size()},
                {"workers", workers_.size()},
                {"coordinator", "rank 0 coordinates only (it runs no runs)"},
                {"rank_cores", o.cores == RankCores::Share ? "share" : "inherit"},
                {"worker_timeout_s", o.worker_timeout_s},
                {"ranks_info", ojson::array({rank_info(place, "coordinator")})},
                {"runs", ojson::array()},
                {"lost_ranks", ojson::array()}};
  }

  ExperimentSummary run() {
    start_ = now_s();
    cpu_start_ = process_cpu_s();
    const ExperimentConfig& config = inputs_.config;
    try {
      // Bad probe files are bad input: reported before the folder is made (and the
      // workers told to stop, as for every error here).
      if (config.accuracy.enabled)
        for (const SweepPoint& p : points_) (void)accuracy_probes(config.accuracy, p.scene);
      folder_.emplace(inputs_, points_, settings_.dir);
      summary_.runs = folder_->runs();
      summary_.skipped = folder_->skipped();
      number_ = summary_.skipped;
      if (!settings_.quiet)
        fmt::print(settings_.log, "hrad experiment: {} ranks: rank 0 coordinates, {} workers{}\n",
                   world_size(), workers_.size(),
                   summary_.skipped > 0
                       ? fmt::format("; resuming {}: {} of {} runs already done",
                                     settings_.dir.string(), summary_.skipped, summary_.runs)
                       : std::string());
      prepare_references();
      dispatch_.emplace(folder_->pending(), workers_, o_.worker_timeout_s, now_s());
      for (const auto& [w, t] : early_hellos_) hand_out(w, dispatch_->ready(w, t), false);
      early_hellos_.clear();
      loop();
      if (!dispatch_->given_up().empty() || dispatch_->stranded())
        throw std::runtime_error(fmt::format(
            "{} runs were not done: {}; the finished runs are kept, resume with --resume",
            summary_.runs - folder_->runs_done(),
            dispatch_->stranded() ? "no worker rank is left" : "each was lost on two ranks"));
    } catch (const std::exception& e) {
      // A signal may have stopped a worker without MPI_Finalize: do not wait for it.
      if (dynamic_cast<const Interrupted*>(&e)) g_skip_finalize = true;
      if (folder_) {
        finish_session();
        folder_->fail(e);
      }
      stop_workers();
      throw;
    }
    finish_session();
    folder_->complete();
    stop_workers();
    summary_.seconds = now_s() - start_;
    summary_.warnings = task_costs_.warnings();
    for (const std::string& w : notes_) summary_.warnings.push_back(w);
    return summary_;
  }

 private:
  // The accuracy references are traced here, before any run, so every worker compares
  // against the same one (read from the folder). Meanwhile the workers that say hello
  // wait, with heartbeats.
  void prepare_references() {
    if (!inputs_.config.accuracy.enabled) return;
    std::set<std::string> scenes;
    for (const SweepPoint& p : points_) scenes.insert(p.scene);
    std::exception_ptr error;
    std::atomic<bool> done{false};
    std::thread tracer([&] {
      try {
        for (const std::string& s : scenes) {
          if (fs::exists(settings_.dir / reference_file_name(s))) continue;
          const Scene scene = load_scene(s);
          (void)scene_reference(settings_.dir, s, scene, inputs_.config.accuracy,
                                static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
                                settings_.log, settings_.quiet);
        }
      } catch (...) {
        error = std::current_exception();
      }
      done = true;
    });
    double backoff = 5e-5, beat = now_s();
    while (!done) {
      while (auto m = poll(MPI_ANY_SOURCE)) {
        if (m->tag == kHello) {
          hello(*m);
          early_hellos_.emplace_back(m->source, now_s());
        }
      }
      if (now_s() - beat > heartbeat_interval(o_)) {
        for (const auto& [w, t] : early_hellos_) out_.send(w, kHeartbeat, {});
        beat = now_s();
      }
      out_.reap(o_.worker_timeout_s);
      nap(backoff);
    }
    tracer.join();
    if (error) std::rethrow_exception(error);
  }

  void hello(const Message& m) {
    auto info = ojson::parse(m.body);
    if (info.value("sweep", std::string()) != sweep_digest(inputs_, points_))
      throw std::runtime_error(fmt::format(
          "rank {} ({}) expanded another sweep than rank 0: every rank must read the same "
          "config file, --quick, --set and --resume folder (a shared file system)",
          m.source, info.value("host", "?")));
    info.erase("sweep");
    min_worker_cpus_ = std::min(min_worker_cpus_, info.value("cpu_count", 1 << 30));
    shared_hosts_ = shared_hosts_ || info.value("shares_host", false);
    session_["ranks_info"].push_back(std::move(info));
  }

  void hand_out(int w, const std::optional<RunId>& id, bool immediate) {
    if (!id) return;
    const SweepPoint& p = points_[static_cast<std::size_t>(id->point)];
    out_.send(w, kAssign,
              ojson{{"point", id->point},
                    {"repetition", id->repetition},
                    {"dir", settings_.dir.string()},
                    {"immediate", immediate}}
                  .dump());
    if (p.options.pin != PinPolicy::None && shared_hosts_ && !warned_pin_) {
      warned_pin_ = true;
      notes_.push_back(fmt::format(
          "point {} pins threads (pin={}) on workers that share a host: hrad pins to the "
          "host's PUs, not the worker's share, so workers' threads may meet on one core; "
          "run one worker per host (see docs/mpi.md)",
          p.index, p.options.pin));
    }
    if (p.options.threads > min_worker_cpus_ && !warned_threads_) {
      warned_threads_ = true;
      notes_.push_back(fmt::format(
          "point {} runs {} threads on a worker of {} CPUs: its threads share cores, and its "
          "times are not those of a dedicated machine",
          p.index, p.options.threads, min_worker_cpus_));
    }
  }

  void on_result(const Message& m) {
    const auto r = nlohmann::json::parse(m.body);
    const RunId id{r.at("point").get<int>(), r.at("repetition").get<int>()};
    const double t = now_s();
    const bool fresh = dispatch_->finished(m.source, id, t);
    // The next run first, so the worker does not wait for the rows to be written.
    hand_out(m.source, dispatch_->ready(m.source, t), true);
    if (!fresh) {
      session_["duplicates_dropped"] = session_.value("duplicates_dropped", 0) + 1;
      return;
    }
    folder_->record(id, parse_rows(r));
    const SweepPoint& p = points_[static_cast<std::size_t>(id.point)];
    const double seconds = r.at("seconds").get<double>();
    task_costs_.add(p.scene, p.options, r.at("task_cpu_ns").get<double>());
    ++summary_.ran;
    ++number_;
    run_seconds_ += seconds;
    session_["runs"].push_back({{"point", id.point},
                                {"repetition", id.repetition},
                                {"rank", m.source},
                                {"seconds", seconds},
                                {"wait_s", r.value("wait_s", 0.0)},
                                {"immediate", r.value("immediate", false)}});
    if (!settings_.quiet) {
      AccuracyFigures acc;
      const bool has_acc = r.contains("accuracy") && !r["accuracy"].is_null();
      if (has_acc) {
        acc.mean = r["accuracy"].at("mean").get<double>();
        acc.max = r["accuracy"].at("max").get<double>();
      }
      const double elapsed = t - start_;
      // Left: the mean run time so far x runs left, shared by the workers.
      const double left = run_seconds_ / summary_.ran * (summary_.runs - number_) /
                          std::max<std::size_t>(1, dispatch_->live_workers().size());
      fmt::print(settings_.log, "{} (rank {})\n",
                 run_line(run_label(number_, summary_.runs, p, id.repetition), seconds,
                          has_acc ? &acc : nullptr, elapsed, left),
                 m.source);
      std::fflush(settings_.log);
    }
  }

  void on_failed(const Message& m) {
    const auto r = nlohmann::json::parse(m.body);
    if (const int sig = r.value("signal", 0)) throw Interrupted(sig);
    throw std::runtime_error(fmt::format("rank {}: point {} repetition {}: {}", m.source,
                                         r.value("point", -1), r.value("repetition", -1) + 1,
                                         r.value("error", std::string("unknown error"))));
  }

  void report(const RunDispatch::Loss& loss) {
    std::string host = "?";
    for (const auto& info : session_["ranks_info"])
      if (info.value("rank", -1) == loss.worker) host = info.value("host", "?");
    const std::string what =
        loss.run
            ? fmt::format(
                  "its run (point {}, repetition {}) {}", loss.run->point, loss.run->repetition + 1,
                  loss.requeued ? "goes to another rank" : "was lost once already and is given up")
            : std::string("it never said ready");
    const std::string line = fmt::format("rank {} ({}) silent for {:.1f} s, taken for dead; {}",
                                         loss.worker, host, loss.silent_s, what);
    fmt::print(settings_.log, "hrad experiment: {}\n", line);
    std::fflush(settings_.log);
    notes_.push_back(line);
    ojson entry = {{"rank", loss.worker},
                   {"host", host},
                   {"silent_s", loss.silent_s},
                   {"at", now_iso8601()},
                   {"requeued", loss.requeued}};
    entry["run"] = loss.run ? run_json(*loss.run) : ojson();
    session_["lost_ranks"].push_back(entry);
    g_skip_finalize = true;
  }

  void loop() {
    double backoff = 5e-5, beat = now_s();
    while (!dispatch_->over() && !dispatch_->stranded()) {
      throw_if_interrupted();
      bool busy = false;
      while (auto m = poll(MPI_ANY_SOURCE)) {
        busy = true;
        const double t = now_s();
        switch (m->tag) {
          case kHello:
            hello(*m);
            // Not a hand-off: the wait before a rank's first run is start-up.
            hand_out(m->source, dispatch_->ready(m->source, t), false);
            break;
          case kHeartbeat: dispatch_->heard(m->source, t); break;
          case kResult: on_result(*m); break;
          case kFailed: on_failed(*m); break;
          default:
            throw std::runtime_error(
                fmt::format("rank {}: unexpected message (tag {})", m->source, m->tag));
        }
      }
      const double t = now_s();
      for (const RunDispatch::Loss& loss : dispatch_->check(t)) report(loss);
      for (const auto& [w, id] : dispatch_->assign_waiting(t)) hand_out(w, id, false);
      if (t - beat > heartbeat_interval(o_)) {
        for (int w : dispatch_->idle_workers()) out_.send(w, kHeartbeat, {});
        beat = t;
      }
      out_.reap(o_.worker_timeout_s);
      if (busy)
        backoff = 5e-5;
      else
        nap(backoff);
    }
  }

  void finish_session() {
    const double wall = now_s() - start_;
    double wait_sum = 0, wait_max = 0;
    int waits = 0;
    for (const auto& r : session_["runs"])
      if (r.value("immediate", false)) {
        const double w = r.value("wait_s", 0.0);
        wait_sum += w;
        wait_max = std::max(wait_max, w);
        ++waits;
      }
    const int n = static_cast<int>(session_["runs"].size());
    session_["finished_at"] = now_iso8601();
    session_["overhead"] = {
        {"wall_s", wall},
        {"coordinator_cpu_s", process_cpu_s() - cpu_start_},
        {"run_s_sum", run_seconds_},
        {"mean_run_s", n ? run_seconds_ / n : 0.0},
        {"handoff_wait_mean_s", waits ? wait_sum / waits : 0.0},
        {"handoff_wait_max_s", wait_max},
        {"handoff_waits", waits},
        {"handoff_fraction_of_run",
         waits && run_seconds_ > 0 ? (wait_sum / waits) / (run_seconds_ / n) : 0.0}};
    auto& m = folder_->manifest();
    if (!m.contains("mpi")) m["mpi"] = ojson::array();
    m["mpi"].push_back(session_);
  }

  void stop_workers() {
    std::vector<int> live;
    if (dispatch_)
      live = dispatch_->live_workers();
    else
      live = workers_;
    for (int w : live) out_.send(w, kStop, ojson{{"finalize", !g_skip_finalize}}.dump());
    out_.drain(2.0);
  }

  const ManifestInputs& inputs_;
  const std::vector<SweepPoint>& points_;
  const RunnerSettings& settings_;
  const Options& o_;
  std::vector<int> workers_;
  std::optional<ResultFolder> folder_;
  std::optional<RunDispatch> dispatch_;
  std::vector<std::pair<int, double>> early_hellos_;
  Outbox out_;
  ojson session_;
  ExperimentSummary summary_;
  TaskCostTable task_costs_;
  std::vector<std::string> notes_;  // thread warnings, lost ranks
  double start_ = 0, cpu_start_ = 0, run_seconds_ = 0;
  int number_ = 0, min_worker_cpus_ = 1 << 30;
  bool warned_threads_ = false, warned_pin_ = false, shared_hosts_ = false;
};

}  // namespace

bool built() { return true; }

void init() {
  int provided = 0;
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided), "MPI_Init_thread");
  g_initialized = true;
  // Errors come back as codes (check() turns them into exceptions) instead of
  // aborting the job, so a lost rank can be dealt with.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  if (provided < MPI_THREAD_SERIALIZED)
    throw std::runtime_error(
        "this MPI library does not allow calls from a second thread (MPI_THREAD_SERIALIZED), "
        "which the heartbeats need");
}

ExperimentSummary run_sweep(const ManifestInputs& inputs, const std::vector<SweepPoint>& points,
                            const RunnerSettings& settings, const Options& options) {
  if (!(options.worker_timeout_s > 0))
    throw std::invalid_argument("--worker-timeout must be positive");
  const Placement place = place_ranks(options.cores);
  if (world_rank() != 0) {
    try {
      return work(inputs, points, settings, options, place);
    } catch (...) {
      g_skip_finalize = true;
      throw;
    }
  }
  Coordinator c(inputs, points, settings, options, place);
  try {
    return c.run();
  } catch (...) {
    g_skip_finalize = true;
    throw;
  }
}

void end(int status) {
  std::fflush(nullptr);
  if (g_initialized && !g_skip_finalize) {
    MPI_Finalize();
    std::exit(status);
  }
  // OpenMPI's finalize waits for every rank, the lost ones too: leave without it.
  ::_exit(status);
}

}  // namespace hrad::experiment::mpi
