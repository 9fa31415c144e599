// `error`: an error-driven oracle. The error of a link is the power it carries
// times how uncertain its transport is:
//   err = rho_r * B_s * A_r * ( spread(F) + F * u(V) )
// where spread(F) is the variation of the point-to-source form factor over the
// receiver (an estimate of the error of a constant-basis link), and u(V) is 1
// when the visibility estimate is partial (0 < V < 1: a shadow boundary crosses
// the link) and 0 when the pair is fully visible or fully hidden. Clusters carry
// no spread estimate; for them the whole F counts as uncertain, weighted as in `bf`
// when they are occluded (oracles/oracle.h). A partly visible surface link whose
// shadow changes its receiver's light by more than kShadowContrast is refined, as in
// `bf`. Parameters (oracle.error.KEY): those of bf.
#include "core/hierarchy/element.h"
#include "oracles/oracle.h"

namespace hrad {
namespace {

class ErrorOracle final : public IOracle {
 public:
  explicit ErrorOracle(const PluginParams& p)
      : occluded_weight_(p.get_double("occluded_cluster_weight")),
        dark_floor_(p.get_double("dark_floor")),
        shadow_contrast_(p.get_double("shadow_contrast")) {}
  Verdict judge(const LinkEstimate& l, const OracleThresholds& t) const override {
    const bool partial = l.visibility > 0 && l.visibility < 1;
    const bool cluster = l.receiver->is_cluster() || l.source->is_cluster();
    const double uncertainty =
        cluster ? l.form_factor : l.form_factor_spread + (partial ? l.form_factor : 0.0);
    const double err = reflected_power_scale(*l.receiver, *l.source, t.channel_weight) *
                       uncertainty * occlusion_weight(l, occluded_weight_);
    const bool accept = err < receiver_threshold(l, t, dark_floor_) &&
                        !shadow_too_sharp(l, shadow_contrast_, t.channel_weight);
    return {accept ? Decision::Accept : Decision::Refine, err};
  }
  bool needs_spread() const override { return true; }
  const char* name() const override { return "error"; }

 private:
  double occluded_weight_, dark_floor_, shadow_contrast_;
};

const bool registered = register_oracle(
    "error", [](const PluginParams& p) { return std::make_unique<ErrorOracle>(p); },
    weighting_params());

}  // namespace
}  // namespace hrad
