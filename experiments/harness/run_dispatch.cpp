#include "experiments/harness/run_dispatch.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace hrad::experiment {

RunDispatch::RunDispatch(std::vector<RunId> pending, const std::vector<int>& workers,
                         double timeout_s, double now)
    : queue_(pending.begin(), pending.end()), timeout_s_(timeout_s) {
  if (!(timeout_s > 0)) throw std::invalid_argument("the worker timeout must be positive");
  for (int w : workers) workers_[w] = Worker{Worker::State::Starting, RunId{}, now};
}

RunDispatch::Worker& RunDispatch::worker(int w) {
  const auto it = workers_.find(w);
  if (it == workers_.end()) throw std::logic_error(fmt::format("rank {} is not a worker", w));
  return it->second;
}

const RunDispatch::Worker& RunDispatch::worker(int w) const {
  return const_cast<RunDispatch*>(this)->worker(w);
}

void RunDispatch::heard(int w, double t) {
  Worker& k = worker(w);
  k.last_heard = t;
  // Taken for dead while busy, it was only slow: it still runs that run (finished()
  // settles it, recorded or dropped as a duplicate). Never heard from: it is starting.
  if (k.state == Worker::State::Dead)
    k.state = k.has_run ? Worker::State::Busy : Worker::State::Starting;
}

std::optional<RunId> RunDispatch::ready(int w, double t) {
  heard(w, t);
  Worker& k = worker(w);
  // Skip runs recorded meanwhile (a re-queued run whose first worker came back).
  while (!queue_.empty() && done_.count(queue_.front())) queue_.pop_front();
  if (queue_.empty()) {
    k.state = Worker::State::Idle;
    return std::nullopt;
  }
  k.state = Worker::State::Busy;
  k.has_run = true;
  k.run = queue_.front();
  queue_.pop_front();
  return k.run;
}

bool RunDispatch::finished(int w, const RunId& id, double t) {
  heard(w, t);
  Worker& k = worker(w);
  if (k.state == Worker::State::Busy && k.run == id) k.state = Worker::State::Idle;
  const bool fresh = done_.insert(id).second;
  if (fresh) {
    // Its re-queued copy, if any, need not run; a given-up run has come back after all.
    queue_.erase(std::remove(queue_.begin(), queue_.end(), id), queue_.end());
    given_up_.erase(std::remove(given_up_.begin(), given_up_.end(), id), given_up_.end());
  }
  return fresh;
}

std::vector<RunDispatch::Loss> RunDispatch::check(double t) {
  std::vector<Loss> losses;
  for (auto& [w, k] : workers_) {
    const bool busy = k.state == Worker::State::Busy;
    if (!(busy || k.state == Worker::State::Starting) || t - k.last_heard <= timeout_s_) continue;
    k.state = Worker::State::Dead;
    Loss loss{w, busy ? std::optional<RunId>(k.run) : std::nullopt, t - k.last_heard, false};
    if (busy && !done_.count(k.run)) {
      if (lost_once_.insert(k.run).second) {
        queue_.push_front(k.run);
        loss.requeued = true;
      } else {
        given_up_.push_back(k.run);
      }
    }
    losses.push_back(loss);
  }
  return losses;
}

std::vector<std::pair<int, RunId>> RunDispatch::assign_waiting(double t) {
  std::vector<std::pair<int, RunId>> out;
  for (int w : idle_workers()) {
    if (queue_.empty()) break;
    if (const auto run = ready(w, t)) out.emplace_back(w, *run);
  }
  return out;
}

bool RunDispatch::over() const {
  if (std::any_of(queue_.begin(), queue_.end(), [&](const RunId& id) { return !done_.count(id); }))
    return false;
  return std::none_of(workers_.begin(), workers_.end(),
                      [](const auto& kv) { return kv.second.state == Worker::State::Busy; });
}

bool RunDispatch::stranded() const { return !over() && live_workers().empty(); }

std::vector<int> RunDispatch::idle_workers() const {
  std::vector<int> out;
  for (const auto& [w, k] : workers_)
    if (k.state == Worker::State::Idle) out.push_back(w);
  return out;
}

std::vector<int> RunDispatch::live_workers() const {
  std::vector<int> out;
  for (const auto& [w, k] : workers_)
    if (k.state != Worker::State::Dead) out.push_back(w);
  return out;
}

bool RunDispatch::dead(int w) const { return worker(w).state == Worker::State::Dead; }

std::optional<RunId> RunDispatch::running(int w) const {
  const Worker& k = worker(w);
  if (k.state == Worker::State::Busy) return k.run;
  return std::nullopt;
}

}  // namespace hrad::experiment
