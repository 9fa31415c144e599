// The fixture of the end-to-end tests: runs the hrad binary (HRAD_BINARY) in a
// temporary folder of its own and captures its exit status, stdout and stderr.
#pragma once

#include "tests/error_text.h"
#include "tests/read_text.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace hrad::test {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out, err;
};

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("hrad-cli-test-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Runs `hrad ARGS` in the temporary folder with stdin closed; `env` is prefixed
  /// to the command ("NAME=value ").
  Result hrad(const std::string& args, const std::string& env = "") const {
    const fs::path out = dir_ / ".stdout", err = dir_ / ".stderr";
    const std::string cmd = "cd '" + dir_.string() + "' && " + env + "'" HRAD_BINARY "' " + args +
                            " > '" + out.string() + "' 2> '" + err.string() + "' < /dev/null";
    const int rc = std::system(cmd.c_str());
    Result r;
    r.status = (rc != -1 && WIFEXITED(rc)) ? WEXITSTATUS(rc) : -1;
    r.out = read_text(out);
    r.err = read_text(err);
    fs::remove(out);
    fs::remove(err);
    return r;
  }

  /// `hrad ARGS` fails within the test's time (a FIFO nobody writes would block a reader
  /// for ever: `timeout` turns that into status 124), says `what`, and leaves the folder
  /// as it was.
  void refused(const std::string& args, const std::string& what) const {
    const int before = entries();
    const Result r = hrad(args, "timeout 20 ");
    EXPECT_NE(r.status, 124) << args << ": blocked";
    EXPECT_NE(r.status, 0) << args;
    EXPECT_TRUE(contains(r.err, what)) << args << ": " << r.err;
    EXPECT_EQ(entries(), before) << args;
  }

  /// Files and folders in the temporary folder (0 when a failed run created nothing).
  [[nodiscard]] int entries() const {
    int n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
    return n;
  }

  void write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
  }

  fs::path dir_;
};

}  // namespace hrad::test
