#include "core/push_weights.h"

#include "core/open_fraction.h"
#include "core/transport.h"

#include <algorithm>

namespace hrad {

namespace {

// The weights of P's children from P's own links: sum_l F(c, s_l) V_l b_l, with F from
// c's centre (one evaluation per child and link: the normalisation below takes out
// the difference between that and the link's own quadrature on average), b_l the
// source's radiosity (all channels) or 1 when `unweighted`.
void weigh_children(Element& p, const Transport& transport, bool unweighted) {
  const auto kids = p.child_span();
  double mine = 0;
  for (const Link& l : p.links)
    mine += l.transport() * (unweighted ? 1.0 : l.source->B.sum());
  if (!(mine > 0)) {
    for (Element& c : kids) c.push_weight = 1;
    return;
  }
  double open_area = 0, weighted = 0;
  for (Element& c : kids) {
    double w = 0;
    for (const Link& l : p.links)
      w += transport.form_factor_from_point(c.center, c.normal, *l.source) *
           static_cast<double>(l.visibility) * (unweighted ? 1.0 : l.source->B.sum());
    c.push_weight = static_cast<float>(w / mine);
    const double a = c.area * open_weight(c);
    open_area += a;
    weighted += a * w / mine;
  }
  // The open-area mean of the weights is 1: P's irradiance is shared out, not made.
  if (!(weighted > 0) || !(open_area > 0)) {
    for (Element& c : kids) c.push_weight = 1;
    return;
  }
  const double scale = open_area / weighted;
  for (Element& c : kids) c.push_weight = static_cast<float>(c.push_weight * scale);
}

}  // namespace

void update_push_weights(const std::vector<Element*>& elements, const Transport& transport,
                         int threads) {
  bool any_light = false;
  for (const Element* e : elements) any_light = any_light || (e->B > 0).any();
  const auto n = static_cast<std::ptrdiff_t>(elements.size());
#pragma omp parallel for num_threads(threads) schedule(dynamic, 64)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Element& p = *elements[static_cast<std::size_t>(i)];
    const auto kids = p.child_span();
    if (kids.empty()) continue;
    if (p.is_cluster() || p.links.empty()) {
      for (Element& c : kids) c.push_weight = 1;
      continue;
    }
    weigh_children(p, transport, !any_light);
  }
}

}  // namespace hrad
