// MGF transform arguments (the `xf` entity and the optional tail of `i`):
//
//   -t dx dy dz   translate            -s f    uniform scale (f != 0; f < 0 mirrors)
//   -rx/-ry/-rz a rotate a degrees counter-clockwise about the axis (right-hand rule)
//   -mx/-my/-mz   mirror about the YZ / XZ / XY plane
//   -i N          repeat the arguments that follow (up to the next -i or -a) N times
//   -a N          make an array: the arguments that follow (up to the next -i or -a)
//                 are applied k times in instance k = 0 .. N-1
//
// Each argument acts on the object as left by the arguments before it, so the local
// transform is M_last * ... * M_first (column vectors). Several -a make a
// multi-dimensional array with the product of their counts as instances.
#pragma once

#include "core/base/geometry.h"
#include "core/scene/scene_builder.h"

#include <span>
#include <string_view>
#include <vector>

namespace hrad {

using Affine = Eigen::Transform<double, 3, Eigen::Affine>;

struct XfGroup {
  Affine m = Affine::Identity();
  long count = 1;      ///< -i repeat count, or the -a instance count
  bool array = false;  ///< -a: the exponent is the instance index, not `count`
};

struct XfSpec {
  std::vector<XfGroup> groups;
  [[nodiscard]] bool has_array() const;
  /// Number of array dimensions (the -a groups).
  [[nodiscard]] std::size_t array_dims() const;
  /// The local transform of one instance; `index` has one entry per -a group, each
  /// in [0, count).
  [[nodiscard]] Affine instance(std::span<const long> index) const;
};

/// Limits on counts a file may ask for; exceeding one is an InputError.
struct XfLimits {
  long max_array = 100000;    ///< largest -a N
  long max_repeat = 1000000;  ///< largest -i N
};

/// Parses transform arguments. Throws InputError at `at` for an unknown option, a
/// missing or non-numeric value, a zero scale, or a count out of range.
XfSpec parse_xf(std::span<const std::string_view> args, const SourceLoc& at, const XfLimits& lim);

/// Parses a finite double (the whole token; a leading '+' is allowed). Throws
/// InputError at `at` naming `what` otherwise.
double parse_mgf_number(std::string_view tok, const SourceLoc& at, std::string_view what);
/// Parses a whole-token integer in [lo, hi]; throws InputError otherwise.
long parse_mgf_integer(std::string_view tok, long lo, long hi, const SourceLoc& at,
                       std::string_view what);

}  // namespace hrad
