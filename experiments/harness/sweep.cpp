#include "experiments/harness/sweep.h"

#include "core/config/options_io.h"

#include <fmt/format.h>

#include <stdexcept>

namespace hrad::experiment {

std::vector<SweepPoint> expand_sweep(const ExperimentConfig& c) {
  const SolverOptions base = base_options(c);
  std::size_t per_scene = 1;
  for (const SweepAxis& a : c.sweep) per_scene *= a.values.size();

  std::vector<SweepPoint> points;
  points.reserve(per_scene * c.scenes.size());
  for (const std::string& scene : c.scenes) {
    for (std::size_t k = 0; k < per_scene; ++k) {
      SweepPoint p;
      p.index = static_cast<int>(points.size());
      p.scene = scene;
      p.options = base;
      // Mixed-radix digits of k, the last axis least significant.
      std::vector<std::size_t> digit(c.sweep.size());
      std::size_t rest = k;
      for (std::size_t i = c.sweep.size(); i-- > 0;) {
        digit[i] = rest % c.sweep[i].values.size();
        rest /= c.sweep[i].values.size();
      }
      for (std::size_t i = 0; i < c.sweep.size(); ++i) {
        const nlohmann::json& v = c.sweep[i].values[digit[i]];
        p.values.emplace_back(c.sweep[i].key, v);
        apply_options_json(p.options, nlohmann::json{{c.sweep[i].key, v}}, "sweep");
      }
      try {
        validate_options(p.options);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(
            fmt::format("sweep point {} ({}): {}", p.index, describe_point(p), e.what()));
      }
      points.push_back(std::move(p));
    }
  }
  return points;
}

std::string describe_point(const SweepPoint& p) {
  std::string s;
  for (const auto& [key, value] : p.values)
    s += fmt::format("{}{}={}", s.empty() ? "" : " ", key,
                     value.is_string() ? value.get<std::string>() : value.dump());
  return s;
}

}  // namespace hrad::experiment
