// Propagation: gather over the links, then push-pull through the hierarchy,
// repeated (Jacobi, accelerated) until the radiosity stops changing.
//
// Gather:    g_e = sum over e's links of transport * B_source   (irradiance),
//            divided by e's open fraction w_e (core/transport/open_fraction.h); with isotropic
//            cluster receivers (the default) as a sparse matrix built once per
//            propagation, over a dense array of the sources' values (the .cpp)
// Push:      H_e = H_parent + g_e                                (top-down)
// Leaf:      B'  = E + rho * s * H      (s: row-sum correction, 1 when off)
// Pull:      B'_e = open-area-weighted mean of the children's B'  (bottom-up)
//
// Acceleration: the plain sweep is an affine map B_{k+1} = G(B_k) whose linear part is
// close to rho K, whose eigenvalues are real (reciprocity: rho K is similar to a
// symmetric matrix) and within the spectral radius a < 1 of 0. Chebyshev's
// semi-iterative method over [-a, a] then converges at a / (1 + sqrt(1 - a^2)) per
// sweep instead of a (0.5 instead of 0.8, a third of the sweeps; any real spectrum in
// (-1, 1) still converges, only more slowly, when a is misjudged):
//            B_{k+1} = B_{k-1} + omega_{k+1} (G(B_k) - B_{k-1}),
//            omega_1 = 1, omega_2 = 1 / (1 - a^2 / 2), omega_{k+1} = 1 / (1 - a^2 omega_k / 4),
// applied at the leaves (every parent is linear in its leaves). a is the contraction of
// the plain sweeps once it has settled (two ratios within 10 % after kPlainSweeps), or the
// one a run's earlier propagation measured. Accelerated sweeps that fall more slowly than
// a allows show an eigenvalue above a: the run starts again with it. A change that grows
// to 8 times the smallest since the start (2 / sqrt(1 - a^2) times for a above 0.968,
// whose first omegas overshoot more), eigenvalues far from real, switches back to
// plain sweeps for good. The result is a deterministic function of the links, as before:
// the changes are maxima, the same on any number of threads.
//
// Stopping: with c_k the largest change of a sweep relative to the largest
// radiosity and q the observed contraction c_k / c_{k-1}, the remaining change of
// a geometric series is about c_k q / (1 - q); the loop stops when that is below
// `tolerance` (or c_k is 0, or the sweep cap is hit, or the iteration diverges).
#pragma once

#include "core/config/modes.h"
#include "core/hierarchy/element.h"

#include <functional>
#include <memory>
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
  /// The contraction a the acceleration assumed (0: plain sweeps throughout); pass it to
  /// the next propagation of the same scene.
  double contraction = 0;
  bool accelerated = false;  ///< the last sweep was accelerated
};

/// Plain sweeps before the contraction is judged settled.
inline constexpr int kPlainSweeps = 4;
/// The largest contraction the acceleration assumes (nearer 1, the omegas approach 2). A
/// closed furnace of reflectance 0.999 contracts by 0.998: with the bound at 0.995 it was
/// never accelerated, and its propagations took 3,800 to 8,500 plain sweeps.
inline constexpr double kMaxContraction = 0.9999;

// ClusterReceiver (how a cluster receiver hands what it gathers to its members) is an
// option: core/config/modes.h.

/// What a run's passes (push_transport, propagate) keep from one to the next: the
/// elements' order for a pass and what a pass reads of them, in dense arrays. Kept while
/// the elements are the same (the same list, so the same hierarchy) and then only
/// refreshed from them; made again otherwise. A pass given none makes its own. Also the
/// gather matrix that push_transport builds from the links (it reads their transport
/// from it): the next propagate with this cache gathers over it and lets it go, so the
/// links must not change between the two (the solver refines before push_transport).
/// That propagation's matrix and value arrays are kept for the next pass: an element
/// whose links are unchanged keeps its rows, with no source read again (renumbered when
/// elements were added; the lab's last three stages kept 92, 96 and 99.9 % of them, the
/// cabin's 94, 97 and 99.4 %), and memory the process holds needs no page faults. They stay allocated through the refinement
/// between (the cabin's matrix is 110 MB, its links 118 MB), which every propagation
/// needs anyway: the cabin's peak resident memory went from 1,183 to 1,197 MB.
class PropagationCache {
 public:
  PropagationCache();
  ~PropagationCache();
  PropagationCache(const PropagationCache&) = delete;
  PropagationCache& operator=(const PropagationCache&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  friend std::size_t push_transport(const std::vector<Element*>&, ClusterReceiver, int,
                                    PropagationCache*);
  friend PropagationResult propagate(const std::vector<Element*>&, double, int, int,
                                     ClusterReceiver, bool, const std::function<void(int, double)>&,
                                     double, PropagationCache*);
  friend double propagation_sweep(const std::vector<Element*>&, int, ClusterReceiver, bool);
};

/// Gather + push of the links' transport (the row sums, core/solver/row_sums.h): sets
/// `next` of every element to the total transport it receives from its own and its
/// ancestors' links, pushed as the propagation pushes irradiance: in channel 0 per unit
/// of area, in channels 1 and 2 per unit of open area, as the propagation gathers
/// (core/transport/open_fraction.h). `elements` lists parents before children.
/// Returns the elements whose rows of the gather matrix were taken from the last
/// propagation's (PropagationCache): those whose links did not change.
std::size_t push_transport(const std::vector<Element*>& elements, ClusterReceiver mode, int threads,
                           PropagationCache* cache = nullptr);

/// `elements` must list parents before children and hold every element a link refers
/// to (Hierarchy::elements()).
/// `grey`: every radiosity, emission and reflectance has equal channels (a grey
/// scene, core/config/effects.h), so the gather sums channel 0 only and copies it; the
/// result is the same to the last bit. Cluster receivers in Cosine mode still
/// gather three channels.
/// `on_sweep`, when given, is called on the calling thread after each sweep with the
/// sweeps done and the last relative change (the progress line).
/// `contraction`: an earlier propagation's PropagationResult::contraction, to accelerate
/// from the first sweep; 0 to measure it here; negative for plain sweeps only.
/// `cache`: the run's PropagationCache, when it has one.
PropagationResult propagate(const std::vector<Element*>& elements, double tolerance, int max_sweeps,
                            int threads, ClusterReceiver mode = ClusterReceiver::Isotropic,
                            bool grey = false,
                            const std::function<void(int sweeps, double change)>& on_sweep = {},
                            double contraction = 0, PropagationCache* cache = nullptr);

/// One Jacobi sweep (gather + push-pull), B <- B'; returns the relative change.
double propagation_sweep(const std::vector<Element*>& elements, int threads,
                         ClusterReceiver mode = ClusterReceiver::Isotropic, bool grey = false);

}  // namespace hrad
