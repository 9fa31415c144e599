// Numbers beyond what can be run (hostile input, round three): every command refuses
// them with the option named before anything is made. --threads 100000 crashed the
// OpenMP runtime in solve, reference and experiment and left an empty output folder;
// reference --max-samples -1 wrapped to 2^64 - 1; --floor nan, --worker-timeout nan and
// simulate's infinite costs were accepted (simulate then wrote inf and nan to its CSV).
#include "tests/cli_fixture.h"

#include <gtest/gtest.h>

#include <string>

namespace {

using hrad::test::contains;
using hrad::test::Result;

// Refusals (Cli::refused) exit with status 1, or 2 for CLI11's usage errors.
using OptionBounds = hrad::test::Cli;

TEST_F(OptionBounds, ThreadCountsAreBoundedEverywhere) {
  refused("solve builtin:cornell --threads 100000 --out run", "threads = 100000 is out of range");
  refused("solve builtin:cornell --set threads=1000000000 --out run", "threads");
  write("t.json", R"({"threads": 50000})");
  refused("solve builtin:cornell --config t.json --out run", "between 1 and 1024");
  refused("reference builtin:cornell --random-probes 4 --threads 100000 --out ref", "--threads");
  write("exp.json",
        R"({"name": "x", "scenes": ["builtin:cornell"], "sweep": {"threads": [1, 100000]}})");
  refused("experiment exp.json --out x", "between 1 and 1024");
  refused("topology --threads 100000", "--threads");
  // Ray counts: a single task ran for minutes.
  refused("solve builtin:cornell --set visibility_rays=100000 --out run", "visibility_rays");
  refused("solve builtin:cornell --set row_sum_rays=10000000 --out run", "row_sum_rays");
}

// A value out of range in a configuration file is said with the file's name, and one
// that underflowed to 0 (1e-400) says so: it was quoted as "eps = 0" with no file.
TEST_F(OptionBounds, AConfigFilesValueOutOfRangeNamesTheFile) {
  write("uf.json", R"({"iterations": 2, "eps": 1e-400})");
  refused("solve builtin:cornell --config uf.json --out run",
          "uf.json: option eps = 0 is out of range");
  refused("solve builtin:cornell --config uf.json --out run", "reads as 0");
  write("neg.json", R"({"threads": -3})");
  refused("solve builtin:cornell --config neg.json --out run",
          "neg.json: option threads = -3 is out of range");
  const Result r = hrad("solve builtin:cornell --config neg.json --out run");
  EXPECT_FALSE(contains(r.err, "reads as 0")) << r.err;
}

TEST_F(OptionBounds, ReferenceNumbersAreFiniteAndInRange) {
  refused("reference builtin:cornell --random-probes 4 --max-samples -1 --out ref",
          "--max-samples");
  refused("reference builtin:cornell --random-probes 4 --floor nan --out ref", "--floor");
  refused("reference builtin:cornell --random-probes 4 --rel-error inf --out ref", "--rel-error");
  refused("reference builtin:cornell --random-probes 4 --rel-error 0 --out ref", "--rel-error");
}

TEST_F(OptionBounds, ExperimentAndSimulateNumbersAreFinite) {
  write("exp.json", R"({"name": "x", "scenes": ["builtin:cornell"]})");
  refused("experiment exp.json --worker-timeout nan --out x", "--worker-timeout");
  refused("simulate missing.trace --take-ns inf", "--take-ns");
  refused("simulate missing.trace --slowdown nan", "--slowdown");
  refused("simulate missing.trace --scale -1", "--scale");
  ASSERT_EQ(
      hrad("solve builtin:cornell --iterations 1 --set trace=t.trace --out run --quiet").status, 0);
  // A cost file cannot bring infinity either: JSON has none, and 1e999 overflows.
  write("costs.json", R"({"take_op_ns": 1e999})");
  refused("simulate run/t.trace --costs costs.json --procs 2", "costs.json: not valid JSON");
}

// Seeds are never negative: reference --seed -1 wrapped to 2^64 - 1 (and ran), while
// solve refused it as "not an unsigned integer"; now every place a seed is read says
// it is out of range.
TEST_F(OptionBounds, NegativeSeedsAreRefusedEverywhere) {
  refused("reference builtin:cornell --random-probes 4 --seed -1 --out ref",
          "--seed: -1 is outside 0..18446744073709551615");
  refused("compare a b --seed -1", "--seed: -1 is outside 0..");
  refused("solve builtin:cornell --set seed=-1 --out run", "option seed = -1 is out of range");
  write("s.json", R"({"seed": -1})");
  refused("solve builtin:cornell --config s.json --out run",
          "s.json: option seed = -1 is out of range");
  write("exp.json", R"({"name": "x", "scenes": ["builtin:cornell"], "sweep": {"seed": [1, -1]}})");
  refused("experiment exp.json --out x", "option seed = -1 is out of range");
}

// A whole number in exponent form is that integer, range-checked like any other:
// threads = 1e9 said "expects an integer, got '1e9'", and 100000000000 (beyond an int)
// the same.
TEST_F(OptionBounds, IntegersInExponentFormAreRangeChecked) {
  refused("solve builtin:cornell --set threads=1e9 --out run",
          "option threads = 1000000000 is out of range: it must be between 1 and 1024");
  refused("solve builtin:cornell --set iterations=100000000000 --out run",
          "option iterations = 100000000000 is out of range: it must be between 1 and 10000");
  refused("solve builtin:cornell --set threads=-1e12 --out run",
          "option threads = -1e12 is out of range: it must be between 1 and 1024");
  refused("solve builtin:cornell --set seed=1e30 --out run", "option seed = 1e30 is out of range");
  // (and a word that is no number is named with the right article)
  refused("solve builtin:cornell --set seed=abc --out run",
          "option 'seed' expects an unsigned integer, got 'abc'");
  refused("solve builtin:cornell --set threads=2.5 --out run", "expects an integer, got '2.5'");
  write("t.json", R"({"threads": 1e10})");
  refused("solve builtin:cornell --config t.json --out run", "t.json: option threads = ");
  refused("solve builtin:cornell --config t.json --out run",
          "is out of range: it must be between 1 and 1024");
  refused("reference builtin:cornell --random-probes 1e9 --out ref",
          "--random-probes: 1e9 is outside 1..1048576");
  refused("topology --threads 1e5", "--threads: 1e5 is outside 1..1024");
  refused("reference builtin:cornell --random-probes 2.5 --out ref",
          "'2.5' is not an integer in 1..1048576");
  // Within range, the exponent form is accepted.
  const Result r =
      hrad("reference builtin:cornell --random-probes 4e0 --max-samples 2e3 --out ref");
  EXPECT_EQ(r.status, 0) << r.err;
}

// A cost file is bounded like the flags: {"take_op_ns": 1e308} was taken, and the CSV
// held inf and -nan.
TEST_F(OptionBounds, ACostFilesValuesAreBounded) {
  ASSERT_EQ(
      hrad("solve builtin:cornell --iterations 1 --set trace=t.trace --out run --quiet").status, 0);
  for (const char* cost : {R"("take_op_ns": 1e308)", R"("block_ns": 1e300)", R"("slowdown": 1e308)",
                           R"("slowdown_per_proc": 1e308)"}) {
    write("costs.json", std::string("{") + cost + "}");
    const std::string key = std::string(cost).substr(1, std::string(cost).find('"', 1) - 1);
    refused("simulate run/t.trace --costs costs.json --procs 2",
            "costs.json: '" + key + "' must be between");
  }
  write("costs.json", R"({"take_op_ns": 1e12, "slowdown": 2})");
  EXPECT_EQ(hrad("simulate run/t.trace --costs costs.json --procs 2 --quiet").status, 0);
}

// hrad render checks its image's memory before it reads the mesh, as solve checks
// image_width: --width 16384 went past 5.5 GB with no check under the default limit.
TEST_F(OptionBounds, RenderRefusesAnImageAboveTheMemoryLimit) {
  ASSERT_EQ(hrad("solve builtin:cornell --iterations 1 --set image_width=64 --set max_memory_gb=1 "
                 "--out run --quiet")
                .status,
            0);
  refused("render run --width 16384 --max-memory-gb 2",
          "--width 16384: rendering 16384 x 12288 pixels needs about 12.1 GB, above the limit of "
          "2 GB");
  refused("render run --width 16384", "above the limit of 1 GB");  // the solve's limit
  EXPECT_FALSE(std::filesystem::exists(dir_ / "run" / "rerender.png"));
  const Result r = hrad("render run --width 1.6e2 --max-memory-gb 1");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "160 x 120 pixels")) << r.out;
}

// Loading and preparing were checked against max_memory_gb only at their ends (a cabin
// of four million polygons took 2.5 GB loading under 0.3 GB): the load stops as it
// passes the limit, and preparing is refused before it starts when the polygons alone
// need more.
TEST_F(OptionBounds, LoadingAndPreparingStopAtTheMemoryLimit) {
  const std::string cabin = "solve 'builtin:cabin?rows=30' --set image_width=64 --out run ";
  refused(cabin + "--set max_memory_gb=0.01",
          "builtin:cabin?rows=30: loading the scene took more than the limit of 0.01 GB");
  // 165,128 polygons: about 40 MB loaded, then about 0.1 GB to prepare.
  refused(cabin + "--set max_memory_gb=0.06",
          "preparing the scene (165128 polygons: ray scene, hierarchy, contacts) needs about "
          "0.0991 GB of memory, above the limit of 0.06 GB");
}

}  // namespace
