// How a cluster's projected area and its members' mean cosine are estimated (option
// cluster_model; used by core/transport/transport.cpp and core/hierarchy's axis areas).
#pragma once

#include "core/base/enum_names.h"

#include <cstdint>
#include <span>

namespace hrad {

///  isotropic    A/4 in every direction, members see 1/4 (Sillion 1995);
///  directional  from the members' areas along +-x, +-y, +-z (exact when every
///               member is axis-aligned, as in most architecture).
enum class ClusterModel : std::uint8_t { Isotropic, Directional };
inline constexpr EnumName<ClusterModel> kClusterModelNames[] = {
    {ClusterModel::Isotropic, "isotropic", "A/4 in every direction, Sillion 1995"},
    {ClusterModel::Directional, "directional", "member areas along +-x, +-y, +-z"},
};
constexpr std::span<const EnumName<ClusterModel>> enum_names(ClusterModel) {
  return kClusterModelNames;
}

}  // namespace hrad
