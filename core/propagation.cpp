#include "core/propagation.h"

#include <algorithm>
#include <cmath>

namespace hrad {

double propagation_sweep(const std::vector<Element*>& elements, int threads) {
  const auto n = static_cast<std::ptrdiff_t>(elements.size());
  // Gather: independent per receiver.
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Element& e = *elements[static_cast<std::size_t>(i)];
    Rgb g = Rgb::Zero();
    for (const Link& l : e.links) g += l.transport() * l.source->B;
    e.gathered = g;
  }
  // Push (parents before children): `next` holds the total irradiance H.
  for (Element* e : elements) {
    e->next = e->gathered + (e->parent ? e->parent->next : Rgb::Zero());
  }
  // Pull (children before parents): `next` becomes the new radiosity. A parent's H
  // is no longer needed once its children have read it in the push.
  for (auto it = elements.rbegin(); it != elements.rend(); ++it) {
    Element& e = **it;
    const auto kids = e.child_span();
    if (kids.empty()) {
      e.next = e.emission + e.rho * (static_cast<double>(e.gather_scale) * e.next);
    } else {
      Rgb sum = Rgb::Zero();
      for (const Element& k : kids) sum += k.area * k.next;
      e.next = e.area > 0 ? Rgb(sum / e.area) : Rgb::Zero();
    }
  }
  double change = 0, largest = 0;
  for (Element* e : elements) {
    change = std::max(change, (e->next - e->B).abs().maxCoeff());
    largest = std::max(largest, e->next.abs().maxCoeff());
    e->B = e->next;
  }
  return largest > 0 ? change / largest : 0.0;
}

PropagationResult propagate(const std::vector<Element*>& elements, double tolerance,
                            int max_sweeps, int threads) {
  PropagationResult r;
  double previous = 0;
  int growing = 0;
  while (r.sweeps < max_sweeps) {
    const double c = propagation_sweep(elements, threads);
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
