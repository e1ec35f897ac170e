#include "io/atomic_output.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "core/error.hpp"

namespace dualcell::io {

namespace fs = std::filesystem;

namespace {

std::string host_name() {
  char name[HOST_NAME_MAX + 1] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "host";
  std::string host(name);
  for (char& c : host)
    if (c == '/') c = '_';
  return host;
}

fs::path folder_of(const fs::path& target) {
  fs::path folder = target.parent_path();
  return folder.empty() ? fs::path(".") : folder;
}

[[noreturn]] void cannot_write(const fs::path& target, const std::string& what, int error) {
  throw InputError(target.string() + ": " + what + ": " + std::strerror(error));
}

// A temporary "<name>.tmp.<host>.<pid>" of a process on this host that no longer runs; or one
// "<name>.tmp.<pid>" as written before hosts were named, which names no host: only when its pid
// runs nowhere here and it is older than a day (no run of that version is still writing it).
bool orphaned(const fs::path& path, const std::string& name, const std::string& host) {
  const std::string entry = path.filename().string();
  const std::string prefix = name + ".tmp.";
  if (entry.rfind(prefix, 0) != 0) return false;
  std::string rest = entry.substr(prefix.size());
  const std::size_t dot = rest.rfind('.');
  const bool legacy = dot == std::string::npos;
  if (!legacy) {
    if (rest.substr(0, dot) != host) return false;
    rest = rest.substr(dot + 1);
  } else {
    std::error_code ec;
    const auto written = fs::last_write_time(path, ec);
    if (ec || fs::file_time_type::clock::now() - written < std::chrono::hours(24)) return false;
  }
  if (rest.empty() || rest.size() > 9 || rest.find_first_not_of("0123456789") != std::string::npos) return false;
  const pid_t pid = static_cast<pid_t>(std::stol(rest));
  return pid > 0 && pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

void remove_orphans(const fs::path& target) {
  const std::string name = target.filename().string(), host = host_name();
  std::error_code ec;
  for (fs::directory_iterator it(folder_of(target), ec), end; !ec && it != end; it.increment(ec)) {
    if (orphaned(it->path(), name, host)) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}

// After the renames: the outputs are in place either way, so a folder that cannot be synced (some
// file systems cannot, EINVAL) is not reported as a failed write; the data were synced before.
void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void check_output_path(const fs::path& target, const std::vector<fs::path>& inputs) {
  if (target.empty()) throw InputError("output path is empty: name the file to write");
  std::error_code ec;  // a name too long for the file system is a message, not an exception
  const fs::path folder = folder_of(target);
  if (!fs::is_directory(folder, ec))
    throw InputError(target.string() + ": cannot write output: folder " + folder.string() + " does not exist");
  struct stat out {};
  if (::stat(target.c_str(), &out) != 0) {
    if (errno == ENOENT) return;  // a new file: it cannot be an input
    cannot_write(target, "cannot write output", errno);
  }
  if (S_ISDIR(out.st_mode)) throw InputError(target.string() + ": cannot write output: it is a directory");
  if (!S_ISREG(out.st_mode))
    throw InputError(target.string() +
                     ": cannot write output: it exists and is not a regular file (a device, pipe or socket); name a "
                     "regular file");
  for (const fs::path& input : inputs) {
    struct stat in {};
    if (!input.empty() && ::stat(input.c_str(), &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino)
      throw InputError(target.string() + ": cannot write output: it is the input " + input.string() +
                       ", which writing would destroy; name another file");
  }
}

void check_outputs(const std::vector<fs::path>& outputs, const std::vector<fs::path>& inputs) {
  for (const fs::path& out : outputs) check_output_path(out, inputs);
  AtomicOutputs probe;  // creates each temporary (the real test of a writable folder), removes it
  for (const fs::path& out : outputs) probe.add(out);
}

fs::path xdmf_beside(const fs::path& h5) {
  fs::path xdmf = h5;
  xdmf.replace_extension(".xdmf");
  return xdmf;
}

void AtomicOutputs::add(const fs::path& target) {
  check_output_path(target);
  const auto same = [](const fs::path& a, const fs::path& b) {
    std::error_code ec;
    return fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal();
  };
  for (const Entry& e : files_)
    if (same(e.target, target))
      throw InputError(target.string() + ": cannot write output: the same file is written twice by this stage");
  remove_orphans(target);
  Entry e{target, target, false};
  e.temporary += ".tmp." + host_name() + "." + std::to_string(::getpid());
  const int fd = ::open(e.temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) cannot_write(target, "cannot write output", errno);
  ::close(fd);
  files_.push_back(std::move(e));
}

AtomicOutputs::Entry& AtomicOutputs::entry(const fs::path& target) {
  for (Entry& e : files_)
    if (e.target == target) return e;
  throw std::logic_error("AtomicOutputs: " + target.string() + " was not registered");
}

namespace {

// Every byte to fd, or 0; otherwise the errno of the failure (the descriptor stays open).
int write_all(int fd, std::string_view bytes) {
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : EIO;
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return 0;
}

// fsync (a pipe or a special file cannot: EINVAL is no failure) and close; 0 or the errno.
int sync_and_close(int fd) {
  if (::fsync(fd) != 0 && errno != EINVAL) {
    const int error = errno;
    ::close(fd);
    return error;
  }
  return ::close(fd) != 0 ? errno : 0;
}

}  // namespace

void AtomicOutputs::write(const fs::path& target, std::string_view bytes) {
  Entry& e = entry(target);
  const int fd = ::open(e.temporary.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) cannot_write(target, "cannot write", errno);
  if (const int error = write_all(fd, bytes)) {
    ::close(fd);
    cannot_write(target, "cannot write", error);
  }
  if (const int error = sync_and_close(fd)) cannot_write(target, "cannot write", error);
  e.written = true;
}

void AtomicOutputs::append(const fs::path& target, std::string_view bytes) {
  Entry& e = entry(target);
  if (e.appending < 0) {
    e.appending = ::open(e.temporary.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (e.appending < 0) cannot_write(target, "cannot write", errno);
  }
  if (const int error = write_all(e.appending, bytes)) cannot_write(target, "cannot write", error);
}

void AtomicOutputs::commit() {
  for (Entry& e : files_) {
    if (e.appending >= 0) {
      const int fd = std::exchange(e.appending, -1);
      if (const int error = sync_and_close(fd)) cannot_write(e.target, "cannot write", error);
      e.written = true;
    }
    if (!e.written) throw std::logic_error("AtomicOutputs: " + e.target.string() + " committed without being written");
  }
  std::vector<fs::path> folders;
  for (const Entry& e : files_) {
    std::error_code ec;
    fs::rename(e.temporary, e.target, ec);
    if (ec) throw InputError(e.target.string() + ": cannot move finished output into place: " + ec.message());
    const fs::path folder = folder_of(e.target);
    if (std::find(folders.begin(), folders.end(), folder) == folders.end()) folders.push_back(folder);
  }
  committed_ = true;
  for (const fs::path& folder : folders) sync_folder(folder);
}

AtomicOutputs::~AtomicOutputs() {
  for (const Entry& e : files_)
    if (e.appending >= 0) ::close(e.appending);
  if (committed_) return;
  for (const Entry& e : files_) {
    std::error_code ec;
    fs::remove(e.temporary, ec);
  }
}

void write_output(const fs::path& target, std::string_view bytes) {
  AtomicOutputs outputs;
  outputs.add(target);
  outputs.write(target, bytes);
  outputs.commit();
}

}  // namespace dualcell::io
