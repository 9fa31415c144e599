// Two-sided faces as pairs of one-sided ones. hrad's faces reflect and emit on their
// front side only; a face whose material is two-sided (MGF `sides 2`, the MGF default)
// gets a back face: the same vertices in reverse order (so the opposite normal) and the
// same material, which receives and emits on its own side and exchanges light with
// its own radiosity. The pair coincides; RayScene treats such twins as one sheet
// (core/raycast/face_twins.h), so neither occludes the other.
//
// The `sides` option chooses:
//   auto  a back face for every face whose material is two-sided (OBJ and built-in
//         scenes have none: they stay one-sided);
//   one   no back faces: every face one-sided, as RenderPark reads MGF;
//   two   a back face for every face, whatever its material.
// A face whose reversed copy is already in the scene (a sheet modelled from both sides)
// gets none. The back face keeps the front's first vertex and reverses the rest, so
// that a quad is split along the same diagonal by the ray tracer (exactly the same
// triangles: no crack between the two sides).
//
// The `emitter_sides` option chooses whether a back face emits:
//   front  the back face of an emitter reflects but does not emit (it gets a copy of
//          the material without emission). MGF says `sides 2` of the material, not
//          of the light: RenderPark, for which the classic MGF scenes were written,
//          reads them one-sided, and Radiance's mgf2rad makes every emitter a `light`,
//          whose polygons shine from the front only; a luminaire strip modelled as
//          one polygon lights the room below it, not the ceiling above.
//   both   the back face emits like the front: MGF `sides 2` taken literally (twice
//          the emitted power of each two-sided emitter).
#pragma once

#include "core/base/enum_names.h"
#include "core/scene/scene.h"

#include <string>
#include <string_view>

namespace hrad {

enum class Sides { Auto, One, Two };
inline constexpr EnumName<Sides> kSidesNames[] = {
    {Sides::Auto, "auto", "MGF sides 2; OBJ and built-in scenes one-sided"},
    {Sides::One, "one", "no back faces: every face one-sided"},
    {Sides::Two, "two", "every face two-sided"},
};
constexpr std::span<const EnumName<Sides>> enum_names(Sides) { return kSidesNames; }

enum class EmitterSides { Front, Both };
inline constexpr EnumName<EmitterSides> kEmitterSidesNames[] = {
    {EmitterSides::Front, "front", "it reflects only, as RenderPark and Radiance read MGF"},
    {EmitterSides::Both, "both", "it emits like the front: MGF sides 2 taken literally"},
};
constexpr std::span<const EnumName<EmitterSides>> enum_names(EmitterSides) {
  return kEmitterSidesNames;
}

/// Appends the back faces `mode` asks for, dark or emitting as `emitters` says, and
/// records the modes and the counts in scene.sides, scene.emitter_sides,
/// scene.back_faces, scene.dark_back_faces and scene.back_faces_present (with a
/// warning when some back faces were kept dark). Run once per scene.
void add_back_faces(Scene& scene, Sides mode, EmitterSides emitters = EmitterSides::Front);

}  // namespace hrad
