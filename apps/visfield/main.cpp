// visfield: the command-line tool. Parses the subcommand, runs it, and turns every failure into one
// line on stderr and a non-zero exit code (2 for bad command lines, 1 for bad input or I/O, 128 + the
// signal's number when SIGINT or SIGTERM stopped it: 130, 143).
#include <iostream>
#include <new>
#include <string>

#include "commands.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/isa.hpp"
#include "visfield/core/parse_only.hpp"

int main(int argc, char** argv) {
  vf::install_interrupt_handlers();
  try {
    vf::check_isa_environment();
  } catch (const vf::Error& e) {
    std::cerr << "visfield: error: " << e.what() << "\n";
    return 2;
  }
  CLI::App app{"visfield: fast ray-scene visibility queries (AO, shadows) with exact structures and visibility fields"};
  app.require_subcommand(1);
  vf::cli::Action action;
  vf::cli::register_render_command(app, action);
  vf::cli::register_walk_command(app, action);
  vf::cli::register_info_command(app, action);
  vf::cli::register_calibrate_command(app, action);
  vf::cli::register_select_command(app, action);
  vf::cli::register_stats_command(app, action);
  vf::cli::register_report_command(app, action);
  vf::cli::register_structures_command(app, action);
  vf::cli::register_field_command(app, action);
  vf::cli::register_compare_command(app, action);
  if (argc > 1 && argv[1][0] != '-') {
    std::string known;
    bool found = false;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      known += (known.empty() ? "" : ", ") + sub->get_name();
      found |= sub->get_name() == argv[1];
    }
    if (!found) {
      std::cerr << "visfield: error: unknown command '" << argv[1] << "' (commands: " << known << ")\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::cerr << "visfield: error: " << vf::one_line(e.what()) << "\n";
    return 2;
  }
  if (vf::parse_only()) return 0;
  try {
    return action();
  } catch (const vf::Interrupted& e) {
    std::cerr << "visfield: " << e.what() << "; nothing was written\n";
    return 128 + e.signal();
  } catch (const vf::Error& e) {
    std::cerr << "visfield: error: " << vf::one_line(e.what()) << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "visfield: error: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << "visfield: error: " << vf::one_line(e.what()) << "\n";
  }
  return 1;
}
