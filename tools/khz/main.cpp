// khz: command-line front end to the Kilohertz libraries.
#include "commands.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/reduced/version.hpp>
#include <khz/reduced/worker_threads.hpp>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app("khz: Kilohertz command-line tool", "khz");
  app.set_version_flag("--version", std::string("khz ") + khz::reduced::library_version());
  app.require_subcommand(1);
  khz::tool::add_info_command(app);
  khz::tool::add_convert_command(app);
  khz::tool::add_repair_command(app);
  khz::tool::add_prep_command(app);
  khz::tool::add_shape_command(app);
  khz::tool::add_run_command(app);
  khz::tool::add_report_command(app);
  try {
    khz::reduced::set_worker_threads_from_environment();  // KHZ_THREADS
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const khz::reduced::Error& error) {
    std::cerr << "khz: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
