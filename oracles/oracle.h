// IOracle: decides, for one candidate link r <- s with its transport estimate,
// whether to accept it or to refine, and reports an error estimate that the
// `priority` scheduler orders by. Oracles are pure functions of the link, the
// frozen radiosities and the thresholds, so the link set never depends on the
// order in which tasks were examined.
#pragma once

#include "core/base/geometry.h"
#include "core/base/plugin_params.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hrad {

struct Element;

enum class Decision : std::uint8_t { Accept, Refine };

/// What the oracle sees of a link. Energies are per colour channel; the oracle
/// compares the largest channel.
struct LinkEstimate {
  const Element* receiver = nullptr;
  const Element* source = nullptr;
  double form_factor = 0;  ///< unoccluded F_rs
  double visibility = 1;   ///< in [0,1]
  /// Largest minus smallest point-to-source form factor over the receiver's
  /// sample points (0 when not computed, e.g. for clusters).
  double form_factor_spread = 0;
};

struct OracleThresholds {
  double eps_power = 0;  ///< absolute power threshold (eps x total emitted power)
  /// The scene's emitted power over its total area (W per unit area): the scale a
  /// receiver's own irradiance is compared with (receiver_threshold). 0: not used.
  double mean_irradiance = 0;
  /// Each colour channel's weight in the oracles' comparisons (channel_weights): the
  /// strongest channel's emitted power over this channel's, so that every channel's
  /// error is judged against its own light. All 1 under grey (or no) emission.
  Rgb channel_weight = Rgb::Ones();
};

struct Verdict {
  Decision decision = Decision::Accept;
  double error = 0;  ///< the oracle's error estimate, in power units
};

class IOracle {
 public:
  virtual ~IOracle() = default;
  [[nodiscard]] virtual Verdict judge(const LinkEstimate& link,
                                      const OracleThresholds& t) const = 0;
  /// True when the oracle wants form_factor_spread computed (it costs extra evaluations).
  [[nodiscard]] virtual bool needs_spread() const { return false; }
  [[nodiscard]] virtual const char* name() const = 0;
};

/// Builds an oracle from its parameters (`--set oracle.NAME.KEY=VALUE`, read through
/// `params`, which knows the declared defaults and ranges).
using OracleFactory = std::function<std::unique_ptr<IOracle>(const PluginParams& params)>;
/// Creates an oracle by name with `params` (by KEY); throws std::invalid_argument for an
/// unknown name (listing the known ones) and for a parameter the oracle does not
/// declare or did not read (PluginParams::report_unused).
std::unique_ptr<IOracle> make_oracle(const std::string& name, const ParamValues& params = {});
std::vector<std::string> oracle_names();
/// Throws make_oracle's std::invalid_argument when `name` is not registered.
void check_oracle_name(const std::string& name);
/// The parameters `name` declared (throws as check_oracle_name for an unknown name).
std::span<const ParamSpec> oracle_params(const std::string& name);
/// Registration: each oracle file defines one `static const bool registered =
/// register_oracle("name", factory, {parameters});`.
bool register_oracle(const std::string& name, OracleFactory factory,
                     std::vector<ParamSpec> params = {});

/// Power reflected at r due to s per unit F, largest channel of w * rho_r * B_s * A_r
/// (w: OracleThresholds::channel_weight).
double reflected_power_scale(const Element& r, const Element& s, const Rgb& w = Rgb::Ones());

/// The most a channel is weighted (channel_weights): a channel with less than a
/// hundredth of the strongest channel's emitted power is judged as if it had that much.
inline constexpr double kMaxChannelWeight = 100;
/// The oracles' channel weights for a scene whose faces emit `power` per channel in
/// all: max(power) / power_c, at most kMaxChannelWeight; all 1 where the channels'
/// powers are equal (grey light) or nothing emits. The threshold eps x emitted power
/// bounds the power a link may get wrong, and the largest channel decides; where the
/// light is coloured, a weak channel's errors were never what decided. In the measured
/// Cornell box (light 18.2 / 11.1 / 1.66 per channel) the least accurate probes were
/// blue; with the weights the medians of two sets of 48 random probes went 1.51 -> 1.25 %
/// and 1.38 -> 0.91 % for 6 % more links (docs/accuracy.md, "Coloured light").
Rgb channel_weights(const Rgb& power);

/// A link with a cluster at either end whose visibility rays were not all unblocked
/// (0 <= V < 1) is judged as if it carried this many times its power: such a link is
/// biased low, not only noisy. Its members are not equally visible, and the ones in
/// view (a desk's top) are brighter than the ones its own parts hide (the chair seat
/// under it), while the link shows the receiver their mean radiosity; and when all
/// of its few rays happen to be blocked it carries nothing. Measured on
/// builtin:office against cosine rays from the receiver (docs/energy-budget.md), such
/// links delivered 79-86 % of their true power. The weight was chosen by a sweep
/// (signed mean error at 64 random probes against `hrad reference`):
///   weight  office   lab     cabin   cluttered furnace rho 0.9
///   1       -7.6 %   -8.2 %  -8.8 %  -1.1 %
///   4       -2.1 %   -2.2 %  -2.3 %  +0.1 %
///   8       -0.9 %   -0.6 %  +0.8 %  +0.2 %
///   16      -0.2 %   +0.5 %  +2.9 %  +0.3 %
/// Surface-to-surface links are not affected (their estimate is within 1 %).
constexpr double kOccludedClusterWeight = 8;
/// `weight` (kOccludedClusterWeight unless an oracle's parameter says otherwise) for an
/// occluded link with a cluster end, else 1.
double occlusion_weight(const LinkEstimate& link, double weight = kOccludedClusterWeight);

/// A receiver darker than the scene's mean is judged against its own light. The
/// threshold eps x total power bounds the power a link may get wrong, the same in a
/// lit patch and in a dark corner, so the dark corner's *relative* error is larger by
/// the ratio of the lights: in the Cornell boxes the worst probes are in the blocks'
/// umbrae at 6-20 % of the mean irradiance, 12-20 % off at eps 1e-4 while the lit
/// probes were within 3 %. So once a receiver has gathered light (its frozen
/// radiosity above its emission, i.e. from the second iteration on), its threshold is
/// scaled by E_r / mean_irradiance, E_r = max over channels of (B - E) / rho (its
/// irradiance from the last solution), clamped to [kDarkThresholdFloor, 1]: never
/// looser than eps, at most 4x tighter. Chosen by measurement (64 random probes
/// against `hrad reference`, docs/accuracy.md): a floor of
/// 0.25 took builtin:cornell's worst probe from 20 to 6.4 % for 15 % more links; 0.1
/// gained nothing more; scaling by E_r / (3 x mean) doubled the links for a smaller
/// gain. Uniformly lit scenes (a furnace) are unchanged.
constexpr double kDarkThresholdFloor = 0.25;
/// t.eps_power, scaled for a dark receiver as above (each channel's irradiance times its
/// channel weight), with `floor` in place of kDarkThresholdFloor when an oracle's
/// parameter says so (1: never tightened).
double receiver_threshold(const LinkEstimate& link, const OracleThresholds& t,
                          double floor = kDarkThresholdFloor);

/// A surface pair whose visibility rays were partly blocked (0 < V < 1) has a shadow
/// boundary across its receiver, and the link hands every part of the receiver the
/// mean. The power threshold lets such a link pass wherever its power is small next to
/// the scene's, though the receiver's own light may be mostly that link's: in
/// builtin:lab a floor piece of 0.64 m^2, half under a shelf 15 cm above it, took 44 %
/// of its light from two ceiling lamps at V 0.5, and the underside of the shelf, which
/// sees that floor, read 2.4 times the path-traced value. So such a link is refined
/// while the radiosity it would bring its receiver at full visibility, rho_r B_s F
/// (largest channel), times 2 min(V, 1 - V) (1 at V = 1/2, 0 for a pair wholly open or
/// hidden), exceeds this fraction of the receiver's reflected radiosity B_r - E_r
/// (largest channel, from the last solution: from the second iteration on), down to
/// min_area. A uniformly lit scene (a furnace) is hardly touched: there no one link
/// brings much of a receiver's light. Chosen by measurement, 2 x 24 random probes per
/// scene against `hrad reference` at 0.5 % (median / worst, before -> after):
///   contrast  Cornell          office           lab               cluttered furnace
///   off       0.97 / 6.5 %     1.51 / 165 %     1.21 / 143 %      0.36 / 2.45 %
///             1.28 / 8.6 %     2.33 / 96 %      2.28 / 17.2 %     0.37 / 1.57 %
///   0.03      0.98 / 4.5 %     1.51 / 119 %     1.21 / 81 %       0.34 / 2.41 %
///             1.23 / 6.9 %     2.19 / 65 %      2.89 / 17.1 %     0.35 / 1.57 %
///   0.01      0.95 / 4.7 %     1.43 / 112 %     1.43 / 86 %       0.34 / 2.04 %
///             1.21 / 6.9 %     2.08 / 49 %      2.96 / 18.0 %     0.35 / 1.66 %
/// with links +27 / +11 / +1.5 / +4 % at 0.03 and +97 / +28 / +4 / +7 % at 0.01.
constexpr double kShadowContrast = 0.03;
/// True when `link` is a partly visible surface pair whose shadow changes its
/// receiver's light by more than `contrast` (above; 0: never).
/// Both radiosities are compared channel by channel times `weight`
/// (OracleThresholds::channel_weight), largest channel.
bool shadow_too_sharp(const LinkEstimate& link, double contrast = kShadowContrast,
                      const Rgb& weight = Rgb::Ones());

/// The parameters bf and error share: the three constants above, for studies
/// (oracle.bf.occluded_cluster_weight, oracle.error.dark_floor, ...).
std::vector<ParamSpec> weighting_params();

}  // namespace hrad
