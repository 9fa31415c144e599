// Every input file must be a regular file (hostile input, round three): probes,
// configurations, views, traces, cost and stats files read from a FIFO blocked for
// ever, and from /dev/zero or /dev/urandom were read until std::bad_alloc without the
// file's name. Each command now names the file and says what it is, at once.
#include "tests/cli_fixture.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <nlohmann/json.hpp>

#include <string>

namespace {

using hrad::test::contains;
using hrad::test::Result;

using InputFiles = hrad::test::Cli;

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
  ASSERT_EQ(
      hrad("solve builtin:cornell --iterations 1 --set trace=t.trace --out run --quiet").status, 0);
  refused("simulate run/t.trace --procs 2 --costs pipe",
          "pipe: the cost file is not a regular file");
  refused("simulate run/t.trace --procs 2 --measured /dev/urandom",
          "/dev/urandom: the stats file is not a regular file (a device)");
  refused("compare run pipe", "pipe: the probe table is not a regular file (a FIFO)");
  refused("solve builtin:cornell --probes run --out run2",
          "run: the probe file is not a regular file (a folder)");
}

}  // namespace

namespace {

// --set trace=FILE overwrote any file, the input scene included, and only at the end of
// the run; now a file that is not an hrad trace is refused before anything is made, and
// an earlier trace is replaced.
TEST_F(InputFiles, ATraceNeverOverwritesAnotherFile) {
  const std::string scene = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  write("tri.obj", scene);
  // (A relative trace is inside the output folder: ../tri.obj from run/ is the scene.)
  Result r = hrad("solve tri.obj --set trace=../tri.obj --out run");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "tri.obj: trace: the file exists and is not an hrad trace")) << r.err;
  EXPECT_EQ(hrad::test::read_text(dir_ / "tri.obj"), scene);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "run"));
  r = hrad("solve builtin:cornell --iterations 1 --set trace=t.trace --out a --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "a" / "t.trace"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "t.trace"));
  const auto stats = nlohmann::json::parse(hrad::test::read_text(dir_ / "a" / "stats.json"));
  EXPECT_EQ(stats["outputs"]["trace"], "t.trace");
  EXPECT_EQ(stats["config"]["trace"], "t.trace");
  // An earlier trace is replaced (an absolute path is used as it is).
  const std::string abs = (dir_ / "a" / "t.trace").string();
  r = hrad("solve builtin:cornell --iterations 1 --set trace=" + abs + " --out b --quiet");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "b" / "t.trace"));
}

// A UTF-8 byte-order mark at the start of an OBJ, MTL, MGF, probe or view file broke
// its first line; now each reads as it does without one.
// A NUL byte (a binary file given as text) cut the message that quoted its line.
TEST_F(InputFiles, ANulByteIsNamedWithItsLine) {
  write("p.txt", std::string("0.5 0.5 0.5 0 0 1\n0.5 0.\0 5 0 0 1\n", 35));
  refused("solve builtin:cornell --probes p.txt --out run",
          "p.txt:2: a NUL byte at column 7: this is not a text file");
  write("box.obj", std::string("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\0 3\n", 34));
  refused("solve box.obj --out run", "box.obj:4: a NUL byte at column 6");
  write("v.view", std::string("eye 0 0 1\nlook 0\0 0 0\n", 23));
  refused("solve builtin:cornell --view v.view --out run", "v.view:2: a NUL byte at column 7");
}

// A full disk said "the stream failed" instead of the system's reason. A file size
// limit (ulimit -f, with SIGXFSZ ignored) fails the writes the same way, with EFBIG.
TEST_F(InputFiles, AFailedWriteSaysWhy) {
  const Result r =
      hrad("solve builtin:cornell --iterations 1 --out run --quiet", "trap '' XFSZ; ulimit -f 8; ");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "error while writing run/solution.ply: File too large")) << r.err;
  // Without the trap SIGXFSZ's default action ended the run in the middle of a write,
  // with no message and the files written so far left behind.
  const Result d = hrad("solve builtin:cornell --iterations 1 --out run2 --quiet", "ulimit -f 8; ");
  EXPECT_EQ(d.status, 1) << d.err;
  EXPECT_TRUE(contains(d.err, "error while writing run2/solution.ply: File too large")) << d.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "run2" / "stats.json"));
}

TEST_F(InputFiles, AByteOrderMarkIsSkipped) {
  const std::string bom = "\xEF\xBB\xBF";
  const std::string obj =
      "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "usemtl wall\nf 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\n"
      "usemtl light\nf 1 4 8 5\n";
  const std::string mtl = "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n";
  const std::string probes = "0.5 0.5 0.001 0 0 1\n";
  const std::string view = "eye 0.5 0.5 0.9\nlook 0.5 0.5 0\nup 0 1 0\n";
  const std::string mgf =
      "m w =\n c\n rd 0.5\n ed 100\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv c =\n p 0 1 0\nf a b c\n";
  for (const bool with : {false, true}) {
    const std::string b = with ? bom : "";
    const std::string d = with ? "with" : "without";
    std::filesystem::create_directories(dir_ / d);
    write(d + "/box.obj", b + obj);
    write(d + "/box.mtl", b + mtl);
    write(d + "/p.txt", b + probes);
    write(d + "/v.view", b + view);
    write(d + "/t.mgf", b + mgf);
    const Result r = hrad("solve " + d + "/box.obj --iterations 1 --probes " + d +
                          "/p.txt --view " + d + "/v.view --out " + d + "/run --quiet");
    EXPECT_EQ(r.status, 0) << d << ": " << r.err;
    const Result m = hrad("solve " + d + "/t.mgf --iterations 1 --out " + d + "/mgf --quiet");
    EXPECT_EQ(m.status, 0) << d << ": " << m.err;
  }
  EXPECT_EQ(hrad::test::read_text(dir_ / "with" / "run" / "probes.csv"),
            hrad::test::read_text(dir_ / "without" / "run" / "probes.csv"));
  EXPECT_EQ(hrad::test::read_text(dir_ / "with" / "mgf" / "solution.ply"),
            hrad::test::read_text(dir_ / "without" / "mgf" / "solution.ply"));
  EXPECT_EQ(hrad("compare with/run with/run/probes.csv").status, 0);
}

}  // namespace
