// Wavefront OBJ/MTL reader. Polygons stay polygons (SceneBuilder keeps planar convex
// ones and triangulates the rest).
//
// Materials (MTL), the path-tracer reading of the Cornell boxes in scenes/:
//   Kd r g b   diffuse reflectance rho, each channel in [0,1] (an error otherwise,
//              naming the .mtl file and the Kd line). A material without Kd gets
//              tinyobjloader's default (0, or 0.6 with a map_Kd) and a counted warning.
//   Ke r g b   emitted RADIANCE L (W m^-2 sr^-1 in scene units). A Lambertian emitter
//              of radiance L has exitance E = pi * L, so Material::emission = pi * Ke.
//   Kd and Ke must be three plain numbers (the spectral/xyz forms are not supported).
//   Everything else (Ka, Ks, Ns, maps, ...) is ignored: hrad surfaces are diffuse.
//
// Statements: v, f (any vertex count >= 3; "v/vt/vn" references, only v is used),
// usemtl, mtllib. vn, vt, g, o, s and other grouping statements are ignored
// silently; l, p, curves and unknown statements are ignored with a counted warning.
//
// Errors (InputError naming file and 1-based line; line 0 for the whole file):
//   - OBJ file that cannot be opened; a NUL byte (binary file);
//   - a coordinate that is not a plain finite number ("nan", "1e400", "1abc"),
//     beyond +-1e30, or fewer than 3 coordinates; a number tinyobjloader reads
//     differently from its exact value (hundreds of digits, huge exponents);
//   - a vertex index of 0, beyond the file's vertex count, or a relative (negative)
//     index reaching before the first vertex; a face with fewer than 3 vertices;
//   - a material library named by mtllib that does not exist (error, not warning:
//     a scene without its materials would silently render grey) -- reported at the
//     OBJ file and the mtllib line;
//   - a bad Kd/Ke (reported at the .mtl file and the Kd/Ke line);
//   - a scene with no polygon of positive area (SceneBuilder::finish).
// Material names are one token (newmtl NAME, usemtl NAME); the first definition of
// a name wins (later ones: counted warning).
// usemtl of a name no .mtl defines, and faces before any usemtl, get
// SceneBuilder::default_material() (grey 0.5) with counted warnings.
//
// Parsing is done by tinyobjloader (its double-precision build, compiled privately
// into obj_reader.cpp). It is lenient where hrad must not be: it reads "nan" as 0,
// "1abc" as 1, keeps "f 1 2 99" with a warning naming the last line of the file,
// keeps relative indices before the first vertex as negative numbers, and counts
// a face's vertices in 8 bits (a 300-gon is reported as a 44-gon). So a
// light pre-scan of the text checks every v/f/Kd/Ke statement first (and records
// line numbers, which tinyobjloader does not give for MTL files); tinyobjloader's
// results are then cross-checked against the pre-scan.
#pragma once

#include <string>
#include <string_view>

#include "core/scene/scene.h"

namespace hrad {

/// Reads an OBJ file and the .mtl files its mtllib statements name (relative to the
/// OBJ's folder). Scene::name is the file stem, Scene::source the path.
Scene read_obj(const std::string& path);

/// Parses OBJ text with its MTL text given inline (for tests and fuzzing); mtllib
/// statements are ignored. Errors name `name_for_errors` for the OBJ text and the
/// same name with ".obj" replaced by ".mtl" (or ".mtl" appended) for the MTL text.
Scene parse_obj(std::string_view obj_text, std::string_view mtl_text,
                const std::string& name_for_errors);

}  // namespace hrad
