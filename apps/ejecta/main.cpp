// ejecta: buried-charge loading of vehicle underbodies. One program, several sub-commands.
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"

int main(int argc, char** argv) {
  CLI::App app{"ejecta: predicts how a buried charge in sand loads a vehicle underbody. SI units throughout."};
  app.set_version_flag("--version", std::string("ejecta ") + ejecta::build_info::version);
  app.require_subcommand(1);
  std::vector<ejecta::cli::Action> actions{ejecta::cli::addSoilCommand(app), ejecta::cli::addVerifyCommand(app), ejecta::cli::addRunCommand(app), ejecta::cli::addSweepCommand(app),
                                           ejecta::cli::addValidateCommand(app)};
  // An empty value ("" or --opt=) never means the default: it is refused, naming the option.
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool empty_inline = arg.size() > 2 && arg.rfind("--", 0) == 0 && arg.back() == '=';
    if (arg.empty() || empty_inline) {
      const std::string opt = empty_inline ? arg.substr(0, arg.size() - 1) : (i > 1 && argv[i - 1][0] == '-' ? argv[i - 1] : "an argument");
      std::cerr << "ejecta: error: " << opt << ": an empty value is not allowed (see ejecta --help)\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ejecta: error: " << e.what() << " (see ejecta --help)\n";
    return 2;
  }
  try {
    for (auto& action : actions)
      if (int rc = action(); rc >= 0) return rc;
    return 2;
  } catch (const ejecta::InputError& e) {
    std::cerr << "ejecta: error: " << e.what() << '\n';
    return 2;
  } catch (const ejecta::RunError& e) {
    std::cerr << "ejecta: run stopped: " << e.what() << '\n';
    return 3;
  } catch (const std::filesystem::filesystem_error& e) {
    // an output path the user named that cannot be made or written (a file where a folder must be,
    // no permission): said in words, naming the path, as bad input
    std::cerr << "ejecta: error: " << e.path1().string() << ": " << e.code().message() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ejecta: failed: " << e.what() << '\n';
    return 1;
  }
}
