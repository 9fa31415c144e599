// Reader for Greg Ward's Materials and Geometry Format (MGF 1.1, LBL 1995-96), the
// lighting-simulation format of RenderPark and Radiance. Everything goes through
// SceneBuilder; bad input is an InputError naming the file and line.
//
// Supported entities and how they map to a Scene:
// | entity              | handling                                                        |
// |---------------------|-----------------------------------------------------------------|
// | # ...               | comment                                                         |
// | o [name]            | object begin / end: names only (unbalanced ends: counted warning)|
// | xf [args]           | transform begin (args, see mgf_xform.h, -a arrays included) / end|
// | i path [args]       | include, path relative to the including file's directory       |
// |                     | (parse_mgf: to the current directory), with optional transform   |
// | ies ...             | rejected: goniometric (IES) luminaires are not supported        |
// | c [id [= [tmpl]]]   | colour contexts; unnamed = equal-energy grey                    |
// | cxy x y             | CIE 1931 chromaticity (x, y >= 0, x + y <= 1; y = 0 allowed)    |
// | cspec lo hi v1 ..   | spectrum: >= 2 values >= 0 (not all 0), evenly spaced over      |
// |                     | 0 < lo < hi nm, linear between; seen through 360..830 nm        |
// | cct T               | black body (Planck) at T >= 1000 K                              |
// | cmix w1 c1 ...      | mix of named colours, weights taken as luminances (XYZ sum)     |
// | m [id [= [tmpl]]]   | material contexts; unnamed = black two-sided absorber           |
// | rd, ed              | diffuse reflectance (0..1) / emittance (lm/m^2), with the       |
// |                     | colour current at that moment; converted and gamut-mapped as in |
// |                     | mgf_color.h (one counted warning for the mapped colours)        |
// | sides {1|2}         | Material::two_sided (2, the MGF default for every material,     |
// |                     | named or not); core/scene/back_faces.h turns it into back faces      |
// | td, rs, ts, ir      | checked, ignored (one counted warning)                          |
// | v [id [= [tmpl]]]   | vertex contexts; p x y z, n dx dy dz set the current vertex     |
// | f v1 v2 v3 ...      | polygon (SceneBuilder triangulates concave / non-planar ones)   |
// | sph cyl cone ring   | tessellated (mgf_shapes.h) with MgfOptions::segments, by default |
// |                     | by the shape's size against the scene's (mgf_segments.h); kept |
// |                     | until the end of the scene, polygons in file order           |
// | torus prism         |                                                                 |
// | anything else       | ignored with a counted warning (the spec's rule for new entities)|
//
// Vertices are taken untransformed and transformed when used (MGF's rule). A mirroring
// transform reverses polygon winding so that surfaces keep facing the mirrored way.
// Faces before any `m` get SceneBuilder::default_material() (counted warning; one-sided).
// The Scene's name is the file's stem; its units are the file's (MGF says metres).
#pragma once

#include "core/scene/scene.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace hrad {

struct MgfOptions {
  /// Divisions of a full circle for sph, cyl, cone, ring, torus: 0 for the automatic
  /// rule of core/scene/mgf/mgf_segments.h (each shape's radius against the scene's diagonal),
  /// else in [3, 4096] for every shape.
  int segments = 0;
  /// Deepest include nesting; deeper (e.g. a file including itself) is an InputError.
  int max_include_depth = 32;
  /// Largest instance count of one `-a N`, and largest `-i N`.
  long max_array = 100000;
  long max_repeat = 1000000;
  /// Most instances a transform array may make, counting those of every enclosing
  /// array (xf -a 1000 -a 1000 makes 1,000,000); more is an InputError at its xf line,
  /// before anything is expanded (xf -a 100000 -a 100000 around one face grew past
  /// 4 GB before max_work stopped it).
  long max_instances = 1000000;
  /// Entities executed plus polygons generated, after expanding arrays and includes;
  /// more is an InputError (guards against exponential include/array blow-up). A
  /// polygon costs the solver about 1.5 KB (a 1,000,000-triangle array: 1.5 GB), so
  /// this keeps a scene within the memory of a workstation.
  std::int64_t max_work = 10'000'000;
};

/// Reads an MGF file. Throws InputError (file, line) on bad input, including a file
/// that cannot be opened (line 0) and a scene without any polygon.
Scene read_mgf(const std::string& path, const MgfOptions& options = {});

/// Parses MGF text. `name_for_errors` names it in errors and warnings and gives the
/// Scene its name; includes resolve relative to the current directory. Throws
/// std::invalid_argument for options out of range, InputError for bad input.
Scene parse_mgf(std::string_view text, const std::string& name_for_errors,
                const MgfOptions& options = {});

}  // namespace hrad
