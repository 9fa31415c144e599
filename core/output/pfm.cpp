#include "core/output/pfm.h"

#include "core/base/atomic_file.h"

#include <fmt/format.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace hrad {

std::string encode_pfm(const Image& img) {
  const auto pixels = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  if (img.width < 1 || img.height < 1 || img.radiance.size() != pixels)
    throw std::invalid_argument("encode_pfm: the pixel buffer does not match the size");
  std::string out = fmt::format("PF\n{} {}\n-1.0\n", img.width, img.height);
  const std::size_t header = out.size();
  out.resize(header + 12 * pixels);
  char* at = out.data() + header;
  constexpr double kMax = std::numeric_limits<float>::max();
  for (int y = img.height - 1; y >= 0; --y) {
    for (int x = 0; x < img.width; ++x) {
      const Rgb& c = img.at(x, y);
      for (int k = 0; k < 3; ++k) {
        if (!(c[k] >= 0 && c[k] <= kMax))
          throw std::invalid_argument(fmt::format(
              "encode_pfm: pixel ({}, {}) has radiance {} (must be finite, >= 0 and fit a "
              "32-bit float)",
              x, y, c[k]));
        const auto bits = std::bit_cast<std::uint32_t>(static_cast<float>(c[k]));
        for (int b = 0; b < 4; ++b) *at++ = static_cast<char>((bits >> (8 * b)) & 0xffu);
      }
    }
  }
  return out;
}

void write_pfm(const Image& img, const std::filesystem::path& out) {
  write_file_atomically(out, encode_pfm(img));
}

namespace {

/// The next whitespace-delimited token of the header, which ends at one whitespace.
std::string_view token(std::string_view bytes, std::size_t& pos) {
  const auto space = [](char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; };
  while (pos < bytes.size() && space(bytes[pos])) ++pos;
  const std::size_t start = pos;
  while (pos < bytes.size() && !space(bytes[pos])) ++pos;
  if (pos == start || pos == bytes.size())
    throw std::invalid_argument("PFM: the header ends early");
  const std::string_view t = bytes.substr(start, pos - start);
  ++pos;  // the single whitespace before the next field (or the data)
  return t;
}

template <class T>
T number(std::string_view text, const char* what) {
  T v{};
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size())
    throw std::invalid_argument(fmt::format("PFM: bad {} '{}'", what, std::string(text)));
  return v;
}

}  // namespace

Image decode_pfm(std::string_view bytes) {
  std::size_t pos = 0;
  const std::string_view magic = token(bytes, pos);
  if (magic != "PF")
    throw std::invalid_argument(
        fmt::format("PFM: the file starts with '{}', not 'PF' (three-channel PFM)",
                    std::string(magic.substr(0, 8))));
  const int width = number<int>(token(bytes, pos), "width");
  const int height = number<int>(token(bytes, pos), "height");
  const double scale = number<double>(token(bytes, pos), "scale");
  if (width < 1 || height < 1 || width > 1 << 16 || height > 1 << 16)
    throw std::invalid_argument(fmt::format("PFM: bad size {} x {}", width, height));
  if (!(scale != 0) || !std::isfinite(scale))
    throw std::invalid_argument("PFM: the scale must be a non-zero number");
  const auto pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (bytes.size() - pos != 12 * pixels)
    throw std::invalid_argument(fmt::format("PFM: {} bytes of pixels, {} x {} x 12 = {} expected",
                                            bytes.size() - pos, width, height, 12 * pixels));
  const bool little = scale < 0;
  Image img;
  img.width = width;
  img.height = height;
  img.radiance.assign(pixels, Rgb::Zero());
  img.coverage.assign(pixels, 0.0f);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data() + pos);
  for (int row = 0; row < height; ++row) {
    const int y = height - 1 - row;  // rows are stored from the bottom
    for (int x = 0; x < width; ++x) {
      Rgb c;
      for (int k = 0; k < 3; ++k) {
        std::uint32_t bits = 0;
        for (int b = 0; b < 4; ++b) {
          const std::uint32_t byte = *data++;
          bits |= little ? byte << (8 * b) : byte << (8 * (3 - b));
        }
        c[k] = std::bit_cast<float>(bits);
      }
      const std::size_t p = static_cast<std::size_t>(y) * width + x;
      img.radiance[p] = c;
      img.coverage[p] = (c != 0).any() ? 1.0f : 0.0f;
    }
  }
  return img;
}

}  // namespace hrad
