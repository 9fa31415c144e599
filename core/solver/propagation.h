// Propagation: gather over the links, then push-pull through the hierarchy,
// repeated (Jacobi) until the radiosity stops changing.
//
// Gather:    g_e = sum over e's links of transport * B_source   (irradiance),
//            divided by e's open fraction w_e (core/transport/open_fraction.h); with isotropic
//            cluster receivers (the default) as a sparse matrix built once per
//            propagation, over a dense array of the sources' values (the .cpp)
// Push:      H_e = H_parent + g_e                                (top-down)
// Leaf:      B'  = E + rho * s * H      (s: row-sum correction, 1 when off)
// Pull:      B'_e = open-area-weighted mean of the children's B'  (bottom-up)
//
// Stopping: with c_k the largest change of a sweep relative to the largest
// radiosity and q the observed contraction c_k / c_{k-1}, the remaining change of
// a geometric series is about c_k q / (1 - q); the loop stops when that is below
// `tolerance` (or c_k is 0, or the sweep cap is hit, or the iteration diverges).
#pragma once

#include "core/config/modes.h"
#include "core/hierarchy/element.h"

#include <functional>
#include <string>
#include <vector>

namespace hrad {

struct PropagationResult {
  int sweeps = 0;
  double last_change = 0;  ///< relative change of the last sweep
  bool converged = false;
  /// The change (not relative: that falls even when B grows) did not fall for 50
  /// sweeps, or a value overflowed: rho K's spectral radius is 1 or more (row sums
  /// above 1).
  bool diverged = false;
};

// ClusterReceiver (how a cluster receiver hands what it gathers to its members) is an
// option: core/config/modes.h.

/// Gather + push: sets `next` of every element to the total irradiance H it
/// receives from its own and its ancestors' links, each link contributing
/// value(link) (per unit of transport: transport() x B_source for radiosity,
/// transport() for row sums). `elements` lists parents before children. With
/// `open_area` (as the propagation does) the result is per unit of open area
/// (core/transport/open_fraction.h); without, per unit of area.
void gather_and_push(const std::vector<Element*>& elements, ClusterReceiver mode, int threads,
                     const std::function<Rgb(const Link&)>& value, bool open_area = true);

/// `elements` must list parents before children and hold every element a link refers
/// to (Hierarchy::elements()).
/// `grey`: every radiosity, emission and reflectance has equal channels (a grey
/// scene, core/config/effects.h), so the gather sums channel 0 only and copies it; the
/// result is the same to the last bit. Cluster receivers in Cosine mode still
/// gather three channels.
/// `on_sweep`, when given, is called on the calling thread after each sweep with the
/// sweeps done and the last relative change (the progress line).
PropagationResult propagate(const std::vector<Element*>& elements, double tolerance, int max_sweeps,
                            int threads, ClusterReceiver mode = ClusterReceiver::Isotropic,
                            bool grey = false,
                            const std::function<void(int sweeps, double change)>& on_sweep = {});

/// One Jacobi sweep (gather + push-pull), B <- B'; returns the relative change.
double propagation_sweep(const std::vector<Element*>& elements, int threads,
                         ClusterReceiver mode = ClusterReceiver::Isotropic, bool grey = false);

}  // namespace hrad
