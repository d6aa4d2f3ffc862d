#pragma once
#include <stdexcept>
#include <string>

namespace ejecta {

// Bad user input: names the offending field and, where it has one, its valid range.
// Front ends turn it into a one-line message and exit code 2.
class InputError : public std::runtime_error {
 public:
  InputError(std::string field, const std::string& message)
      : std::runtime_error(field + ": " + message), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// A run that cannot go on (NaN, negative density, collapsing time step). Front ends exit 3.
class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A failure that every MPI rank met together (a collective found it) and stops with: the front end
// says it once, from rank 0, and exits 1 as for any other failure.
class SharedFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A run stopped by a signal (SIGINT, SIGTERM, SIGHUP): the front end exits 128 + the signal, as
// the shell would for a process the signal killed. `every_rank`: every MPI rank stops with it at
// the same step (they agreed on it in a collective), so none waits for another and the ranks end
// as a run that ended well does, without an abort.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& message, bool every_rank = false)
      : std::runtime_error(message), signal_(signal), every_rank_(every_rank) {}
  int signal() const { return signal_; }
  bool everyRank() const { return every_rank_; }

 private:
  int signal_;
  bool every_rank_;
};

}  // namespace ejecta
