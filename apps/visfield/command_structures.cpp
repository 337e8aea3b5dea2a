#include <iostream>
#include <memory>

#include "commands.hpp"
#include "visfield/registry/registry.hpp"

namespace vf::cli {

void register_structures_command(CLI::App& app, Action& action) {
  CLI::App* cmd = app.add_subcommand(
      "structures", "List the structures --accel and --occluder accept, with their parameters and defaults");
  cmd->callback([&action] {
    action = [] {
      std::cout << "Structures, written NAME[:key=value,...] (for example bvh:leaf=4,levels=2):\n" << structures_help();
      return 0;
    };
  });
}

}  // namespace vf::cli
