// `bf`: the classic oracle of Hanrahan, Salzman and Aupperle (1991): a link is
// good enough when the power it carries, rho_r * B_s * F_rs * A_r (largest
// channel, unoccluded F so that shadow boundaries are still refined), is below
// eps x total emitted power (tightened for a receiver darker than the scene's mean,
// receiver_threshold); a link with a cluster end that is partly or wholly occluded
// counts kOccludedClusterWeight times (oracles/oracle.h). Element size
// limits (min_area) are applied by the refiner, for every oracle alike.
#include "core/hierarchy/element.h"
#include "oracles/oracle.h"

namespace hrad {
namespace {

class BfOracle final : public IOracle {
 public:
  Verdict judge(const LinkEstimate& l, const OracleThresholds& t) const override {
    const double err =
        reflected_power_scale(*l.receiver, *l.source) * l.form_factor * occlusion_weight(l);
    return {err < receiver_threshold(l, t) ? Decision::Accept : Decision::Refine, err};
  }
  const char* name() const override { return "bf"; }
};

const bool registered = register_oracle("bf", [] { return std::make_unique<BfOracle>(); });

}  // namespace
}  // namespace hrad
