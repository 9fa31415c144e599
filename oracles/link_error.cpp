// What every oracle weighs a link's error by: the power it reflects, and the
// occlusion weight of links with a cluster end; the threshold it is compared with,
// scaled for dark receivers; and the shadow test of partly visible surface links
// (oracles/oracle.h).
#include "core/hierarchy/element.h"
#include "oracles/oracle.h"

#include <algorithm>
#include <cmath>

namespace hrad {

double reflected_power_scale(const Element& r, const Element& s, const Rgb& w) {
  return (w * r.rho * s.B).maxCoeff() * r.area;
}

Rgb channel_weights(const Rgb& power) {
  const double strongest = power.maxCoeff();
  Rgb w = Rgb::Ones();
  if (!(strongest > 0) || !std::isfinite(strongest)) return w;
  for (int c = 0; c < 3; ++c)
    if (power[c] < strongest)
      w[c] = power[c] > strongest / kMaxChannelWeight ? strongest / power[c] : kMaxChannelWeight;
  return w;
}

double occlusion_weight(const LinkEstimate& l, double weight) {
  const bool cluster = l.receiver->is_cluster() || l.source->is_cluster();
  return cluster && l.visibility < 1 ? weight : 1.0;
}

double receiver_threshold(const LinkEstimate& l, const OracleThresholds& t, double floor) {
  const Element& r = *l.receiver;
  if (!(t.mean_irradiance > 0)) return t.eps_power;
  double irradiance = 0;
  bool gathered = false;
  for (int c = 0; c < 3; ++c) {
    const double reflected = r.B[c] - r.emission[c];
    gathered = gathered || reflected != 0;
    if (r.rho[c] > 0) irradiance = std::max(irradiance, t.channel_weight[c] * reflected / r.rho[c]);
  }
  // Nothing gathered yet (the first iteration): nothing known about its light.
  if (!gathered) return t.eps_power;
  return t.eps_power * std::clamp(irradiance / t.mean_irradiance, floor, 1.0);
}

bool shadow_too_sharp(const LinkEstimate& l, double contrast, const Rgb& weight) {
  const Element& r = *l.receiver;
  const Element& s = *l.source;
  if (!(contrast > 0) || r.is_cluster() || s.is_cluster()) return false;
  if (!(l.visibility > 0 && l.visibility < 1)) return false;
  const double reflected = (weight * (r.B - r.emission)).maxCoeff();
  if (!(reflected > 0)) return false;  // nothing gathered yet: nothing to compare with
  const double full = (weight * r.rho * s.B).maxCoeff() * l.form_factor;
  return full * 2 * std::min(l.visibility, 1 - l.visibility) > contrast * reflected;
}

std::vector<ParamSpec> weighting_params() {
  return {{"occluded_cluster_weight", ParamSpec::Type::Double, kOccludedClusterWeight, 1, 1000,
           "how many times its power an occluded link with a cluster end counts"},
          {"dark_floor", ParamSpec::Type::Double, kDarkThresholdFloor, 0.001, 1,
           "the tightest a dark receiver's threshold gets, as a fraction of eps (1: never "
           "tightened)"},
          {"shadow_contrast", ParamSpec::Type::Double, kShadowContrast, 0, 1,
           "a partly visible surface link is refined while its shadow changes its receiver's "
           "reflected radiosity by more than this fraction (0: never)"}};
}

}  // namespace hrad
