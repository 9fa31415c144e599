// `bf`: the classic oracle of Hanrahan, Salzman and Aupperle (1991): a link is
// good enough when the power it carries, rho_r * B_s * F_rs * A_r (largest
// channel, unoccluded F so that shadow boundaries are still refined), is below
// eps x total emitted power (tightened for a receiver darker than the scene's mean,
// receiver_threshold); a link with a cluster end that is partly or wholly occluded
// counts kOccludedClusterWeight times, and a partly visible surface link whose shadow
// changes its receiver's light by more than kShadowContrast is refined whatever its
// power (oracles/oracle.h). Parameters (oracle.bf.KEY): occluded_cluster_weight,
// dark_floor and shadow_contrast, the three constants of oracles/oracle.h. Element size
// limits (min_area) are applied by the refiner, for every oracle alike.
#include "core/hierarchy/element.h"
#include "oracles/oracle.h"

namespace hrad {
namespace {

class BfOracle final : public IOracle {
 public:
  explicit BfOracle(const PluginParams& p)
      : occluded_weight_(p.get_double("occluded_cluster_weight")),
        dark_floor_(p.get_double("dark_floor")),
        shadow_contrast_(p.get_double("shadow_contrast")) {}
  Verdict judge(const LinkEstimate& l, const OracleThresholds& t) const override {
    const double err = reflected_power_scale(*l.receiver, *l.source, t.channel_weight) *
                       l.form_factor * occlusion_weight(l, occluded_weight_);
    const bool accept = err < receiver_threshold(l, t, dark_floor_) &&
                        !shadow_too_sharp(l, shadow_contrast_, t.channel_weight);
    return {accept ? Decision::Accept : Decision::Refine, err};
  }
  const char* name() const override { return "bf"; }

 private:
  double occluded_weight_, dark_floor_, shadow_contrast_;
};

const bool registered = register_oracle(
    "bf", [](const PluginParams& p) { return std::make_unique<BfOracle>(p); }, weighting_params());

}  // namespace
}  // namespace hrad
