// ejecta: buried-charge loading of vehicle underbodies. One program, several sub-commands.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
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
  // A communicator of its own for the ranks' last agreement (agreeOnExit): a rank still inside a
  // collective of the run's communicator never meets it there, and nothing of the run can match it.
  MPI_Comm ending = MPI_COMM_NULL;
  MpiSession(int& argc, char**& argv) {
    if (!launchedByMpi()) return;
    MPI_Init(&argc, &argv);
    on = true;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_dup(MPI_COMM_WORLD, &ending);
  }
  ~MpiSession() {
    if (!on) return;
    MPI_Comm_free(&ending);
    MPI_Finalize();
  }
  // Every rank's last collective: the largest exit status of all, once every rank has come here,
  // or nothing if `seconds` (> 0) pass first. A rank that ended well waits without a limit (rank 0
  // may still be writing the outputs); a failed one waits `seconds`: bad input is met by every rank
  // alike, each after its own parse, while a rank that failed alone finds the others missing (they
  // wait in the run's collectives) and the caller ends them all.
  std::optional<int> agreeOnExit(int rc, double seconds) {
    int all = rc;
    MPI_Request req = MPI_REQUEST_NULL;
    MPI_Iallreduce(&rc, &all, 1, MPI_INT, MPI_MAX, ending, &req);
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
      int done = 0;
      MPI_Test(&req, &done, MPI_STATUS_IGNORE);
      if (done) return all;
      if (seconds > 0.0 && std::chrono::steady_clock::now() >= until) return std::nullopt;   // (the request dies with the abort)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
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
// What a rank other than 0 left unsaid, trusting rank 0 to say the same (bad input).
std::string unsaid;
// Bad input, which every rank meets alike: rank 0 says it; another rank keeps it, with its rank, to
// say if it turns out to have met it alone.
void sayOnce(const std::string& what) {
  if (ejecta::cli::speaks())
    std::cerr << "ejecta: error: " << what << '\n';
  else
    unsaid = "ejecta: error: " + ejecta::cli::rankPrefix() + what;
}
#ifdef EJECTA_HAVE_MPI
// How long a failed rank waits for the others to come to the end too before it ends them
// (agreeOnExit): long enough for a slow rank's parse under load, short beside a batch job's time.
constexpr double kAgreeSeconds = 10.0;
#endif
}

int main(int argc, char** argv) {
#ifdef EJECTA_HAVE_MPI
  ejecta::cli::MpiSession mpi(argc, argv);
  ejecta::cli::session = &mpi;
  const int rc = runCommand(argc, argv);
  if (!mpi.on || mpi.size == 1) return rc;
  // Every rank ends as a run that ended well (MPI_Finalize, no abort, so that rank 0 has said what
  // failed and cleaned up), with the largest status of all, once every rank has come to the end:
  // after a failure the ranks agreed on in the run (an interrupt at one step, a write that failed),
  // or one that each met on its own (bad input, found by every rank's parse; a signal to every
  // rank, also while rank 0 writes the outputs and the others wait here). A rank that failed alone
  // would leave the others waiting in a collective: after the wait it stops them all.
  const auto agreed = mpi.agreeOnExit(rc, rc == 0 || failed_together ? 0.0 : kAgreeSeconds);
  if (!agreed) {
    if (!unsaid.empty()) std::cerr << unsaid << '\n';
    // said by ejecta itself: Open MPI's own notice of the abort is sometimes lost on the way out
    std::cerr << "ejecta: " << ejecta::cli::rankPrefix() << "the other ranks did not come to the end within " << kAgreeSeconds
              << " s: ending every rank (MPI_Abort)\n";
    MPI_Abort(MPI_COMM_WORLD, rc);
  }
  return *agreed;
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
      sayOnce(opt + ": an empty value is not allowed (see ejecta --help)");
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    sayOnce(std::string(e.what()) + " (see ejecta --help)");
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
    sayOnce(e.what());
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
