// Portable Float Map (PFM) images: linear radiance for quantitative comparison, beside
// the tone-mapped render.png.
//
// Layout, as written: the text header "PF\n<width> <height>\n-1.0\n" (PF: three channels;
// a negative scale means little-endian floats), then width x height pixels of three
// 32-bit IEEE floats R, G, B, rows from the *bottom* of the picture to the top (the PFM
// convention), each row left to right. Values are the pixel's mean radiance L = B / pi
// over its samples (W per steradian per unit area of the scene's units), misses 0:
// exactly the values render.png is tone-mapped from (core/output/render.h).
#pragma once

#include "core/output/render.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace hrad {

/// The PFM file of an image's radiance (above). Throws std::invalid_argument when a
/// value is negative, not finite or beyond a 32-bit float.
[[nodiscard]] std::string encode_pfm(const Image& img);

/// encode_pfm, written atomically.
void write_pfm(const Image& img, const std::filesystem::path& out);

/// Reads a PFM file's bytes (three channels, either byte order) back into an Image
/// (rows from the top, coverage 1 where any channel is non-zero). Throws
/// std::invalid_argument saying what is wrong with the header or the size.
[[nodiscard]] Image decode_pfm(std::string_view bytes);

}  // namespace hrad
