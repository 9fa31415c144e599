// IOracle: decides, for one candidate link r <- s with its transport estimate,
// whether to accept it or to refine, and reports an error estimate that the
// `priority` scheduler orders by. Oracles are pure functions of the link, the
// frozen radiosities and the thresholds, so the link set never depends on the
// order in which tasks were examined.
#pragma once

#include "core/geometry.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hrad {

struct Element;

enum class Decision : std::uint8_t { Accept, Refine };

/// What the oracle sees of a link. Energies are per colour channel; the oracle
/// compares the largest channel.
struct LinkEstimate {
  const Element* receiver = nullptr;
  const Element* source = nullptr;
  double form_factor = 0;  ///< unoccluded F_rs
  double visibility = 1;   ///< in [0,1]
  /// Largest minus smallest point-to-source form factor over the receiver's
  /// sample points (0 when not computed, e.g. for clusters).
  double form_factor_spread = 0;
};

struct OracleThresholds {
  double eps_power = 0;  ///< absolute power threshold (eps x total emitted power)
};

struct Verdict {
  Decision decision = Decision::Accept;
  double error = 0;  ///< the oracle's error estimate, in power units
};

class IOracle {
 public:
  virtual ~IOracle() = default;
  [[nodiscard]] virtual Verdict judge(const LinkEstimate& link, const OracleThresholds& t) const = 0;
  /// True when the oracle wants form_factor_spread computed (it costs extra evaluations).
  [[nodiscard]] virtual bool needs_spread() const { return false; }
  [[nodiscard]] virtual const char* name() const = 0;
};

using OracleFactory = std::function<std::unique_ptr<IOracle>()>;
std::unique_ptr<IOracle> make_oracle(const std::string& name);
std::vector<std::string> oracle_names();
bool register_oracle(const std::string& name, OracleFactory factory);

/// Power reflected at r due to s per unit F, largest channel: rho_r * B_s * A_r.
double reflected_power_scale(const Element& r, const Element& s);

}  // namespace hrad
