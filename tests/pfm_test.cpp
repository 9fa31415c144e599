// Portable Float Map output (core/output/pfm.h): header, byte order, row order, round trip
// and errors.
#include "core/output/pfm.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace hrad {
namespace {

Image small() {
  Image img;
  img.width = 3;
  img.height = 2;
  for (int i = 0; i < 6; ++i) {
    img.radiance.push_back(Rgb(i, 10 + i, 0.25 * i));
    img.coverage.push_back(1.0f);
  }
  img.radiance[0] = Rgb::Zero();  // a miss
  return img;
}

float float_at(const std::string& bytes, std::size_t offset) {
  std::uint32_t bits = 0;
  for (int b = 0; b < 4; ++b)
    bits |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[offset + b])) << (8 * b);
  return std::bit_cast<float>(bits);
}

TEST(Pfm, HeaderLayoutAndRowOrder) {
  const std::string bytes = encode_pfm(small());
  const std::string header = "PF\n3 2\n-1.0\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  ASSERT_EQ(bytes.size(), header.size() + 3 * 2 * 12);
  // The first pixel stored is the bottom-left one (x 0, row 1 of the picture: index
  // 3), little-endian floats R, G, B; the last one is the top-right (index 2).
  EXPECT_EQ(float_at(bytes, header.size()), 3.0f);
  EXPECT_EQ(float_at(bytes, header.size() + 4), 13.0f);
  EXPECT_EQ(float_at(bytes, header.size() + 8), 0.75f);
  EXPECT_EQ(float_at(bytes, bytes.size() - 12), 2.0f);
}

TEST(Pfm, RoundTripsAndReadsBigEndian) {
  const Image a = small();
  const Image b = decode_pfm(encode_pfm(a));
  ASSERT_EQ(b.width, 3);
  ASSERT_EQ(b.height, 2);
  for (std::size_t i = 0; i < a.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(b.radiance[i][c], static_cast<float>(a.radiance[i][c])) << i;
  EXPECT_EQ(b.coverage[0], 0.0f);  // (0, 0, 0): nothing there
  EXPECT_EQ(b.coverage[1], 1.0f);

  // A big-endian file (positive scale) of one pixel.
  std::string big = "PF\n1 1\n1.0\n";
  for (float f : {1.5f, 2.0f, 0.0f}) {
    const auto bits = std::bit_cast<std::uint32_t>(f);
    for (int s = 24; s >= 0; s -= 8) big.push_back(static_cast<char>((bits >> s) & 0xff));
  }
  const Image one = decode_pfm(big);
  EXPECT_EQ(one.radiance[0][0], 1.5);
  EXPECT_EQ(one.radiance[0][1], 2.0);
}

TEST(Pfm, RejectsBadFilesAndValues) {
  EXPECT_THROW((void)decode_pfm("Pf\n1 1\n-1.0\n1234"), std::invalid_argument);  // grey
  EXPECT_THROW((void)decode_pfm("PF\n2 1\n-1.0\n" + std::string(12, '\0')),
               std::invalid_argument);  // short
  EXPECT_THROW((void)decode_pfm("PF\n0 1\n-1.0\n"), std::invalid_argument);
  EXPECT_THROW((void)decode_pfm("PF\n1 1\n0\n" + std::string(12, '\0')), std::invalid_argument);
  EXPECT_THROW((void)decode_pfm("PF\n1"), std::invalid_argument);
  Image bad = small();
  bad.radiance[4][1] = -1;
  EXPECT_THROW((void)encode_pfm(bad), std::invalid_argument);
  bad.radiance[4][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)encode_pfm(bad), std::invalid_argument);
  bad.radiance[4][1] = 1e39;  // beyond a float
  EXPECT_THROW((void)encode_pfm(bad), std::invalid_argument);
  bad.radiance.pop_back();
  EXPECT_THROW((void)encode_pfm(bad), std::invalid_argument);
}

}  // namespace
}  // namespace hrad
