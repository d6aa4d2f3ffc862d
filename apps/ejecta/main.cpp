// ejecta: buried-charge loading of vehicle underbodies. One program, several sub-commands.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "core/error.hpp"
#include "ejecta/build_info.hpp"

#ifdef EJECTA_HAVE_MPI
#include <mpi.h>

#include <cstdlib>
#endif

namespace ejecta::cli {
#ifdef EJECTA_HAVE_MPI
namespace {
// MPI starts only under a launcher (mpirun sets these), so that a plain `ejecta` never needs one.
bool launchedByMpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}
struct MpiSession {
  bool on = false;
  int size = 1, rank = 0;
  MpiSession(int& argc, char**& argv) {
    if (!launchedByMpi()) return;
    MPI_Init(&argc, &argv);
    on = true;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  }
  ~MpiSession() {
    if (on) MPI_Finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};
MpiSession* session = nullptr;
}  // namespace
int mpiRanks() { return session ? session->size : 1; }
int mpiRank() { return session ? session->rank : 0; }
#else
int mpiRanks() { return 1; }
int mpiRank() { return 0; }
#endif
// Bad input is found by every rank alike: rank 0 says it once. A run that stops may stop on one
// rank alone, which says so.
bool speaks() { return mpiRank() == 0; }
std::string rankPrefix() { return mpiRanks() > 1 ? "rank " + std::to_string(mpiRank()) + ": " : std::string(); }
}  // namespace ejecta::cli

namespace {
int runCommand(int argc, char** argv);
// The command failed on every MPI rank together (a collective found the failure: an agreed
// interrupt, a shared write failure), so no rank is left waiting for another.
bool failed_together = false;
}

int main(int argc, char** argv) {
#ifdef EJECTA_HAVE_MPI
  ejecta::cli::MpiSession mpi(argc, argv);
  ejecta::cli::session = &mpi;
  const int rc = runCommand(argc, argv);
  // A rank that failed alone would leave the others waiting in a collective: stop them all. Bad
  // input fails every rank alike and rank 0 alone says so: the others give it time to say it
  // before their abort kills it (under load a rank 1 that parsed first took rank 0 down unheard).
  // A failure the ranks agreed on ends every rank as a run that ended well (MPI_Finalize), with
  // its exit status and no abort: an interrupted run's ranks stop at one step, rank 0 keeps the
  // checkpoint and says so, and mpirun returns the status.
  if (rc != 0 && mpi.on && mpi.size > 1 && !failed_together) {
    if (mpi.rank != 0) std::this_thread::sleep_for(std::chrono::seconds(2));
    MPI_Abort(MPI_COMM_WORLD, rc);
  }
  return rc;
#else
  return runCommand(argc, argv);
#endif
}

namespace {

int runCommand(int argc, char** argv) {
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
  if (ejecta::cli::mpiRanks() > 1 && !app.got_subcommand("run")) {
    if (ejecta::cli::speaks()) std::cerr << "ejecta: error: ranks: only `ejecta run` runs on MPI ranks; start the others without mpirun\n";
    return 2;
  }
  try {
    for (auto& action : actions)
      if (int rc = action(); rc >= 0) return rc;
    return 2;
  } catch (const ejecta::InputError& e) {
    if (ejecta::cli::speaks()) std::cerr << "ejecta: error: " << e.what() << '\n';
    return 2;
  } catch (const ejecta::Interrupted& e) {
    if (ejecta::cli::speaks()) std::cerr << "ejecta: " << e.what() << '\n';
    failed_together = e.everyRank();
    return 128 + e.signal();
  } catch (const ejecta::RunError& e) {
    std::cerr << "ejecta: run stopped: " << ejecta::cli::rankPrefix() << e.what() << '\n';
    return 3;
  } catch (const std::filesystem::filesystem_error& e) {
    // an output path the user named that cannot be made or written (a file where a folder must be,
    // no permission): said in words, naming the path, as bad input
    std::cerr << "ejecta: error: " << e.path1().string() << ": " << e.code().message() << '\n';
    return 2;
  } catch (const ejecta::SharedFailure& e) {
    if (ejecta::cli::speaks()) std::cerr << "ejecta: failed: " << e.what() << '\n';
    failed_together = true;
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "ejecta: failed: " << ejecta::cli::rankPrefix() << e.what() << '\n';
    return 1;
  }
}
}  // namespace
