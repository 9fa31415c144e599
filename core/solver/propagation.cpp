#include "core/solver/propagation.h"

#include "core/base/hash.h"
#include "core/base/interrupt.h"
#include "core/parallel/team_barrier.h"
#include "core/transport/cluster_exposure.h"
#include "core/transport/open_fraction.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <type_traits>

namespace hrad {

namespace {

// Who does what. The hierarchy is cut into subtrees: starting from the root, the
// heaviest subtree (by weight: its elements' links plus a constant per element for its
// push, pull and update) is opened, its root moved to the *top* and its children made
// subtrees, until the heaviest subtree weighs at most 1/kSubtreesPerPart of a part's
// share (or is a leaf). The subtrees are dealt to the parts, heaviest first, each to the
// part with the least weight so far, and a part's subtrees are kept in memory order.
// A sweep then needs two barriers whatever the depth of the hierarchy (and a
// propagation's sweeps share one parallel region, Sweeper): one thread gathers and
// pushes the top (a few hundred elements, parents first); each thread then goes through
// its part's elements, laid out one after another (Layout), forwards gathering and
// pushing, backwards pulling and finishing, so its data are touched by one core; after
// a barrier one thread pulls the top, children first. (Level-synchronous sweeps crossed
// a barrier after every level, down and up: thousands of barriers per run, each
// waiting for the slowest thread; on a loaded machine a thread that had lost its core
// held up every level.) A thread handles the same subtrees in every sweep, so they stay
// in its core's cache.
struct Partition {
  int parts = 1;
  std::vector<Element*> top;            // above the cut, parents before children
  std::vector<Element*> roots;          // subtree roots, part by part
  std::vector<std::size_t> part_begin;  // part t: roots[part_begin[t] .. part_begin[t + 1])
};

constexpr double kElementWeight = 4;  // push + pull + update, in links' worth of work
constexpr int kSubtreesPerPart = 8;

// Numbers the elements (Element::index = position in `elements`) for its own use.
Partition partition(const std::vector<Element*>& elements, int threads) {
  Partition p;
  p.parts = std::max(threads, 1);
  p.part_begin.assign(static_cast<std::size_t>(p.parts) + 1, 0);
  if (elements.empty()) return p;
  for (std::size_t i = 0; i < elements.size(); ++i)
    elements[i]->index = static_cast<std::uint32_t>(i);
  std::vector<double> weight(elements.size());  // of the subtree below each element
  for (std::size_t i = elements.size(); i-- > 0;) {
    const Element& e = *elements[i];
    weight[i] = kElementWeight + static_cast<double>(e.links.size());
    for (const Element& k : e.child_span()) weight[i] += weight[k.index];
  }
  const double target = weight[0] / (static_cast<double>(p.parts) * kSubtreesPerPart);
  const auto lighter = [&](const Element* a, const Element* b) {
    return weight[a->index] < weight[b->index] ||
           (weight[a->index] == weight[b->index] && a->index > b->index);
  };
  std::vector<Element*> open{elements[0]};  // a max-heap of subtrees by weight
  while (!open.empty()) {
    Element* heaviest = open.front();
    if (weight[heaviest->index] <= target || heaviest->child_span().empty()) break;
    std::pop_heap(open.begin(), open.end(), lighter);
    open.pop_back();
    p.top.push_back(heaviest);  // lighter than its parent: parents come first
    for (Element& k : heaviest->child_span()) {
      open.push_back(&k);
      std::push_heap(open.begin(), open.end(), lighter);
    }
  }
  // Heaviest first, each to the lightest part so far (ties: the lower part).
  std::sort(open.begin(), open.end(),
            [&](const Element* a, const Element* b) { return lighter(b, a); });
  std::vector<double> load(static_cast<std::size_t>(p.parts), 0.0);
  std::vector<std::vector<Element*>> parts(static_cast<std::size_t>(p.parts));
  for (Element* r : open) {
    const auto t =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[t] += weight[r->index];
    parts[t].push_back(r);
  }
  for (std::size_t t = 0; t < parts.size(); ++t) {
    std::sort(parts[t].begin(), parts[t].end(),
              [](const Element* a, const Element* b) { return a->index < b->index; });
    p.roots.insert(p.roots.end(), parts[t].begin(), parts[t].end());
    p.part_begin[t + 1] = p.roots.size();
  }
  return p;
}

// What an element's own links deliver, per unit of its whole area, becomes per unit
// of open area: the links' visibility already counted the closed-in part as blocked.
// A mostly closed-in leaf is divided by at most 1 / kMinOpenFraction, so that the noise
// of its few open samples (its w comes from kOpenPoints points, its links' visibility
// from a few rays) is not blown up; a wholly closed-in element gathers nothing. A
// parent's w is a mean over its children, not a small sample, and is used as it is.
double open_gain(const Element& e) {
  const double w = open_weight(e);
  if (w <= 0) return 0.0;
  const bool leaf = !e.is_cluster() && e.child_span().empty();
  return 1.0 / (leaf ? std::max(w, kMinOpenFraction) : w);
}

// How a sweep's leaves move (Chebyshev acceleration, see propagate): B_{k+1} =
// B_{k-1} + omega (G(B_k) - B_{k-1}), G the plain Jacobi update; omega 1 is the plain
// sweep. `older` (indexed by position, Layout) holds each leaf's B_{k-1} and is updated
// as the sweep goes; null: plain sweeps, nothing kept.
struct Relaxation {
  double omega = 1;
  std::vector<Rgb>* older = nullptr;
};

struct alignas(64) SweepChange {
  double change = 0, largest = 0;
};

// The elements in the order a pass visits them: the top first (parents first), then
// each part's subtrees depth first (preorder). A part is one range of positions, and
// every element comes after its parent, its subtree right after it: elements near each
// other in the hierarchy, which light each other most, get nearby value slots, so the
// gather's reads stay in fewer cache lines (breadth first, the cabin's sweeps took about
// 15 % longer). Element::index is set to the position: the gather matrix's row and value slot.
struct Layout {
  int parts = 1;
  std::vector<Element*> order;
  std::size_t top = 0;                  // positions [0, top): the top
  std::vector<std::size_t> part_begin;  // part t: positions [part_begin[t], part_begin[t + 1])
};

Layout lay_out(const std::vector<Element*>& elements, int threads) {
  const Partition p = partition(elements, threads);
  Layout l;
  l.parts = p.parts;
  l.order.reserve(elements.size());
  l.order.insert(l.order.end(), p.top.begin(), p.top.end());
  l.top = l.order.size();
  l.part_begin.push_back(l.top);
  std::vector<Element*> stack;
  for (std::size_t t = 0; t < static_cast<std::size_t>(p.parts); ++t) {
    for (std::size_t r = p.part_begin[t + 1]; r-- > p.part_begin[t];) stack.push_back(p.roots[r]);
    while (!stack.empty()) {
      Element* e = stack.back();
      stack.pop_back();
      l.order.push_back(e);
      const std::span<Element> kids = e->child_span();
      for (std::size_t k = kids.size(); k-- > 0;) stack.push_back(&kids[k]);
    }
    l.part_begin.push_back(l.order.size());
  }
  if (l.order.size() != elements.size())
    throw std::logic_error("propagation: the element list is not one hierarchy");
  for (std::size_t i = 0; i < l.order.size(); ++i)
    l.order[i]->index = static_cast<std::uint32_t>(i);
  return l;
}

// What a pass reads and writes of every element, by position (Layout), in dense arrays
// that it streams through, instead of the elements themselves (456 bytes each, a pass
// touching four or five of their cache lines in hierarchy order). Made with its layout
// and kept with it (PropagationCache) while the hierarchy is the same, refreshed from
// the elements before each pass; a pass writes their B, gathered and next back at the
// end (write_back). A cluster's ClusterLight is used where it is.
class PassState {
 public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  enum Flag : std::uint8_t { kCluster = 1, kLeaf = 2, kChain = 4, kUnderCluster = 8 };

  // The scalars of one element, read together.
  struct Node {
    std::uint32_t parent;     // position, kNone at the root
    std::uint32_t first_kid;  // kids_[first_kid .. next node's first_kid): children
    std::uint8_t flags;
    std::uint32_t xslot;   // under a cluster with exposures: its place in xin_ / xout_, else kNone
    float push_weight;     // Element::push_weight
    float gather_scale;    // Element::gather_scale
    float cluster_scale;   // Element::cluster_scale
    float cluster_weight;  // Element::cluster_weight
    double gain;           // open_gain
    double weight;         // area x open weight: its share of its parent's pull
    double area;
  };

  // The layout's structure (parents, children, kinds), then refresh().
  PassState(const Layout& l, int threads) : layout_(l) {
    const std::size_t n = l.order.size();
    node_.resize(n + 1);
    emission_.resize(n);
    rho_.resize(n);
    B_.resize(n);
    next_.resize(n);
    gathered_.resize(n);
    normal_.resize(n);
    light_.resize(n);
    // The children's positions, counted first (each element read once in parallel).
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
      const auto u = static_cast<std::size_t>(i);
      const Element& e = *l.order[u];
      Node& d = node_[u];
      d.parent = e.parent ? e.parent->index : kNone;
      d.first_kid = static_cast<std::uint32_t>(e.child_span().size());  // until the sums below
      const bool cluster = e.is_cluster(), parent_cluster = e.parent && e.parent->is_cluster();
      d.flags = static_cast<std::uint8_t>((cluster ? kCluster : 0) |
                                          (e.child_span().empty() ? kLeaf : 0) |
                                          (e.parent && !parent_cluster && !cluster ? kChain : 0) |
                                          (parent_cluster ? kUnderCluster : 0));
      // 0 marks a member of a cluster with exposures (numbered below); reading its
      // parent's ClusterLight here, in parallel, spares the serial loop the cache misses
      // (on the cabin, 0.07 s a build on one thread).
      const bool exposed = e.parent && e.parent->light && !e.parent->light->exposure.empty();
      d.xslot = exposed ? 0 : kNone;
    }
    std::uint32_t kids = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t count = node_[i].first_kid;
      node_[i].first_kid = kids;
      kids += count;
    }
    node_[n].first_kid = kids;
    kids_.resize(kids);
    // The members' exposures within their clusters (cluster_exposure.h), in pass order.
    for (std::size_t i = 0; i < n; ++i) {
      if (node_[i].xslot == kNone) continue;
      const Element& e = *l.order[i];
      node_[i].xslot = static_cast<std::uint32_t>(xout_.size());
      const std::array<float, 6>& x = exposure_within_parent(e);
      // What the pull weighs the member's light by along each axis direction: its
      // exposure, times its axis share for a polygon (add_by_axis).
      std::array<float, 6> out{};
      const std::array<double, 6> w =
          e.is_cluster() ? std::array<double, 6>{1, 1, 1, 1, 1, 1} : axis_shares(e.normal);
      for (std::size_t k = 0; k < 6; ++k)
        out[k] = static_cast<float>(w[k] * static_cast<double>(x[k]));
      xout_.push_back(out);
    }
    xin_.resize(xout_.size());
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
      const auto u = static_cast<std::size_t>(i);
      std::uint32_t* k = kids_.data() + node_[u].first_kid;
      for (const Element& c : l.order[u]->child_span()) *k++ = c.index;
    }
    refresh(threads);
  }

  /// Reads what may have changed since the last pass on the same hierarchy from the
  /// elements (push weights, row-sum scales, open fractions, radiosity; emission and
  /// reflectance too), numbers them again (another pass may have), and sums the
  /// clusters' open areas.
  void refresh(int threads) {
    const std::vector<Element*>& order = layout_.order;
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(order.size()); ++i) {
      const auto u = static_cast<std::size_t>(i);
      Element& e = *order[u];
      Node& d = node_[u];
      e.index = static_cast<std::uint32_t>(u);
      d.push_weight = e.push_weight;
      d.cluster_weight = e.cluster_weight;
      d.gather_scale = e.gather_scale;
      d.cluster_scale = e.cluster_scale;
      d.gain = open_gain(e);
      d.weight = e.area * open_weight(e);
      d.area = e.area;
      emission_[u] = e.emission;
      rho_[u] = e.rho;
      B_[u] = e.B;
      normal_[u] = e.normal;
      if (e.is_cluster() && !e.light) e.light = std::make_unique<ClusterLight>();
      light_[u] = e.light.get();
    }
    prepare_clusters(threads);
  }

  [[nodiscard]] const Layout& layout() const { return layout_; }
  [[nodiscard]] std::size_t size() const { return B_.size(); }
  [[nodiscard]] bool cluster(std::size_t i) const { return (node_[i].flags & kCluster) != 0; }
  [[nodiscard]] const Rgb& B(std::size_t i) const { return B_[i]; }
  [[nodiscard]] ClusterLight* light(std::size_t i) const { return light_[i]; }
  [[nodiscard]] double gain(std::size_t i) const { return node_[i].gain; }
  Rgb& gathered(std::size_t i) { return gathered_[i]; }

  /// The push (one element, its parent done): below an input polygon, what its surface
  /// chain gathered (the parent's links and those of its surface ancestors) is shared
  /// out by the push weights; what came from the clusters above passes on as it came
  /// (core/solver/push_weights.h). Once pushed, a surface element's `gathered` holds its
  /// surface chain's irradiance for its children.
  void push(std::size_t i, bool cosine) {
    const Node& d = node_[i];
    if (d.parent == kNone) {
      next_[i] = gathered_[i];
      return;
    }
    const std::size_t p = d.parent;
    if ((d.flags & kChain) != 0) {
      const Rgb chain = gathered_[i] + static_cast<double>(d.push_weight) * gathered_[p];
      next_[i] = static_cast<double>(d.cluster_weight) * (next_[p] - gathered_[p]) + chain;
      gathered_[i] = chain;
      return;
    }
    next_[i] = gathered_[i] + next_[p];
    if (!cosine || (d.flags & kUnderCluster) == 0) return;
    const std::array<Rgb, 6>& up = light_[p]->arriving;
    if (d.xslot != kNone) {  // by exposure (prepare_exposures)
      const std::array<float, 6>& in = xin_[d.xslot];
      if ((d.flags & kCluster) != 0) {
        for (std::size_t k = 0; k < 6; ++k)
          light_[i]->arriving[k] += static_cast<double>(in[k]) * up[k];
      } else {
        for (std::size_t k = 0; k < 6; ++k) next_[i] += static_cast<double>(in[k]) * up[k];
      }
    } else if ((d.flags & kCluster) != 0) {
      for (std::size_t k = 0; k < 6; ++k) light_[i]->arriving[k] += up[k];
    } else {
      // The member's share of each axis direction, as add_by_axis splits its area.
      const std::array<double, 6> w = axis_shares(normal_[i]);
      for (std::size_t k = 0; k < 6; ++k) next_[i] += w[k] * up[k];
    }
  }

  /// The pull (one element, its children done). A parent's radiosity is the mean of its
  /// children's over their open area (core/transport/open_fraction.h): a closed-in part
  /// shows no radiosity to anyone. Parents are linear in their leaves, so relaxing the
  /// leaves relaxes every element.
  void pull(std::size_t i, const Relaxation& relax) {
    const Node& d = node_[i];
    if ((d.flags & kLeaf) != 0) {
      // After the push, gathered_ holds what the surface chain gathered and next_ that
      // plus what came from the clusters above (push).
      if (d.cluster_scale == d.gather_scale)
        next_[i] = emission_[i] + rho_[i] * (static_cast<double>(d.gather_scale) * next_[i]);
      else
        next_[i] = emission_[i] +
                   rho_[i] * (static_cast<double>(d.gather_scale) * gathered_[i] +
                              static_cast<double>(d.cluster_scale) * (next_[i] - gathered_[i]));
      if (relax.older) {
        Rgb& older = (*relax.older)[i];
        const Rgb before = older;
        older = B_[i];
        if (relax.omega != 1) next_[i] = before + relax.omega * (next_[i] - before);
      }
      // The solution is at least the emission (the transport's terms are not
      // negative), but an extrapolated sweep can step below it where a leaf gathers
      // almost nothing: a floor under a closed room, lit only through round-off, came
      // out at -5e-14. Such a step is cut off at the emission, where the solution lies.
      next_[i] = next_[i].max(emission_[i]);
      return;
    }
    const std::uint32_t* kid = kids_.data() + d.first_kid;
    const std::uint32_t* const end = kids_.data() + node_[i + 1].first_kid;
    if ((d.flags & kCluster) != 0) {
      // What leaves the cluster along each axis direction (see ClusterLight).
      std::array<Rgb, 6>& leaving = light_[i]->leaving_next;
      leaving.fill(Rgb::Zero());
      for (const std::uint32_t* k = kid; k != end; ++k) {
        const std::uint32_t slot = node_[*k].xslot;
        if (slot != kNone) {  // weighed by exposure
          const std::array<float, 6>& out = xout_[slot];
          if (cluster(*k)) {
            const std::array<Rgb, 6>& from = light_[*k]->leaving_next;
            for (std::size_t j = 0; j < 6; ++j) leaving[j] += static_cast<double>(out[j]) * from[j];
          } else {
            const Rgb b = node_[*k].weight * next_[*k];
            for (std::size_t j = 0; j < 6; ++j) leaving[j] += static_cast<double>(out[j]) * b;
          }
        } else if (cluster(*k)) {
          for (std::size_t j = 0; j < 6; ++j) leaving[j] += light_[*k]->leaving_next[j];
        } else {
          add_by_axis(leaving, normal_[*k], Rgb(node_[*k].weight * next_[*k]));
        }
      }
    }
    Rgb sum = Rgb::Zero();
    double open_area = 0;
    for (const std::uint32_t* k = kid; k != end; ++k) {
      sum += node_[*k].weight * next_[*k];
      open_area += node_[*k].weight;
    }
    if (open_area > 0) {
      next_[i] = sum / open_area;
    } else {  // wholly closed in: the plain mean (nobody sees it either way)
      sum = Rgb::Zero();
      for (const std::uint32_t* k = kid; k != end; ++k) sum += node_[*k].area * next_[*k];
      next_[i] = d.area > 0 ? Rgb(sum / d.area) : Rgb::Zero();
    }
  }

  /// The last step of an element's sweep, once its `next` is final: B <- next (and the
  /// cluster's directional sums), with the change recorded.
  void finish(std::size_t i, SweepChange& c) {
    c.change = std::max(c.change, (next_[i] - B_[i]).abs().maxCoeff());
    c.largest = std::max(c.largest, next_[i].abs().maxCoeff());
    B_[i] = next_[i];
    if (ClusterLight* cl = light_[i]) {
      cl->leaving = cl->leaving_next;
      cl->leaving_made = true;
    }
  }

  /// Hands the elements their B, gathered and next.
  void write_back(int threads) const {
    const auto n = static_cast<std::ptrdiff_t>(size());
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      Element& e = *layout_.order[u];
      e.B = B_[u];
      e.gathered = gathered_[u];
      e.next = next_[u];
    }
  }

 private:
  // Every cluster's members' open area by axis direction, children before parents:
  // each part in parallel, then the top.
  void prepare_clusters(int threads) {
    const auto prepare = [&](std::size_t i) {
      if (!cluster(i)) return;
      std::array<double, 6>& oa = light_[i]->open_area;
      std::array<double, 6>& ea = light_[i]->exposed_area;
      oa.fill(0);
      ea.fill(0);
      for (std::uint32_t j = node_[i].first_kid; j < node_[i + 1].first_kid; ++j) {
        const std::uint32_t k = kids_[j];
        const std::uint32_t slot = node_[k].xslot;
        if (cluster(k)) {
          for (std::size_t a = 0; a < 6; ++a) {
            oa[a] += light_[k]->open_area[a];
            ea[a] += (slot != kNone ? static_cast<double>(xout_[slot][a]) : 1.0) *
                     light_[k]->exposed_area[a];
          }
        } else {
          const std::array<double, 6> w = axis_shares(normal_[k]);
          for (std::size_t a = 0; a < 6; ++a) {
            oa[a] += w[a] * node_[k].weight;
            ea[a] += (slot != kNone ? static_cast<double>(xout_[slot][a]) : w[a]) * node_[k].weight;
          }
        }
      }
    };
    const Layout& l = layout_;
#pragma omp parallel for num_threads(std::min(threads, l.parts)) schedule(dynamic, 1)
    for (int t = 0; t < l.parts; ++t)
      for (std::size_t i = l.part_begin[static_cast<std::size_t>(t) + 1];
           i-- > l.part_begin[static_cast<std::size_t>(t)];)
        prepare(i);
    for (std::size_t i = l.top; i-- > 0;) prepare(i);
    prepare_exposures(threads);
  }

  // What the push weighs the light arriving at a member's cluster by along each axis
  // direction: per unit of the cluster's exposed area (its open area over its exposed
  // area), times the member's exposure, times its axis share for a polygon or over its
  // own gain for a cluster (whose own push divides by it again). The total over the
  // members is what arrived. Along a direction in which no member is exposed, the
  // members share it alike (else it would be lost).
  void prepare_exposures(int threads) {
    const auto n = static_cast<std::ptrdiff_t>(size());
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const Node& d = node_[static_cast<std::size_t>(i)];
      if (d.xslot == kNone) continue;
      const ClusterLight& parent = *light_[d.parent];
      std::array<float, 6>& in = xin_[d.xslot];
      const bool is_cluster = cluster(static_cast<std::size_t>(i));
      const std::array<double, 6> w =
          is_cluster ? std::array<double, 6>{1, 1, 1, 1, 1, 1} : axis_shares(normal_[i]);
      for (std::size_t k = 0; k < 6; ++k) {
        if (!(parent.exposed_area[k] > 0)) {  // every member hidden: shared alike
          in[k] = static_cast<float>(w[k]);
          continue;
        }
        double g = static_cast<double>(xout_[d.xslot][k]) * exposure_gain(parent, k);
        if (is_cluster) g /= exposure_gain(*light_[static_cast<std::size_t>(i)], k);
        in[k] = static_cast<float>(g);
      }
    }
  }

  // A cluster's open area over its exposed area along axis direction k: what a unit of
  // irradiance per open area is per exposed area (1 where nothing is exposed).
  static double exposure_gain(const ClusterLight& l, std::size_t k) {
    return l.exposed_area[k] > 0 ? l.open_area[k] / l.exposed_area[k] : 1.0;
  }

  const Layout& layout_;
  std::vector<Node> node_;  // one more than elements: the end of the last one's children
  std::vector<std::uint32_t> kids_;
  std::vector<Rgb> emission_, rho_, B_, next_, gathered_;
  std::vector<Vec3> normal_;
  std::vector<ClusterLight*> light_;
  // Per member under a cluster with exposures (Node::xslot; cluster_exposure.h): the
  // push's and the pull's weights along each axis direction (prepare_exposures, the
  // constructor).
  std::vector<std::array<float, 6>> xin_, xout_;
};

// A pass over the hierarchy (see Partition), in three pieces: one thread gathers and
// pushes the top (down over its positions); then every thread of the team does its
// parts (down over each part's positions, with a full pass then up over them); with a
// full pass, one thread then pulls and finishes the top (up over its positions). The
// team meets at a barrier between the pieces. An element is finished (then
// `stored(i)`) as soon as its pull is done, its largest change and radiosity recorded
// in per_part[its part] (the top's in per_part.back()). `gather` must read nothing
// that `stored` or finish write in the same pass (the sweeper reads last sweep's
// values and stores into the next's). A team smaller than the parts takes several
// parts each.
template <class Gather>
void down(PassState& s, std::size_t begin, std::size_t end, bool cosine, const Gather& gather) {
  for (std::size_t i = begin; i < end; ++i) {
    gather(i);
    s.push(i, cosine);
  }
}

template <class Stored>
void up(PassState& s, std::size_t begin, std::size_t end, const Relaxation& relax,
        const Stored& stored, SweepChange& c) {
  for (std::size_t i = end; i-- > begin;) {
    s.pull(i, relax);
    s.finish(i, c);
    stored(i);
  }
}

template <class Gather, class Stored>
void parts(PassState& s, bool cosine, bool full, const Relaxation& relax, const Gather& gather,
           const Stored& stored, int me, int team, std::vector<SweepChange>& per_part) {
  const Layout& l = s.layout();
  for (int t = me; t < l.parts; t += team) {
    const std::size_t begin = l.part_begin[static_cast<std::size_t>(t)];
    const std::size_t end = l.part_begin[static_cast<std::size_t>(t) + 1];
    down(s, begin, end, cosine, gather);
    if (full) up(s, begin, end, relax, stored, per_part[static_cast<std::size_t>(t)]);
  }
}

// Runs body(me, team, barrier) on every thread of one parallel region of up to `threads`
// threads, with a TeamBarrier for the team OpenMP actually gave.
template <class Body>
void in_team(int threads, const Body& body) {
  std::optional<TeamBarrier> barrier;
#pragma omp parallel num_threads(threads)
  {
#pragma omp single
    barrier.emplace(omp_get_num_threads());
    body(omp_get_thread_num(), barrier->count(), *barrier);
  }
}

// The largest change and radiosity over the parts; the parts are reset for the next pass.
SweepChange take_total(std::vector<SweepChange>& per_part) {
  SweepChange total;
  for (SweepChange& c : per_part) {
    total.change = std::max(total.change, c.change);
    total.largest = std::max(total.largest, c.largest);
    c = SweepChange{};
  }
  return total;
}

template <class V>
V channels(const Rgb& x) {
  if constexpr (std::is_same_v<V, double>) {
    return x[0];
  } else {
    return x;
  }
}

// Every element's links as a sparse matrix over value slots, for the propagation's
// gather. Slot i holds the radiosity of elements[i]; a cluster has six more, the mean
// radiosity of its members facing each axis direction (ClusterLight's leaving /
// open_area). An element's row is the irradiance its links deliver; with cosine
// cluster receivers a cluster's row is six sums instead, the irradiance arriving along
// each axis direction (ClusterLight::arriving: each link's irradiance on a unit surface
// facing its source, |d_i| of it along axis i, as gather_one splits it). A link is one
// entry of one of three kinds:
//  Entry   a surface's radiosity (or a cluster's mean, when no member faces the
//          receiver) times its transport, into a row gathered whole: 8 bytes;
//  Triple  three weights on three slots in a row gathered whole: a cluster source seen
//          along d, on the slots of the directions d is seen along, weighted by
//          |d_i| open_area / their sum (the value radiosity_towards gives); or, into a
//          cosine cluster receiver, one slot split along three of its axis
//          directions: 16 bytes;
//  Fat     a cluster source seen along d (three slots) into a cosine cluster receiver,
//          split along three of its directions: 32 bytes.
// (With a plain entry per slot and row, a link between two clusters was up to nine
// entries, 72 bytes and nine reads of a value: on the lab they were 22 % of the links
// and over half of the 3.3 M entries.) Links and open areas do not change during a
// propagation, so the matrix is built once per propagation, and each sweep's gather
// streams over it and a small dense array of values instead of reading every link's
// source element (456 bytes apart; for a cluster its ClusterLight too). Weights are
// floats, like the links' form factor and visibility they come from. The next
// iteration's build keeps the rows of the elements whose links did not change
// (GatherMatrix::Reuse, PropagationCache).
class GatherMatrix {
 public:
  // `elements` in pass order (Layout: Element::index is the position), clusters
  // prepared (PassState). `previous`: the last propagation's matrix, or null; the
  // elements whose links are those it was built from keep their rows (Reuse), and it is
  // left empty.
  GatherMatrix(const std::vector<Element*>& elements, int threads, bool cosine,
               GatherMatrix* previous = nullptr)
      : cosine_(cosine) {
    measure(elements, threads);
    Reuse reuse = plan_reuse(previous);
    // One pass over the links (each reads its source's element, a cache miss): a chunk
    // of elements collects its rows in a thread's scratch chunk (a kept element's rows
    // copied), then keeps exact-size copies. The links' transport is summed on the way
    // (transport()).
    const auto chunks = static_cast<std::ptrdiff_t>(chunks_.size());
    std::size_t kept = 0;
#pragma omp parallel num_threads(threads) reduction(+ : kept)
    {
      Chunk scratch;
#pragma omp for schedule(dynamic, 1)
      for (std::ptrdiff_t c = 0; c < chunks; ++c)
        kept += fill_chunk(static_cast<std::size_t>(c), elements, reuse, scratch);
    }
    reused_ = kept;
    if (previous) *previous = GatherMatrix();
  }

  /// Elements whose rows were taken from the previous matrix.
  [[nodiscard]] std::size_t reused() const { return reused_; }

  [[nodiscard]] std::size_t slots() const { return slots_; }

  /// The transport of the own links of the element e at position i (or, for a cluster
  /// in Cosine mode, zero, and the transport split along the axes into
  /// `light->arriving`): in channel 0 per unit of area, in channels 1 and 2 per unit of
  /// open area (core/transport/open_fraction.h), so that one pass gives the row sums
  /// both ways (core/solver/row_sums.h). From the sums the build made: the row sums'
  /// pass reads no link.
  Rgb transport(std::size_t i, Element& e) const {
    if (by_axis(e)) {
      e.light->arriving = arriving_[(axis_[i] - first_axis_slot()) / 6];
      return Rgb::Zero();
    }
    const double g = link_total_[i];
    const double open = open_gain(e) * g;
    return Rgb(g, open, open);
  }

  /// Writes the slots of `values` of the element at position i from its B and
  /// directional sums.
  template <class V>
  void store(const PassState& s, std::size_t i, std::vector<V>& values) const {
    values[i] = channels<V>(s.B(i));
    if (!s.cluster(i)) return;
    const ClusterLight& cl = *s.light(i);
    for (std::size_t k = 0; k < 6; ++k)
      values[axis_[i] + k] = cl.leaving_made && cl.exposed_area[k] > 0
                                 ? channels<V>(cl.leaving[k] / cl.exposed_area[k])
                                 : channels<V>(s.B(i));
  }

  /// The row of the element at position i times `values`: the irradiance its own links
  /// deliver (not for a cosine cluster receiver: gather_axes).
  template <class V>
  [[nodiscard]] V gather(std::size_t i, const std::vector<V>& values) const {
    V g = channels<V>(Rgb::Zero());
    const Row r = row(i);
    for (const Entry& x : r.plain) g += static_cast<double>(x.weight) * values[x.slot];
    for (const Triple& x : r.triples) g += towards(x.slot, x.weight, values);
    return g;
  }

  /// For a cosine cluster receiver at position i: what its links deliver along each
  /// axis direction.
  template <class V>
  void gather_axes(std::size_t i, const std::vector<V>& values, std::array<V, 6>& arriving) const {
    arriving.fill(channels<V>(Rgb::Zero()));
    const Row r = row(i);
    for (const Triple& x : r.triples)
      spread(x.slot >> kSlotBits, x.weight, values[x.slot & kSlotMask], arriving);
    for (const Fat& x : r.fats)
      spread(x.signs, x.receiver, towards(x.slot, x.source, values), arriving);
  }

  /// Whether the rows of the element at position i are the six axis directions (a
  /// cluster, cosine receivers).
  [[nodiscard]] bool by_axis(const PassState& s, std::size_t i) const {
    return cosine_ && s.cluster(i);
  }
  [[nodiscard]] bool by_axis(const Element& e) const { return cosine_ && e.is_cluster(); }
  [[nodiscard]] bool cosine() const { return cosine_; }

 private:
  // Adds link l of the element e at position i to its transport sums (transport()).
  void add_transport(const Element& e, const Link& l, std::size_t i) {
    const double t = l.transport();
    if (!by_axis(e)) {
      link_total_[i] += t;
      return;
    }
    // Undo the link's mean cosine and split the irradiance a unit surface facing the
    // source would get along the axes. The mean cosine is over the members' area, or
    // their open area, so the members (their open parts) receive in total what the link
    // delivers to the cluster.
    const Vec3 d = (l.source->center - e.center).normalized();
    const double whole = e.projected_area(d), open = e.light->projected_open_area(d);
    const double per_whole = whole > 0 ? t * (e.area / whole) : 0.0;
    const double per_open = open > 0 ? t * (e.area / open) : 0.0;
    const Rgb facing(per_whole, per_open, per_open);
    std::array<Rgb, 6>& dir = arriving_[(axis_[i] - first_axis_slot()) / 6];
    for (int a = 0; a < 3; ++a)
      dir[static_cast<std::size_t>(2 * a + (d[a] < 0))] += std::abs(d[a]) * facing;
  }

  GatherMatrix() = default;  // empty: what a matrix whose rows were taken is left as

  // A slot takes kSlotBits of an entry's 32; the other three say which of each axis's
  // two directions it means (bit kSlotBits + a for axis a: the negative one).
  static constexpr int kSlotBits = 29;
  static constexpr std::uint32_t kSlotMask = (std::uint32_t{1} << kSlotBits) - 1;
  struct Entry {
    std::uint32_t slot;
    float weight;
  };
  struct Triple {
    std::uint32_t slot;  // with sign bits: the source's (row gathered whole), or the receiver's
    std::array<float, 3> weight;
  };
  struct Fat {
    std::uint32_t slot;   // the source's first axis slot, with its sign bits
    std::uint32_t signs;  // the receiver's: bit a for axis a
    std::array<float, 3> source;
    std::array<float, 3> receiver;
  };
  // The sign bits of d: bit a set where d_a < 0.
  static std::uint32_t signs_of(const Vec3& d) {
    return (d[0] < 0 ? 1u : 0u) | (d[1] < 0 ? 2u : 0u) | (d[2] < 0 ? 4u : 0u);
  }
  // A cluster's radiosity towards a direction: w[a] on the slot of axis a's direction
  // that the sign bits name.
  template <class V>
  static V towards(std::uint32_t slot, const std::array<float, 3>& w,
                   const std::vector<V>& values) {
    const std::uint32_t base = slot & kSlotMask;
    return static_cast<double>(w[0]) * values[base + ((slot >> kSlotBits) & 1u)] +
           static_cast<double>(w[1]) * values[base + 2 + ((slot >> (kSlotBits + 1)) & 1u)] +
           static_cast<double>(w[2]) * values[base + 4 + (slot >> (kSlotBits + 2))];
  }
  // Adds w[a] v to the direction of axis a that the sign bits name (2a: axis a's
  // positive one, 2a + 1 its negative one).
  template <class V>
  static void spread(std::uint32_t signs, const std::array<float, 3>& w, const V& v,
                     std::array<V, 6>& out) {
    for (std::uint32_t a = 0; a < 3; ++a)
      out[2 * a + ((signs >> a) & 1u)] += static_cast<double>(w[a]) * v;
  }

  // The rows of kChunk consecutive elements: element r's entries of kind k are
  // [at[3 r + k], at[3 r + 3 + k]) of that kind's array (the three kinds' ends side by
  // side: one line read per element). Chunks of 32 elements made the cabin's sweeps
  // 20 % slower.
  struct Chunk {
    std::vector<std::uint32_t> at;
    std::vector<Entry> plain;
    std::vector<Triple> triples;
    std::vector<Fat> fats;
    void clear() {
      at.assign(3, 0);
      plain.clear();
      triples.clear();
      fats.clear();
    }
    void end_row() {
      at.push_back(static_cast<std::uint32_t>(plain.size()));
      at.push_back(static_cast<std::uint32_t>(triples.size()));
      at.push_back(static_cast<std::uint32_t>(fats.size()));
    }
  };
  struct Row {
    std::span<const Entry> plain;
    std::span<const Triple> triples;
    std::span<const Fat> fats;
  };
  static constexpr std::size_t kChunk = 128;
  static constexpr int kAhead = 8;

  // How rows come from the last matrix `old`: not at all (null); in place, for the
  // same elements with the same cluster areas (old's storage taken over, a chunk whose
  // elements all keep their rows left as it is); or moved, when elements were added
  // (a kept row's slots renumbered). An element keeps its rows when its links are the
  // ones old was built from (hash_links) and nothing else its entries read changed: the
  // areas by axis of the clusters among its sources, and of itself as a cosine cluster
  // receiver (hash_areas; a leaf split in two changes its ancestors' open areas).
  // Besides, the entries read only the elements' fixed geometry and kind.
  struct Reuse {
    GatherMatrix* old = nullptr;
    bool in_place = false;
    std::vector<std::uint32_t> old_of;   // moved: position -> old position (kNone: new)
    std::vector<std::uint32_t> slot_of;  // moved: old slot -> slot (kNone: areas changed)
    // Moved: per chunk of old, the chunks of this matrix still to read it; the last one
    // frees it, so that the two matrices are not both whole at once (the lab's peak
    // memory: 214 MB with none kept, 241 MB with old freed at the end).
    std::unique_ptr<std::atomic<std::uint32_t>[]> readers;
  };
  static constexpr std::uint32_t kNone = PassState::kNone;

  // Slots, links' and clusters' hashes of `elements` (read once, in parallel; the
  // prefix sum runs over a dense array: axis_ holds 1 for a cluster until then).
  void measure(const std::vector<Element*>& elements, int threads) {
    const auto n = static_cast<std::ptrdiff_t>(elements.size());
    order_.assign(elements.begin(), elements.end());
    axis_.assign(elements.size(), 0);
    links_hash_.assign(elements.size(), 0);
    area_hash_.assign(elements.size(), 0);
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const Element& e = *elements[u];
      axis_[u] = e.is_cluster() ? 1 : 0;
      links_hash_[u] = hash_links(e);
      if (e.is_cluster() && e.light) area_hash_[u] = hash_areas(*e.light);
    }
    std::size_t slot = elements.size();
    for (std::size_t i = 0; i < elements.size(); ++i) {
      if (axis_[i] != 0) {
        axis_[i] = static_cast<std::uint32_t>(slot);
        slot += 6;
      }
    }
    // Over half a billion slots is over 70 million elements, far more than memory holds.
    if (slot > kSlotMask) throw std::length_error("propagation: too many elements for the gather");
    slots_ = slot;
  }

  // How this build keeps rows of `previous` (Reuse), with the sums' and chunks' storage
  // made (in place: taken over from previous; fresh memory costs page faults).
  Reuse plan_reuse(GatherMatrix* previous) {
    Reuse r;
    if (previous && previous->cosine_ == cosine_ && !previous->order_.empty()) r.old = previous;
    if (r.old && r.old->order_ == order_ && r.old->area_hash_ == area_hash_) {
      r.in_place = true;
      link_total_ = std::move(r.old->link_total_);
      arriving_ = std::move(r.old->arriving_);
      chunks_ = std::move(r.old->chunks_);
      return r;
    }
    link_total_.assign(order_.size(), 0.0);
    if (cosine_) {
      std::array<Rgb, 6> none;
      none.fill(Rgb::Zero());
      arriving_.assign((slots_ - first_axis_slot()) / 6, none);
    }
    chunks_.resize((order_.size() + kChunk - 1) / kChunk);
    if (!r.old) return r;
    GatherMatrix& o = *r.old;
    r.old_of.assign(order_.size(), kNone);
    r.slot_of.assign(o.slots_, kNone);
    for (std::size_t p = 0; p < o.order_.size(); ++p) {
      const std::uint32_t u = o.order_[p]->index;  // its position now
      if (u >= order_.size() || order_[u] != o.order_[p]) continue;
      r.old_of[u] = static_cast<std::uint32_t>(p);
      const bool cluster = o.axis_[p] != 0;
      if (cluster && o.area_hash_[p] != area_hash_[u]) continue;
      r.slot_of[p] = u;
      for (std::uint32_t k = 0; cluster && k < 6; ++k) r.slot_of[o.axis_[p] + k] = axis_[u] + k;
    }
    r.readers = std::make_unique<std::atomic<std::uint32_t>[]>(o.chunks_.size());
    for (std::size_t c = 0; c < chunks_.size(); ++c) {
      std::uint32_t last = kNone;  // each old chunk once per chunk
      for (std::size_t i = c * kChunk; i < std::min((c + 1) * kChunk, order_.size()); ++i)
        if (const std::uint32_t p = r.old_of[i]; p != kNone && p / kChunk != last) {
          last = static_cast<std::uint32_t>(p / kChunk);
          r.readers[last].fetch_add(1, std::memory_order_relaxed);
        }
    }
    for (std::size_t c = 0; c < o.chunks_.size(); ++c)
      if (r.readers[c].load(std::memory_order_relaxed) == 0) o.chunks_[c] = Chunk{};
    return r;
  }

  // The rows of chunk c (its elements' entries and sums); returns the elements that kept
  // theirs. `scratch`: the calling thread's.
  std::size_t fill_chunk(std::size_t c, const std::vector<Element*>& elements, Reuse& reuse,
                         Chunk& scratch) {
    const std::size_t begin = c * kChunk;
    const std::size_t end = std::min(begin + kChunk, elements.size());
    if (reuse.in_place) {
      std::size_t same = 0;
      for (std::size_t i = begin; i < end; ++i)
        same += reuse.old->links_hash_[i] == links_hash_[i] ? 1 : 0;
      if (same == end - begin) return same;  // the chunk as it was
    }
    scratch.clear();
    std::size_t kept = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const Element& e = *elements[i];
      if (keep_rows(reuse, i, e, scratch)) {
        ++kept;
        scratch.end_row();
        continue;
      }
      link_total_[i] = 0;
      if (by_axis(e)) arriving_[(axis_[i] - first_axis_slot()) / 6].fill(Rgb::Zero());
      // The sources' lines are asked for kAhead links before they are read.
      auto ahead = e.links.begin();
      for (int a = 0; a < kAhead && ahead != e.links.end(); ++a, ++ahead)
        __builtin_prefetch(ahead->source);
      for (const Link& l : e.links) {
        if (ahead != e.links.end()) {
          __builtin_prefetch(ahead->source);
          ++ahead;
        }
        add_transport(e, l, i);
        append(e, l, scratch);
      }
      scratch.end_row();
    }
    if (reuse.readers) {  // done with old's rows: free the chunks no one else reads
      std::uint32_t last = kNone;
      for (std::size_t i = begin; i < end; ++i)
        if (const std::uint32_t p = reuse.old_of[i]; p != kNone && p / kChunk != last) {
          last = static_cast<std::uint32_t>(p / kChunk);
          if (reuse.readers[last].fetch_sub(1, std::memory_order_acq_rel) == 1)
            reuse.old->chunks_[last] = Chunk{};
        }
    }
    // Exact sizes (assign from a range allocates just that; an in-place chunk's storage
    // is kept where it is large enough).
    Chunk& chunk = chunks_[c];
    chunk.at.assign(scratch.at.begin(), scratch.at.end());
    chunk.plain.assign(scratch.plain.begin(), scratch.plain.end());
    chunk.triples.assign(scratch.triples.begin(), scratch.triples.end());
    chunk.fats.assign(scratch.fats.begin(), scratch.fats.end());
    return kept;
  }

  // Whether the element e at position i keeps its rows and sums from reuse.old (see
  // Reuse); if so its rows are appended to `out` and its sums set.
  bool keep_rows(const Reuse& reuse, std::size_t i, const Element& e, Chunk& out) {
    if (!reuse.old) return false;
    if (reuse.in_place) {  // its rows and sums are in this matrix's storage already
      if (reuse.old->links_hash_[i] != links_hash_[i]) return false;
      append_row(row(i), nullptr, out);
      return true;
    }
    const GatherMatrix& o = *reuse.old;
    const std::uint32_t p = reuse.old_of[i];
    if (p == kNone || o.links_hash_[p] != links_hash_[i]) return false;
    if (by_axis(e) && o.area_hash_[p] != area_hash_[i]) return false;
    const Row r = o.row(p);
    const auto gone = [&](std::uint32_t slot) { return reuse.slot_of[slot & kSlotMask] == kNone; };
    if (std::any_of(r.plain.begin(), r.plain.end(), [&](const Entry& x) { return gone(x.slot); }) ||
        std::any_of(r.triples.begin(), r.triples.end(),
                    [&](const Triple& x) { return gone(x.slot); }) ||
        std::any_of(r.fats.begin(), r.fats.end(), [&](const Fat& x) { return gone(x.slot); }))
      return false;
    append_row(r, &reuse.slot_of, out);
    link_total_[i] = o.link_total_[p];
    if (by_axis(e))
      arriving_[(axis_[i] - first_axis_slot()) / 6] =
          o.arriving_[(o.axis_[p] - o.first_axis_slot()) / 6];
    return true;
  }

  // Appends row r to `out`, its slots renumbered by slot_of (null: as they are).
  static void append_row(const Row& r, const std::vector<std::uint32_t>* slot_of, Chunk& out) {
    const auto renumber = [&](std::uint32_t slot) {
      return slot_of ? ((*slot_of)[slot & kSlotMask] | (slot & ~kSlotMask)) : slot;
    };
    for (const Entry& x : r.plain) out.plain.push_back(Entry{renumber(x.slot), x.weight});
    for (const Triple& x : r.triples) out.triples.push_back(Triple{renumber(x.slot), x.weight});
    for (const Fat& x : r.fats)
      out.fats.push_back(Fat{renumber(x.slot), x.signs, x.source, x.receiver});
  }

  // A hash of e's links as a set: each one's source and the bits of its form factor and
  // visibility, in any order. (A refinement stage stores the links it keeps again, in
  // the order its tasks ran: with an order-dependent hash a lab run reused 16 % of the
  // rows its last stage left unchanged, with this one all of them. A reused row keeps
  // its old order, so the sums it gives may differ from a rebuilt row's in the last
  // bit.)
  static std::uint64_t hash_links(const Element& e) {
    std::uint64_t h = 0x6A09E667F3BCC909ull;
    for (const Link& l : e.links) {
      std::uint64_t values = 0;
      static_assert(sizeof(l.form_factor) + sizeof(l.visibility_q) + sizeof(l.decided_q) ==
                    sizeof(values));
      std::memcpy(&values, &l.form_factor, sizeof(values));
      h += splitmix64_mix(splitmix64_mix(std::bit_cast<std::uintptr_t>(l.source)) ^ values);
    }
    return h;
  }

  // A hash of a cluster's open and exposed areas by axis.
  static std::uint64_t hash_areas(const ClusterLight& cl) {
    std::uint64_t h = 0xBB67AE8584CAA73Bull;
    for (std::size_t a = 0; a < 6; ++a) {
      h = splitmix64_mix(h ^ std::bit_cast<std::uint64_t>(cl.open_area[a]));
      h = splitmix64_mix(h ^ std::bit_cast<std::uint64_t>(cl.exposed_area[a]));
    }
    return h;
  }

  // Appends link l of the receiver e to `out` as one entry (see the class comment).
  void append(const Element& e, const Link& l, Chunk& out) const {
    const Element& s = *l.source;
    const double t = l.transport();
    // The source's side: a cluster shows e the mean of its members facing e along each
    // axis, weighted by |d_a| times their exposed area (radiosity_towards); with none
    // facing e, its mean.
    std::uint32_t slot = s.index;
    std::array<float, 3> source{};
    bool directional = false;
    if (s.is_cluster()) {
      const Vec3 d = e.center - s.center;
      const std::array<double, 6>& oa = s.light->exposed_area;
      std::array<double, 3> part{};
      double sum = 0;
      for (std::size_t a = 0; a < 3; ++a) {
        const auto i = static_cast<Eigen::Index>(a);
        part[a] = std::abs(d[i]) * oa[2 * a + (d[i] < 0 ? 1 : 0)];
        sum += part[a];
      }
      if (sum > 0) {
        directional = true;
        slot = axis_[s.index] | signs_of(d) << kSlotBits;
        for (std::size_t a = 0; a < 3; ++a) source[a] = static_cast<float>(t * part[a] / sum);
      }
    }
    if (!by_axis(e)) {
      if (directional)
        out.triples.push_back(Triple{slot, source});
      else
        out.plain.push_back(Entry{slot, static_cast<float>(t)});
      return;
    }
    // A cosine cluster receiver: undo the link's mean cosine over the members' open
    // area and split the irradiance along the axes, as gather_one does.
    const Vec3 d = (s.center - e.center).normalized();
    const double projected = e.light->projected_open_area(d);
    if (!(projected > 0)) return;
    const double facing = e.area / projected;
    if (directional) {
      std::array<float, 3> receiver{};
      for (std::size_t a = 0; a < 3; ++a)
        receiver[a] = static_cast<float>(std::abs(d[static_cast<Eigen::Index>(a)]) * facing);
      out.fats.push_back(Fat{slot, signs_of(d), source, receiver});
      return;
    }
    std::array<float, 3> w{};
    for (std::size_t a = 0; a < 3; ++a)
      w[a] = static_cast<float>(t * std::abs(d[static_cast<Eigen::Index>(a)]) * facing);
    out.triples.push_back(Triple{slot | signs_of(d) << kSlotBits, w});
  }

  // The first axis slot: one past the elements' own.
  [[nodiscard]] std::size_t first_axis_slot() const { return order_.size(); }

  // The entries of the element at position i.
  [[nodiscard]] Row row(std::size_t i) const {
    const Chunk& c = chunks_[i / kChunk];
    const std::size_t r = i % kChunk;
    const std::uint32_t* at = c.at.data() + 3 * r;  // this row's starts, then its ends
    return Row{std::span<const Entry>(c.plain.data() + at[0], at[3] - at[0]),
               std::span<const Triple>(c.triples.data() + at[1], at[4] - at[1]),
               std::span<const Fat>(c.fats.data() + at[2], at[5] - at[2])};
  }

  bool cosine_ = false;
  std::vector<Chunk> chunks_;                 // elements[i]'s rows in chunks_[i / kChunk]
  std::vector<std::uint32_t> axis_;           // per element: its first axis slot (clusters)
  std::vector<double> link_total_;            // per element: the transport of its own links
  std::vector<std::array<Rgb, 6>> arriving_;  // cosine: per cluster, the links' transport by axis
  std::vector<const Element*> order_;         // the elements, in pass order
  std::vector<std::uint64_t> links_hash_;     // per element: hash_links
  std::vector<std::uint64_t> area_hash_;      // per element: hash_areas (clusters), else 0
  std::size_t slots_ = 0;
  std::size_t reused_ = 0;
};

// A Sweeper's value arrays, kept from one propagation to the next: memory the process
// already holds costs no page faults (on the cabin, first touches of fresh arrays took
// about 0.1 s a propagation).
struct SweepBuffers {
  std::vector<Rgb> older;  // Relaxation::older
  std::array<std::vector<Rgb>, 2> colour;
  std::array<std::vector<double>, 2> channel0;
};

// What a propagation keeps from sweep to sweep: the layout, the pass state, the gather
// matrix and its values (one channel in a grey scene), twice: a sweep gathers from the
// last sweep's and stores into the other, since one thread may finish an element while
// another still gathers from it. run() does all the sweeps in one parallel region, the
// team meeting at two TeamBarrier waits per sweep and at no OpenMP barrier, and hands
// the elements their radiosity at the end.
class Sweeper {
 public:
  // `matrix`: the gather matrix of these elements' links when one was built (by
  // push_transport), else one is built here. `buffers`: arrays to reuse (any sizes).
  Sweeper(PassState& state, int threads, ClusterReceiver mode, bool grey,
          std::optional<GatherMatrix> matrix = std::nullopt, SweepBuffers buffers = {})
      : layout_(state.layout()),
        state_(state),
        matrix_(matrix ? std::move(*matrix)
                       : GatherMatrix(layout_.order, threads, mode == ClusterReceiver::Cosine)),
        cosine_(mode == ClusterReceiver::Cosine),
        grey_(grey),
        buffers_(std::move(buffers)) {
    if (grey_) {
      init(buffers_.channel0);
    } else {
      init(buffers_.colour);
    }
  }

  /// The gather matrix, for the next build, and the value
  /// arrays, for the next sweeper (this one cannot sweep after either).
  GatherMatrix release_matrix() { return std::move(matrix_); }
  SweepBuffers release_buffers() {
    relax_.older = nullptr;
    return std::move(buffers_);
  }

  /// The leaves' relaxation factor from the next sweep on (Relaxation); the first call
  /// starts keeping each leaf's previous radiosity. Called from after_sweep.
  void relax(double omega) {
    if (!relax_.older) {
      buffers_.older.assign(state_.size(), Rgb::Zero());
      relax_.older = &buffers_.older;
    }
    relax_.omega = omega;
  }
  /// Back to plain sweeps.
  void plain() { relax_ = Relaxation{}; }

  /// Sweeps until after_sweep(largest change and radiosity of the sweep) returns false;
  /// after_sweep runs on the calling thread (the team's thread 0) while the others wait.
  /// Then the elements get their B (and gathered, next).
  template <class After>
  void run(const After& after_sweep) {
    if (grey_) {
      run_with(buffers_.channel0, after_sweep);
    } else {
      run_with(buffers_.colour, after_sweep);
    }
    state_.write_back(layout_.parts);
  }

 private:
  template <class V>
  static Rgb as_rgb(const V& v) {
    if constexpr (std::is_same_v<V, double>) {
      return Rgb::Constant(v);
    } else {
      return v;
    }
  }
  template <class V>
  void init(std::array<std::vector<V>, 2>& values) {
    for (std::vector<V>& v : values) v.resize(matrix_.slots());
    const auto n = static_cast<std::ptrdiff_t>(state_.size());
#pragma omp parallel for num_threads(layout_.parts) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i)
      matrix_.store(state_, static_cast<std::size_t>(i), values[0]);
  }
  template <class V, class After>
  void run_with(std::array<std::vector<V>, 2>& buffers, const After& after_sweep) {
    const GatherMatrix& m = matrix_;
    PassState& s = state_;
    const std::vector<V>& values = buffers[0];  // swapped after each sweep
    std::vector<V>& next = buffers[1];
    const auto gather = [&](std::size_t i) {
      if (m.by_axis(s, i)) {  // a cosine cluster receiver: what arrives along each axis
        std::array<V, 6> arriving;
        m.gather_axes(i, values, arriving);
        for (std::size_t k = 0; k < 6; ++k) s.light(i)->arriving[k] = as_rgb(arriving[k]);
        s.gathered(i) = Rgb::Zero();
        return;
      }
      s.gathered(i) = s.gain(i) * as_rgb(m.gather(i, values));
    };
    const auto store = [&](std::size_t i) { m.store(s, i, next); };
    const std::size_t top = layout_.top;
    std::vector<SweepChange> per_part(static_cast<std::size_t>(layout_.parts) + 1);
    bool more = true;  // written by thread 0 between barriers
    in_team(layout_.parts, [&](int me, int team, TeamBarrier& barrier) {
      // Two barriers a sweep: thread 0 ends one sweep (the top's pull, the bookkeeping)
      // and starts the next (the top's push) between the same two.
      if (me == 0) down(s, 0, top, cosine_, gather);
      barrier.wait();
      while (more) {
        parts(s, cosine_, true, relax_, gather, store, me, team, per_part);
        barrier.wait();
        if (me == 0) {
          up(s, 0, top, relax_, store, per_part.back());
          std::swap(buffers[0], buffers[1]);  // every slot was stored: the sweep's result
          more = after_sweep(take_total(per_part));
          if (more) down(s, 0, top, cosine_, gather);
        }
        barrier.wait();
      }
    });
  }

  const Layout& layout_;
  PassState& state_;
  GatherMatrix matrix_;
  bool cosine_;
  bool grey_;
  Relaxation relax_;
  SweepBuffers buffers_;
};

// How far an accelerated change may rise over the smallest before the acceleration is
// given up (a change growing by 1.5 a sweep gets there in five): kGiveUp, or for a
// contraction a near 1 2 / sqrt(1 - a^2), since the first omegas overshoot more there.
// (A closed furnace of reflectance 0.999, a = 0.999, rose 8.6-fold in its first four
// accelerated sweeps, and plain sweeps then took 3,800 and 8,500 sweeps to converge.)
// Below a = 0.968 the bound is kGiveUp.
constexpr double kGiveUp = 8;
double give_up_factor(double a) { return std::max(kGiveUp, 2 / std::sqrt(1 - a * a)); }

// The asymptotic rate of Chebyshev acceleration over [-a, a], per sweep.
double chebyshev_rate(double a) { return a / (1 + std::sqrt(1 - a * a)); }

// Whether Chebyshev over [-a, a] converges more slowly than it would with the spectral
// radius at a: after `since` accelerated sweeps whose last two changes fell by `q1` and
// `q0`. An eigenvalue l above a falls by (x + sqrt(x^2 - 1)) r per sweep, x = l / a and
// r = chebyshev_rate(a); so the mean y = sqrt(q0 q1) / r gives x = (y + 1 / y) / 2.
// Returns l when it is over 2 % above a (the interval to start again with), else 0. The
// first sweeps of a run are left alone: their omegas are still far from the limit.
double underestimated(double a, int since, double q1, double q0) {
  if (since < 4 || !(q0 > 0) || !(q1 > 0)) return 0;
  const double y = std::sqrt(q0 * q1) / chebyshev_rate(a);
  if (!(y > 1.05) || !(y < 1 / chebyshev_rate(a))) return 0;
  const double l = std::min(a * (y + 1 / y) / 2, kMaxContraction);
  return l > 1.02 * a ? l : 0;
}

// The largest change of a sweep relative to the largest radiosity.
double relative(const SweepChange& c) { return c.largest > 0 ? c.change / c.largest : 0.0; }

}  // namespace

// The layout and pass state of the last pass, kept while its elements are the same.
struct PropagationCache::Impl {
  std::vector<Element*> elements;
  std::optional<Layout> layout;
  std::optional<PassState> state;
  /// The gather matrix push_transport built, for the propagation that follows it (the
  /// links have not changed in between); that propagation takes it.
  std::optional<GatherMatrix> matrix;
  /// The last propagation's matrix: the next build takes the rows of the elements whose
  /// links have not changed from it (a refinement stage after the first changes the
  /// links of few elements), renumbered if elements were added.
  std::optional<GatherMatrix> previous;
  /// The last propagation's value arrays.
  SweepBuffers buffers;

  // A gather matrix of `order` built with what `previous` holds, which is gone afterwards.
  GatherMatrix build(const std::vector<Element*>& order, int threads, bool cosine) {
    GatherMatrix m(order, threads, cosine, previous ? &*previous : nullptr);
    previous.reset();
    return m;
  }

  // The matrix push_transport left if it is for this mode, else one built now; either
  // way none is left.
  GatherMatrix take_matrix(const std::vector<Element*>& order, int threads, ClusterReceiver mode) {
    const bool cosine = mode == ClusterReceiver::Cosine;
    std::optional<GatherMatrix> m;
    if (matrix && matrix->cosine() == cosine) m = std::move(matrix);
    matrix.reset();
    return m ? std::move(*m) : build(order, threads, cosine);
  }

  PassState& prepare(const std::vector<Element*>& list, int threads) {
    if (state && layout->parts == std::max(threads, 1) && list == elements) {
      state->refresh(threads);
      return *state;
    }
    matrix.reset();
    state.reset();
    layout.reset();
    elements.clear();
    layout.emplace(lay_out(list, threads));
    state.emplace(*layout, threads);
    elements = list;
    return *state;
  }
};

PropagationCache::PropagationCache() : impl_(std::make_unique<Impl>()) {}
PropagationCache::~PropagationCache() = default;

std::size_t push_transport(const std::vector<Element*>& elements, ClusterReceiver mode, int threads,
                           PropagationCache* cache) {
  const bool cosine = mode == ClusterReceiver::Cosine;
  PropagationCache own;
  PropagationCache::Impl& c = *(cache ? *cache : own).impl_;
  PassState& s = c.prepare(elements, threads);
  const Layout& l = s.layout();
  // The propagation that follows gathers over the same matrix: it is built here, and
  // the pass reads the links' transport from the sums it makes on the way.
  const GatherMatrix& m = c.matrix.emplace(c.build(l.order, threads, cosine));
  std::vector<SweepChange> per_part(static_cast<std::size_t>(l.parts) + 1);
  const auto gather = [&](std::size_t i) { s.gathered(i) = m.transport(i, *l.order[i]); };
  const auto none = [](std::size_t) {};
  in_team(l.parts, [&](int me, int team, TeamBarrier& barrier) {
    if (me == 0) down(s, 0, l.top, cosine, gather);
    barrier.wait();
    parts(s, cosine, false, Relaxation{}, gather, none, me, team, per_part);
  });
  s.write_back(l.parts);
  return m.reused();
}

double propagation_sweep(const std::vector<Element*>& elements, int threads, ClusterReceiver mode,
                         bool grey) {
  double change = 0;
  PropagationCache own;
  Sweeper(own.impl_->prepare(elements, threads), threads, mode, grey)
      .run([&](const SweepChange& s) {
        change = relative(s);
        return false;
      });
  return change;
}

PropagationResult propagate(const std::vector<Element*>& elements, double tolerance, int max_sweeps,
                            int threads, ClusterReceiver mode, bool grey,
                            const std::function<void(int sweeps, double change)>& on_sweep,
                            double contraction, PropagationCache* cache) {
  PropagationResult r;
  if (max_sweeps < 1 || interrupted()) return r;
  PropagationCache own;
  PropagationCache::Impl& c = *(cache ? *cache : own).impl_;
  PassState& state = c.prepare(elements, threads);
  // The links do not change here.
  Sweeper sweeper(state, threads, mode, grey, c.take_matrix(state.layout().order, threads, mode),
                  std::move(c.buffers));
  double previous = 0, previous_change = 0, previous_q = 0;
  int growing = 0;
  // Chebyshev acceleration over [-a, a], a the plain sweeps' contraction (given, or
  // measured here): sweep `since` of the accelerated run uses omega.
  double a = std::min(contraction, kMaxContraction);
  int since = 0;
  double omega = 1, best = std::numeric_limits<double>::infinity();
  bool given_up = false;
  const auto accelerate = [&] {
    r.contraction = a;
    since = 0;
    omega = 1;
    best = std::numeric_limits<double>::infinity();
    sweeper.relax(omega);
  };
  if (a > 0) accelerate();
  // After each sweep: whether to sweep again.
  sweeper.run([&](const SweepChange& s) {
    const double c = relative(s);
    ++r.sweeps;
    r.last_change = c;
    if (on_sweep) on_sweep(r.sweeps, c);
    // Past the largest double the changes are inf - inf: never "no change".
    if (!std::isfinite(s.largest) || !std::isfinite(s.change)) {
      r.diverged = true;
      return false;
    }
    if (c < 1e-13) {  // at round-off: nothing left to converge
      r.converged = true;
      return false;
    }
    // Growth is judged on the change itself: with rho K's spectral radius q >= 1 it
    // grows (or stays) by q every sweep, while the change relative to the radiosity,
    // which grows too, falls towards (q - 1) / q and never rises.
    growing = r.sweeps >= 2 && s.change >= previous_change ? growing + 1 : 0;
    if (growing > 50) {
      r.diverged = true;
      return false;
    }
    const double observed = previous > 0 ? c / previous : 0.0;
    if (r.sweeps >= 2 && previous > 0) {
      // Accelerated, the changes can fall unevenly: never count on more than the
      // method's own rate.
      const double q = a > 0 ? std::max(observed, chebyshev_rate(a)) : observed;
      if (q < 1 && c * q / (1 - q) < tolerance) {
        r.converged = true;
        return false;
      }
    }
    // The acceleration judges the change itself (the relative change of a growing B
    // falls even when the sweeps diverge).
    const double shrink = previous_change > 0 ? s.change / previous_change : 0.0;
    if (a > 0) {
      // A change give_up_factor(a) times the smallest since the acceleration began: the
      // spectrum is not what it assumes (far from real); plain sweeps from here on. (Its
      // first omegas overshoot: the change may double for a sweep or two while the error
      // falls.)
      best = std::min(best, s.change);
      if (s.change > give_up_factor(a) * best) {
        sweeper.plain();
        a = 0;
        r.contraction = 0;
        r.accelerated = false;
        given_up = true;
      } else if (const double found = underestimated(a, since, shrink, previous_q); found > 0) {
        a = found;  // start again from here with the larger interval
        accelerate();
      } else {
        ++since;
        omega = since == 1 ? 1 / (1 - a * a / 2) : 1 / (1 - a * a * omega / 4);
        sweeper.relax(omega);
        r.accelerated = true;
      }
    } else if (contraction >= 0 && !given_up && r.sweeps >= kPlainSweeps && previous_q > 0 &&
               shrink <= kMaxContraction && std::abs(shrink - previous_q) <= 0.1 * shrink) {
      // The plain sweeps' contraction has settled: their spectral radius.
      a = std::min(std::max(shrink, previous_q), kMaxContraction);
      accelerate();
    }
    previous_q = shrink;
    previous = c;
    previous_change = s.change;
    return r.sweeps < max_sweeps && !interrupted();
  });
  c.previous = sweeper.release_matrix();
  c.buffers = sweeper.release_buffers();
  return r;
}

}  // namespace hrad
