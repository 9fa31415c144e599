// read_text: a whole file as a string (bytes as they are), for tests that check what
// a command or writer put in a file. An unreadable file reads as "".
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace hrad::test {

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace hrad::test
