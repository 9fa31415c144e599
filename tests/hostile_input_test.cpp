// Hostile input (issue 15): each case crashed, hung, wrote a misleading file or
// printed an unreadable message before its fix.
#include "tests/cli_fixture.h"

#include <gtest/gtest.h>

#include <string>

namespace {

using hrad::test::contains;
using hrad::test::Result;
namespace fs = std::filesystem;

class HostileInput : public hrad::test::Cli {};

std::string nested(int levels) {
  return std::string(static_cast<std::size_t>(levels), '[') +
         std::string(static_cast<std::size_t>(levels), ']');
}

// 100,000 nested brackets crashed (SIGSEGV while echoing the value), and 50,000 gave
// a 100 KB message; a 5 MB string was echoed whole.
TEST_F(HostileInput, DeeplyNestedOrHugeJsonIsRejectedWithAShortMessage) {
  write("deep.json", "{\"threads\":\n" + nested(100000) + "}");
  Result r = hrad("solve builtin:cornell --config deep.json --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "deep.json:2: JSON nested deeper than 64 levels")) << r.err;
  EXPECT_LT(r.err.size(), 300u);

  write("exp.json", "{\"scenes\": " + nested(100000) + "}");
  r = hrad("experiment exp.json --out x");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "exp.json:1: JSON nested deeper than 64 levels")) << r.err;
  EXPECT_LT(r.err.size(), 300u);

  // Nesting within the bound is not refused for its depth but for its type, briefly.
  write("fifty.json", "{\"threads\": " + nested(50) + "}");
  r = hrad("solve builtin:cornell --config fifty.json --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "option 'threads' expects an integer")) << r.err;
  EXPECT_LT(r.err.size(), 400u);

  write("long.json", "{\"scheduler\": \"" + std::string(5'000'000, 'x') + "\"}");
  r = hrad("solve builtin:cornell --config long.json --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "more characters")) << r.err.substr(0, 300);
  EXPECT_LT(r.err.size(), 2200u);
  EXPECT_EQ(entries(), 4);  // the four files written here, no output folder
}

}  // namespace
