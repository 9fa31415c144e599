#include "core/propagation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hrad {

ClusterReceiver parse_cluster_receiver(const std::string& name) {
  if (name == "isotropic") return ClusterReceiver::Isotropic;
  if (name == "cosine") return ClusterReceiver::Cosine;
  throw std::invalid_argument("cluster_receiver must be isotropic or cosine, not '" + name + "'");
}

namespace {

// `elements` is in breadth-first order (parents before children, each level's
// children appended after it), so every level is a contiguous range; returns the
// range starts plus the end. Push and pull run level by level, in parallel within
// a level: an element there only reads its parent (push) or children (pull).
std::vector<std::size_t> level_starts(const std::vector<Element*>& elements) {
  std::vector<std::size_t> starts{0};
  std::size_t begin = 0, end = elements.empty() ? 0 : 1;
  while (begin < end) {
    starts.push_back(end);
    std::size_t next = end;
    for (std::size_t i = begin; i < end; ++i) next += elements[i]->child_span().size();
    begin = end;
    end = std::min(next, elements.size());
  }
  return starts;
}

void push_one(Element* e, bool cosine) {
  e->next = e->gathered + (e->parent ? e->parent->next : Rgb::Zero());
  if (!cosine || !e->parent || !e->parent->is_cluster()) return;
  const std::array<Rgb, 6>& up = *e->parent->directional;
  if (e->is_cluster()) {
    for (std::size_t k = 0; k < 6; ++k) (*e->directional)[k] += up[k];
  } else {
    for (int a = 0; a < 3; ++a) {
      const double na = e->normal[a];
      e->next += std::max(0.0, na) * up[static_cast<std::size_t>(2 * a)] +
                 std::max(0.0, -na) * up[static_cast<std::size_t>(2 * a + 1)];
    }
  }
}

void pull_one(Element& e) {
  const auto kids = e.child_span();
  if (kids.empty()) {
    e.next = e.emission + e.rho * (static_cast<double>(e.gather_scale) * e.next);
  } else {
    Rgb sum = Rgb::Zero();
    for (const Element& k : kids) sum += k.area * k.next;
    e.next = e.area > 0 ? Rgb(sum / e.area) : Rgb::Zero();
  }
}

// Push (parents before children): `next` holds the total irradiance H.
void push_levels(const std::vector<Element*>& elements, bool cosine, int threads) {
  const std::vector<std::size_t> levels = level_starts(elements);
  for (std::size_t l = 0; l + 1 < levels.size(); ++l) {
    const auto b = static_cast<std::ptrdiff_t>(levels[l]), e = static_cast<std::ptrdiff_t>(levels[l + 1]);
#pragma omp parallel for num_threads(threads) schedule(static) if (e - b > 4096)
    for (std::ptrdiff_t i = b; i < e; ++i) push_one(elements[static_cast<std::size_t>(i)], cosine);
  }
}

}  // namespace

void gather_and_push(const std::vector<Element*>& elements, ClusterReceiver mode, int threads,
                     const std::function<Rgb(const Link&)>& value) {
  const bool cosine = mode == ClusterReceiver::Cosine;
  if (cosine) {
    for (Element* e : elements)
      if (e->is_cluster() && !e->directional) e->directional = std::make_unique<std::array<Rgb, 6>>();
  }
  const auto n = static_cast<std::ptrdiff_t>(elements.size());
  // Gather: independent per receiver.
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Element& e = *elements[static_cast<std::size_t>(i)];
    Rgb g = Rgb::Zero();
    if (cosine && e.is_cluster()) {
      // Undo the link's mean cosine (projected_area / area) and split the irradiance
      // a unit surface facing the source would get along the axes.
      std::array<Rgb, 6>& dir = *e.directional;
      dir.fill(Rgb::Zero());
      for (const Link& l : e.links) {
        const Vec3 d = (l.source->center - e.center).normalized();
        const double mean_cos = e.area > 0 ? e.projected_area(d) / e.area : 0.0;
        if (!(mean_cos > 0)) continue;
        const Rgb facing = value(l) / mean_cos;
        for (int a = 0; a < 3; ++a)
          dir[static_cast<std::size_t>(2 * a + (d[a] < 0))] += std::abs(d[a]) * facing;
      }
    } else {
      for (const Link& l : e.links) g += value(l);
    }
    e.gathered = g;
  }
  push_levels(elements, cosine, threads);
}

double propagation_sweep(const std::vector<Element*>& elements, int threads,
                         ClusterReceiver mode, bool grey) {
  if (grey && mode == ClusterReceiver::Isotropic) {
    // One channel: the same products and sums as channel 0 of the Rgb gather.
    const auto n = static_cast<std::ptrdiff_t>(elements.size());
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      Element& e = *elements[static_cast<std::size_t>(i)];
      double g = 0;
      for (const Link& l : e.links) g += l.transport() * l.source->B[0];
      e.gathered = Rgb::Constant(g);
    }
    push_levels(elements, false, threads);
  } else {
    gather_and_push(elements, mode, threads,
                    [](const Link& l) -> Rgb { return l.transport() * l.source->B; });
  }
  // Pull (children before parents): `next` becomes the new radiosity. A parent's H
  // is no longer needed once its children have read it in the push.
  const std::vector<std::size_t> levels = level_starts(elements);
  for (std::size_t l = levels.size() - 1; l-- > 0;) {
    const auto b = static_cast<std::ptrdiff_t>(levels[l]), e = static_cast<std::ptrdiff_t>(levels[l + 1]);
#pragma omp parallel for num_threads(threads) schedule(static) if (e - b > 4096)
    for (std::ptrdiff_t i = b; i < e; ++i) pull_one(*elements[static_cast<std::size_t>(i)]);
  }
  double change = 0, largest = 0;
  const auto n = static_cast<std::ptrdiff_t>(elements.size());
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : change, largest)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Element& e = *elements[static_cast<std::size_t>(i)];
    change = std::max(change, (e.next - e.B).abs().maxCoeff());
    largest = std::max(largest, e.next.abs().maxCoeff());
    e.B = e.next;
  }
  return largest > 0 ? change / largest : 0.0;
}

PropagationResult propagate(const std::vector<Element*>& elements, double tolerance,
                            int max_sweeps, int threads, ClusterReceiver mode, bool grey) {
  PropagationResult r;
  double previous = 0;
  int growing = 0;
  while (r.sweeps < max_sweeps) {
    const double c = propagation_sweep(elements, threads, mode, grey);
    ++r.sweeps;
    r.last_change = c;
    if (c < 1e-13) {  // at round-off: nothing left to converge
      r.converged = true;
      break;
    }
    if (r.sweeps >= 2 && previous > 0) {
      const double q = c / previous;
      if (q < 1) {
        growing = 0;
        if (c * q / (1 - q) < tolerance) {
          r.converged = true;
          break;
        }
      } else if (++growing > 50) {
        r.diverged = true;
        break;
      }
    }
    previous = c;
  }
  return r;
}

}  // namespace hrad
