// `hrad experiment CONFIG.json`: the experiment harness (sweeps over scenes, schedulers,
// thread counts; issue 6). Until it lands this command only checks that the file
// exists and says honestly that nothing was run (exit status 2).
#include "experiments/commands.h"

#include <fmt/format.h>

#include <filesystem>
#include <string>

namespace hrad::cli {

void register_experiment(CLI::App& app, CommandContext& ctx) {
  CLI::App* sub = app.add_subcommand(
      "experiment", "Run an experiment described by a JSON file (not built yet: issue 6).");
  auto config = std::make_shared<std::string>();
  sub->add_option("CONFIG", *config, "Experiment configuration (JSON)")->required();
  sub->callback([&ctx, config] {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(*config, ec)) {
      fmt::print(stderr, "hrad: {}: no such file\n", *config);
      ctx.status = 1;
      return;
    }
    fmt::print(stderr, "hrad experiment: the experiment harness is not built yet (issue 6)\n");
    ctx.status = 2;
  });
}

}  // namespace hrad::cli
