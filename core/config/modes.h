// The options that choose between modes, for the layers above config that act on them:
// each enum with its one table of names (core/base/enum_names.h), which parsing,
// printing, validation and --help read. The options with their own layer's enum
// (pin, placement, pool_order, cluster_model, sides) keep it there.
#pragma once

#include "core/base/enum_names.h"

#include <cstdint>
#include <span>

namespace hrad {

/// effects (core/config/effects.h).
enum class EffectsMode : std::uint8_t {
  Auto,  ///< turn off what the scene does not need
  All,   ///< compute every effect regardless (the reference for the shortcuts)
};
inline constexpr EnumName<EffectsMode> kEffectsModeNames[] = {
    {EffectsMode::Auto, "auto", "skip what the scene does not need, reported in stats.json"},
    {EffectsMode::All, "all", "compute every effect"},
};
constexpr std::span<const EnumName<EffectsMode>> enum_names(EffectsMode) {
  return kEffectsModeNames;
}

/// cluster_receiver: how a cluster receiver hands what it gathers to its members
/// (core/solver/propagation.h):
///  Isotropic  every member gets the cluster's mean irradiance (Sillion 1995);
///  Cosine     each link's irradiance is split along +-x, +-y, +-z by its direction
///             and a member with normal n gets sum_i max(0, +-n_i) / |n|_1 of each
///             part: its own cosine in the directional model (exact for axis-aligned
///             members; see add_by_axis in core/hierarchy/element.h).
///             The total over the members is the same as with Isotropic.
enum class ClusterReceiver : std::uint8_t { Isotropic, Cosine };
inline constexpr EnumName<ClusterReceiver> kClusterReceiverNames[] = {
    {ClusterReceiver::Isotropic, "isotropic", "every member the cluster's mean irradiance"},
    {ClusterReceiver::Cosine, "cosine", "each member its own cosine to each link"},
};
constexpr std::span<const EnumName<ClusterReceiver>> enum_names(ClusterReceiver) {
  return kClusterReceiverNames;
}

/// cluster_members: how a cluster's members share the light it receives along each axis
/// direction and which of their radiosities it shows (core/transport/cluster_exposure.h;
/// with cluster_receiver = cosine).
///   Exposed  by open area times each member's exposure within the cluster, from rays
///            (a member that the cluster's other members hide catches and shows little)
///   Alike    by open area alone
enum class ClusterMembers : std::uint8_t { Exposed, Alike };
inline constexpr EnumName<ClusterMembers> kClusterMembersNames[] = {
    {ClusterMembers::Exposed, "exposed",
     "by open area times each member's exposure within the cluster (rays)"},
    {ClusterMembers::Alike, "alike", "by open area alone, hidden members like exposed ones"},
};
constexpr std::span<const EnumName<ClusterMembers>> enum_names(ClusterMembers) {
  return kClusterMembersNames;
}

/// row_sums: the leaf row-sum rescale, for studies (core/solver/row_sums.h).
enum class RowSumMode : std::uint8_t { Keep, Clamp, Normalize };
inline constexpr EnumName<RowSumMode> kRowSumModeNames[] = {
    {RowSumMode::Keep, "keep", "the links as they are"},
    {RowSumMode::Clamp, "clamp", "leaves above 1 rescaled to 1"},
    {RowSumMode::Normalize, "normalize", "every leaf to its ray-measured covered share"},
};
constexpr std::span<const EnumName<RowSumMode>> enum_names(RowSumMode) { return kRowSumModeNames; }

/// shaft_culling (core/transport/shaft.h).
enum class ShaftCulling : std::uint8_t { Off, On };
inline constexpr EnumName<ShaftCulling> kShaftCullingNames[] = {
    {ShaftCulling::Off, "off", "always cast the visibility rays"},
    {ShaftCulling::On, "on", "V = 1 without rays for pairs whose shaft holds no polygon"},
};
constexpr std::span<const EnumName<ShaftCulling>> enum_names(ShaftCulling) {
  return kShaftCullingNames;
}

/// decision_rays (core/solver/refiner.h, RefineLimits::independent_estimates).
enum class DecisionRays : std::uint8_t { Shared, Independent };
inline constexpr EnumName<DecisionRays> kDecisionRaysNames[] = {
    {DecisionRays::Shared, "shared", "an accepted link keeps the visibility its oracle decided on"},
    {DecisionRays::Independent, "independent",
     "where the decision depended on it, the visibility is estimated again from independent "
     "rays (unbiased, for the study of that selection)"},
};
constexpr std::span<const EnumName<DecisionRays>> enum_names(DecisionRays) {
  return kDecisionRaysNames;
}

/// push_visibility: the visibility a push weight gives a child for each partly
/// visible link of its parent's surface chain (core/solver/push_weights.h).
enum class PushVisibility : std::uint8_t { Link, Child };
inline constexpr EnumName<PushVisibility> kPushVisibilityNames[] = {
    {PushVisibility::Link, "link", "every child the link's own visibility"},
    {PushVisibility::Child, "child",
     "each child its own, from visibility_rays rays per child and link (costs rays)"},
};
constexpr std::span<const EnumName<PushVisibility>> enum_names(PushVisibility) {
  return kPushVisibilityNames;
}

/// shading: how render.png and solution.ply shade the leaves (core/output/smooth_shading.h).
enum class Shading : std::uint8_t { Smooth, Flat };
inline constexpr EnumName<Shading> kShadingNames[] = {
    {Shading::Smooth, "smooth", "one value per vertex and surface, continuous across leaves"},
    {Shading::Flat, "flat", "each leaf its own constant"},
};
constexpr std::span<const EnumName<Shading>> enum_names(Shading) { return kShadingNames; }

}  // namespace hrad
