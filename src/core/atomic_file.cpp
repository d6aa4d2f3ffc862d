#include <sstream>
#include "core/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <unistd.h>

#include "core/error.hpp"

namespace ejecta::io {

std::filesystem::path temporarySibling(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  auto name = fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), counter++);
  return path.parent_path() / name;
}

namespace {
// The write-then-rename that makes a file atomic would replace whatever the path is: a device
// node, a FIFO, a symbolic link. Those are refused (exit code 2), never replaced.
void requireRegularTarget(const std::filesystem::path& path) {
  std::error_code ec;
  const auto st = std::filesystem::symlink_status(path, ec);
  if (ec || st.type() == std::filesystem::file_type::not_found || st.type() == std::filesystem::file_type::regular) return;
  const char* what = st.type() == std::filesystem::file_type::symlink     ? "a symbolic link"
                     : st.type() == std::filesystem::file_type::directory ? "a directory"
                     : st.type() == std::filesystem::file_type::fifo      ? "a FIFO"
                                                                          : "a device or special file";
  throw InputError(path.string(), fmt::format("is {}; outputs are written to regular files only (give a new or regular file's path)", what));
}

// The messages name the file the user will look for, not its temporary sibling, and the system's
// reason where it left one (a full disk, a file size limit).
void writeTo(const std::filesystem::path& tmp, const std::filesystem::path& path, const std::function<void(std::ostream&)>& writer) {
  errno = 0;
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(fmt::format("cannot write {}{}", path.string(), errno ? ": " + std::string(std::strerror(errno)) : ""));
  writer(out);
  out.flush();
  if (!out) throw std::runtime_error(fmt::format("write failed for {}{}", path.string(), errno ? ": " + std::string(std::strerror(errno)) : ""));
}
}  // namespace

void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& writer) {
  requireRegularTarget(path);
  auto tmp = temporarySibling(path);
  try {
    writeTo(tmp, path, writer);
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

void writeFileAtomically(const std::filesystem::path& path, const std::string& content) {
  writeFileAtomically(path, [&](std::ostream& os) { os << content; });
}

OutputTransaction::~OutputTransaction() {
  if (!committed_) discard();
}

void OutputTransaction::discard() {
  for (auto& [tmp, final_path] : staged_) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
  }
  staged_.clear();
}

std::filesystem::path OutputTransaction::reserve(const std::filesystem::path& final_path) {
  requireRegularTarget(final_path);
  auto tmp = temporarySibling(final_path);
  staged_.emplace_back(tmp, final_path);
  return tmp;
}

std::filesystem::path OutputTransaction::stage(const std::filesystem::path& final_path,
                                               const std::function<void(std::ostream&)>& writer) {
  auto tmp = reserve(final_path);
  writeTo(tmp, final_path, writer);
  return tmp;
}

void OutputTransaction::commit() {
  for (auto& [tmp, final_path] : staged_) std::filesystem::rename(tmp, final_path);
  committed_ = true;
}

std::optional<std::string> readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace ejecta::io
