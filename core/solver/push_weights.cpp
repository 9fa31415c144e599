#include "core/solver/push_weights.h"

#include "core/base/interrupt.h"
#include "core/parallel/parallel_any.h"
#include "core/transport/open_fraction.h"
#include "core/transport/transport.h"

#include <algorithm>
#include <numbers>
#include <unordered_map>
#include <utility>
#include <vector>

namespace hrad {

namespace {

// A surface source farther than this many of its radii from a child's centre is
// weighed by the differential form factor A cos cos / (pi d^2), within about 1 / k^2 of
// the exact value (the contour integral costs ten times as much): most of a deep
// element's chain is far from it, and the weights' normalisation takes out what is
// common to all children.
constexpr double kFarSource = 3.0;
// A chain of more than kPushExactChain links (each child's weight evaluates every one)
// is cut to its kPushExactChain strongest (by the link's own form factor x visibility x
// the source's radiosity, or without the radiosity when nothing is lit), and the rest
// add to every child the value their links give their receivers: the variation of the
// weakest links over P's children is left out. Of the builtin scenes only the cluttered
// furnace has longer chains (up to 1,256 links, at a few parents; the lab's longest
// hold 661, the office's 387), and every one's solution is bit for bit what it was (the
// cut links' share of a weight is below a float's last bit there). A polygon
// triangulated into 15,000 long slivers above a floor
// gave the floor's pieces chains of up to 11,000 links, every sliver near every child
// (3 of its radii are half its length): 195 M exact point evaluations and 16-30 s of
// push weights an iteration, after 1.3 s of refinement.
constexpr std::size_t kExactChain = kPushExactChain;
// Below this open-area mean of 1 - (a child's chain weight) the clusters above hand P
// next to nothing, and its children share it alike.
constexpr double kMinUncovered = 0.02;
// With push_visibility = child, a child's own visibility to a source is per unit of its
// open area (the rays count its closed-in part as blocked, and what the push hands on
// is per unit of open area), at most 1, its open fraction taken as at least
// kMinOpenFraction.

// A link of P's surface chain: its source, visibility and form factor.
struct ChainLink {
  const Element* source;
  double visibility;
  double form_factor;
};

double point_weight(const Vec3& x, const Vec3& n, const Element& s, const Transport& transport) {
  if (s.is_cluster()) return transport.form_factor_from_point(x, n, s);
  const Vec3 d = s.center - x;
  const double dist2 = d.squaredNorm();
  const double r = s.radius();
  if (dist2 < kFarSource * kFarSource * r * r) return transport.form_factor_from_point(x, n, s);
  const double cos_x = n.dot(d), cos_s = -s.normal.dot(d);
  if (!(cos_x > 0) || !(cos_s > 0)) return 0;
  return s.area * cos_x * cos_s / (std::numbers::pi * dist2 * dist2);
}

// The children's own visibilities to the partly visible sources of P's chain
// (push_visibility = child), from the previous update's `old` where it has the source,
// else from rays; kept in `now`, and row[e] is chain entry e's source's row there
// (entries with V = 0 or 1 have none: the link's value stands).
std::uint64_t own_visibilities(const Element& p, const Transport& transport,
                               const std::vector<ChainLink>& chain,
                               const PushWeights::ChildVisibility* old,
                               PushWeights::ChildVisibility& now, std::vector<std::size_t>& row) {
  const auto kids = p.child_span();
  const std::size_t n = kids.size();
  std::uint64_t rays = 0;
  now.sources.clear();
  for (const ChainLink& l : chain)
    if (l.visibility > 0 && l.visibility < 1) now.sources.push_back(l.source);
  std::sort(now.sources.begin(), now.sources.end());
  now.sources.erase(std::unique(now.sources.begin(), now.sources.end()), now.sources.end());
  now.visibility.assign(now.sources.size() * n, 0.0f);
  for (std::size_t j = 0; j < now.sources.size(); ++j) {
    const Element* s = now.sources[j];
    float* out = &now.visibility[j * n];
    if (old != nullptr) {
      const auto at = std::lower_bound(old->sources.begin(), old->sources.end(), s);
      if (at != old->sources.end() && *at == s) {
        const auto i = static_cast<std::size_t>(at - old->sources.begin());
        std::copy_n(old->visibility.begin() + static_cast<std::ptrdiff_t>(i * n), n, out);
        continue;
      }
    }
    for (std::size_t k = 0; k < n; ++k)
      out[k] = static_cast<float>(transport.visibility(kids[k], *s, rays));
  }
  row.resize(chain.size());
  for (std::size_t e = 0; e < chain.size(); ++e)
    row[e] = static_cast<std::size_t>(
        std::lower_bound(now.sources.begin(), now.sources.end(), chain[e].source) -
        now.sources.begin());
  return rays;
}

// What the links cut from a chain give every child alike (kExactChain).
struct Rest {
  double light = 0, geometry = 0;
};

// Cuts `chain` to its kExactChain strongest links (ties by source id, so that the cut
// does not depend on the order the links were stored in) and returns what the others
// give each child.
Rest cut_chain(std::vector<ChainLink>& chain, bool any_light, const Rgb& w) {
  Rest rest;
  if (chain.size() <= kExactChain) return rest;
  const auto strength = [any_light, &w](const ChainLink& l) {
    return l.form_factor * std::max(l.visibility, 0.0) *
           (any_light ? (w * l.source->B).sum() : 1.0);
  };
  const auto end = chain.begin() + static_cast<std::ptrdiff_t>(kExactChain);
  std::nth_element(chain.begin(), end, chain.end(), [&](const ChainLink& a, const ChainLink& b) {
    const double sa = strength(a), sb = strength(b);
    if (sa != sb) return sa > sb;
    if (a.source->id != b.source->id) return a.source->id < b.source->id;
    return a.visibility < b.visibility;
  });
  for (auto l = end; l != chain.end(); ++l) {
    if (!(l->visibility > 0)) continue;
    const double f = l->form_factor * l->visibility;
    rest.geometry += f;
    rest.light += f * (w * l->source->B).sum();
  }
  chain.erase(end, chain.end());
  return rest;
}

// Both sets of weights of P's children, into light[k] and geometry[k] (child k): the
// form factors from each child's centre to the sources of the links of P's surface
// chain (P and its surface ancestors up to its input polygon), times the links'
// visibility, and for `light` the sources' radiosity (all channels, times the channel
// weights `w`; the geometric weights when every source is dark), each set normalised to
// an open-area mean of 1 over the children (which also takes out the difference between
// the centre values and the links' own quadrature on average). A chain without links
// leaves both at 1.
std::uint64_t weigh_children(const Element& p, const Transport& transport, bool any_light,
                             const Rgb& w, PushVisibility mode, std::vector<ChainLink>& chain,
                             const PushWeights::ChildVisibility* old,
                             PushWeights::ChildVisibility* now, std::vector<std::size_t>& row,
                             float* light, float* geometry, float* cluster) {
  const auto kids = p.child_span();
  chain.clear();
  for (const Element* a = &p; a != nullptr && !a->is_cluster(); a = a->parent)
    for (const Link& l : a->links)
      chain.push_back({l.source, l.visibility(), static_cast<double>(l.form_factor)});
  if (chain.empty()) return 0;
  const Rest rest = cut_chain(chain, any_light, w);
  std::uint64_t rays = 0;
  const bool own = mode == PushVisibility::Child;
  if (own) rays = own_visibilities(p, transport, chain, old, *now, row);
  double open_area = 0, by_light = 0, by_geometry = 0, uncovered = 0;
  for (std::size_t k = 0; k < kids.size(); ++k) {
    const Element& c = kids[k];
    double wl = 0, wg = 0;
    const double open_share = std::max(open_weight(c), kMinOpenFraction);
    for (std::size_t e = 0; e < chain.size(); ++e) {
      const auto& [source, visibility, form_factor] = chain[e];
      if (!(visibility > 0)) continue;
      double v = visibility;
      if (own && visibility < 1)
        v = std::min(1.0,
                     static_cast<double>(now->visibility[row[e] * kids.size() + k]) / open_share);
      const double f = point_weight(c.center, c.normal, *source, transport) * v;
      wg += f;
      wl += f * (w * source->B).sum();
    }
    wg += rest.geometry;
    wl += rest.light;
    if (!any_light) wl = wg;
    light[k] = static_cast<float>(wl);
    geometry[k] = static_cast<float>(wg);
    // What the clusters above hand P comes from the directions its chain's sources
    // leave free: a child whose chain covers more of its hemisphere (a piece of a panel
    // 6 cm behind a drawer pedestal, which fills most of its view) gets less of it.
    cluster[k] = static_cast<float>(std::max(0.0, 1.0 - static_cast<double>(geometry[k])));
    const double area = c.area * open_weight(c);
    open_area += area;
    by_light += area * wl;
    by_geometry += area * wg;
    uncovered += area * static_cast<double>(cluster[k]);
  }
  for (std::size_t k = 0; k < kids.size(); ++k)
    cluster[k] = open_area > 0 && uncovered > kMinUncovered * open_area
                     ? static_cast<float>(cluster[k] * (open_area / uncovered))
                     : 1.0f;
  // The open-area mean of the weights is 1: P's irradiance is shared out, not made.
  const auto normalise = [&](float* w, double weighted) {
    const bool ok = weighted > 0 && open_area > 0;
    for (std::size_t k = 0; k < kids.size(); ++k)
      w[k] = ok ? static_cast<float>(w[k] * (open_area / weighted)) : 1.0f;
  };
  normalise(light, by_light);
  normalise(geometry, by_geometry);
  return rays;
}

}  // namespace

std::uint64_t PushWeights::update(const std::vector<Element*>& elements, const Transport& transport,
                                  int threads, PushVisibility mode, const Rgb& channel_weight) {
  const bool any_light =
      parallel_any(elements, threads, [](const Element* e) { return (e->B > 0).any(); });
  threads_ = threads;
  parents_.clear();
  offset_.assign(1, 0);
  for (Element* e : elements)
    if (!e->child_span().empty()) {
      parents_.push_back(e);
      offset_.push_back(offset_.back() + e->child_span().size());
    }
  light_.assign(offset_.back(), 1.0f);
  geometry_.assign(offset_.back(), 1.0f);
  cluster_.assign(offset_.back(), 1.0f);
  const auto n = static_cast<std::ptrdiff_t>(parents_.size());
  // The previous update's children's visibilities, by parent (push_visibility = child).
  std::unordered_map<const Element*, std::size_t> previous;
  if (mode == PushVisibility::Child)
    for (std::size_t i = 0; i < old_parents_.size(); ++i) previous.emplace(old_parents_[i], i);
  std::vector<ChildVisibility> now(mode == PushVisibility::Child ? parents_.size() : 0);
  std::vector<ChainLink> chain;
  std::vector<std::size_t> row;
  std::uint64_t rays = 0, evaluations = 0;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 64) firstprivate(chain, row) \
    reduction(+ : rays, evaluations)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const Element& p = *parents_[u];
    if (p.is_cluster() || interrupted()) continue;
    const std::size_t at = offset_[u];
    const ChildVisibility* old = nullptr;
    if (const auto it = previous.find(&p); it != previous.end()) old = &own_[it->second];
    rays += weigh_children(p, transport, any_light, channel_weight, mode, chain, old,
                           now.empty() ? nullptr : &now[u], row, &light_[at], &geometry_[at],
                           &cluster_[at]);
    evaluations += p.child_span().size() * chain.size();  // the chain as weigh_children cut it
  }
  throw_if_interrupted();
  evaluations_ = evaluations;
  own_ = std::move(now);
  old_parents_.clear();
  if (mode == PushVisibility::Child) old_parents_.assign(parents_.begin(), parents_.end());
  return rays;
}

void PushWeights::apply(bool geometric) const {
  const std::vector<float>& w = geometric ? geometry_ : light_;
  const auto n = static_cast<std::ptrdiff_t>(parents_.size());
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const auto kids = parents_[u]->child_span();
    for (std::size_t k = 0; k < kids.size(); ++k) {
      kids[k].push_weight = w[offset_[u] + k];
      kids[k].cluster_weight = cluster_[offset_[u] + k];
    }
  }
}

void update_push_weights(const std::vector<Element*>& elements, const Transport& transport,
                         int threads, bool geometric, PushVisibility mode) {
  PushWeights w;
  w.update(elements, transport, threads, mode);
  w.apply(geometric);
}

}  // namespace hrad
