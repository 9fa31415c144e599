// Every input file must be a regular file (hostile input, round three): probes,
// configurations, views, traces, cost and stats files read from a FIFO blocked for
// ever, and from /dev/zero or /dev/urandom were read until std::bad_alloc without the
// file's name. Each command now names the file and says what it is, at once.
#include "tests/cli_fixture.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>

namespace {

using hrad::test::contains;
using hrad::test::Result;

class InputFiles : public hrad::test::Cli {
 protected:
  /// `hrad ARGS` fails within the test's time (a FIFO nobody writes would block a
  /// reader for ever: `timeout` turns that into status 124) and says `what`.
  void refused(const std::string& args, const std::string& what) const {
    const Result r = hrad(args, "timeout 20 ");
    EXPECT_NE(r.status, 124) << args << ": blocked";
    EXPECT_NE(r.status, 0) << args;
    EXPECT_TRUE(contains(r.err, what)) << args << ": " << r.err;
  }
};

TEST_F(InputFiles, FifosDevicesAndFoldersAreRefusedByName) {
  ASSERT_EQ(::mkfifo((dir_ / "pipe").c_str(), 0600), 0);
  for (const std::string f : {"pipe", "/dev/zero"}) {
    const std::string kind = f == "pipe" ? "(a FIFO)" : "(a device)";
    refused("solve builtin:cornell --probes " + f + " --out run",
            f + ": the probe file is not a regular file " + kind);
    refused("solve builtin:cornell --config " + f + " --out run",
            f + ": the config file is not a regular file " + kind);
    refused("solve builtin:cornell --view " + f + " --out run",
            f + ": the view file is not a regular file " + kind);
    refused("simulate " + f + " --procs 2", f + ": the trace is not a regular file " + kind);
    refused("experiment " + f + " --out x",
            f + ": the experiment configuration is not a regular file " + kind);
    refused("reference builtin:cornell --probes " + f + " --out ref",
            f + ": the probe file is not a regular file " + kind);
  }
  ASSERT_EQ(hrad("solve builtin:cornell --iterations 1 --set trace=t.trace --out run --quiet").status,
            0);
  refused("simulate t.trace --procs 2 --costs pipe", "pipe: the cost file is not a regular file");
  refused("simulate t.trace --procs 2 --measured /dev/urandom",
          "/dev/urandom: the stats file is not a regular file (a device)");
  refused("compare run pipe", "pipe: the probe table is not a regular file (a FIFO)");
  refused("solve builtin:cornell --probes run --out run2",
          "run: the probe file is not a regular file (a folder)");
}

}  // namespace
