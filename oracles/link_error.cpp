// What every oracle weighs a link's error by: the power it reflects, and the
// occlusion weight of links with a cluster end (oracles/oracle.h).
#include "core/element.h"
#include "oracles/oracle.h"

namespace hrad {

double reflected_power_scale(const Element& r, const Element& s) {
  return (r.rho * s.B).maxCoeff() * r.area;
}

double occlusion_weight(const LinkEstimate& l) {
  const bool cluster = l.receiver->is_cluster() || l.source->is_cluster();
  return cluster && l.visibility < 1 ? kOccludedClusterWeight : 1.0;
}

}  // namespace hrad
