#include "journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <optional>
#include <vector>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace clothsim::analysis {
namespace {

namespace fs = std::filesystem;

std::runtime_error io_error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what + ": " + std::strerror(errno));
}

void write_all(int fd, const std::string& text, const std::string& path) {
  for (std::size_t at = 0; at < text.size();) {
    const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw io_error(path, "cannot write");
    }
    at += static_cast<std::size_t>(n);
  }
}

// An item file's name is its number, nothing else (temporaries start with '.').
bool item_number(const std::string& name, std::size_t& item) {
  if (name.empty() || name.size() > 12 || name.find_first_not_of("0123456789") != std::string::npos) return false;
  item = std::stoul(name);
  return true;
}

// An item or lane file ends with a mark giving its payload's length, so a file cut short (a
// full disk under a copy, a damaged transfer) is told from a whole one even when the cut falls
// between two rows.
constexpr const char* kEndMark = "\n#clothsim journal entry, bytes: ";

std::string with_end_mark(const std::string& payload) {
  return payload + kEndMark + std::to_string(payload.size()) + "\n";
}

// The payload of a marked file; nullopt when the mark is missing or does not match.
std::optional<std::string> without_end_mark(const std::string& text) {
  const std::size_t at = text.rfind(kEndMark);
  if (at == std::string::npos) return std::nullopt;
  const std::string tail = text.substr(at + std::strlen(kEndMark));
  if (tail.size() < 2 || tail.back() != '\n' || tail.find_first_not_of("0123456789\n") != std::string::npos ||
      tail.find('\n') != tail.size() - 1 || tail.size() > 13)
    return std::nullopt;
  if (std::stoull(tail) != at) return std::nullopt;
  return text.substr(0, at);
}

// DIR/FOLDER's item files, by item. `damaged` (the rerun's reading): a damaged file is removed,
// so its item runs again; without it (merge's), a damaged file is an error naming it.
std::map<std::size_t, std::string> read_folder(const std::string& dir, const char* folder, bool remove_damaged) {
  std::map<std::size_t, std::string> items;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(fs::path(dir) / folder, ec)) {
    std::size_t item = 0;
    if (!item_number(e.path().filename().string(), item)) continue;
    const std::optional<std::string> payload = without_end_mark(read_whole_file(e.path().string()));
    if (payload) {
      items[item] = *payload;
    } else if (remove_damaged) {
      fs::remove(e.path(), ec);
    } else {
      throw std::runtime_error(e.path().string() + ": damaged (cut short or altered: its end mark is missing or "
                               "wrong); remove it and rerun the shard to redo the item");
    }
  }
  if (ec) throw std::runtime_error(dir + ": cannot read the journal: " + ec.message());
  return items;
}

// "." NAME ".tmp-" PID "-" R: write_file_atomically's named temporary.
std::optional<pid_t> temporary_owner(const std::string& name) {
  const std::size_t at = name.rfind(".tmp-");
  if (name.empty() || name.front() != '.' || at == std::string::npos) return std::nullopt;
  const std::string rest = name.substr(at + 5);
  const std::size_t dash = rest.find('-');
  if (dash == 0 || dash == std::string::npos || rest.substr(0, dash).find_first_not_of("0123456789") != std::string::npos)
    return std::nullopt;
  return static_cast<pid_t>(std::stol(rest.substr(0, dash)));
}

// Removes the named temporaries a killed writer left in DIR (SIGKILL between naming the file
// and renaming it): those of processes that no longer exist on this machine.
void remove_stale_temporaries(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::optional<pid_t> owner = temporary_owner(e.path().filename().string());
    if (owner && (*owner == ::getpid() || (::kill(*owner, 0) != 0 && errno == ESRCH))) stale.push_back(e.path());
  }
  for (const fs::path& p : stale) fs::remove(p, ec);
}

// A file with no name yet in DIR (O_TMPFILE), or -1 where the file system has none.
int nameless_file_in(const fs::path& dir) {
#ifdef O_TMPFILE
  return ::open(dir.empty() ? "." : dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
#else
  (void)dir;
  return -1;
#endif
}

}  // namespace

// The bytes are written and synced into a nameless file (O_TMPFILE): a process killed then
// leaves nothing. Only then is it named, under a hidden temporary name renamed over PATH
// (microseconds; a rerun's Journal removes what a kill in between leaves). File systems without
// O_TMPFILE write the named temporary from the start.
void write_file_atomically(const std::string& path, const std::string& text) {
  const fs::path target(path);
  const std::string tmp = (target.parent_path() / ("." + target.filename().string() + ".tmp-" +
                                                   std::to_string(::getpid()) + "-" +
                                                   std::to_string(std::hash<std::string>{}(text) & 0xffffff)))
                              .string();
  int fd = nameless_file_in(target.parent_path());
  const bool nameless = fd >= 0;
  if (!nameless) fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw io_error(tmp, "cannot create");
  try {
    write_all(fd, text, tmp);
    if (::fsync(fd) != 0) throw io_error(tmp, "cannot sync");  // the rename must not outrun the bytes
    if (nameless) {
      const std::string self = "/proc/self/fd/" + std::to_string(fd);
      if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, tmp.c_str(), AT_SYMLINK_FOLLOW) != 0)
        throw io_error(tmp, "cannot name");
    }
  } catch (...) {
    ::close(fd);
    if (!nameless) ::unlink(tmp.c_str());
    throw;
  }
  ::close(fd);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::runtime_error e = io_error(path, "cannot rename into place");
    ::unlink(tmp.c_str());
    throw e;
  }
}

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error(path, "cannot read");
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

Journal::Journal(std::string dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(fs::path(dir_) / "items", ec);
  if (!ec) fs::create_directories(fs::path(dir_) / "lanes", ec);
  if (ec) throw std::runtime_error(dir_ + ": cannot create the journal: " + ec.message());
  for (const char* folder : {"", "items", "lanes"}) remove_stale_temporaries(fs::path(dir_) / folder);
  items_ = read_folder(dir_, "items", /*remove_damaged=*/true);
}

bool Journal::done(std::size_t item) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return items_.count(item) > 0;
}

std::size_t Journal::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return items_.size();
}

void Journal::record(std::size_t item, const std::string& payload, const std::string& lane) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!lane.empty())
    write_file_atomically((fs::path(dir_) / "lanes" / std::to_string(item)).string(), with_end_mark(lane));
  write_file_atomically((fs::path(dir_) / "items" / std::to_string(item)).string(), with_end_mark(payload));
  items_[item] = payload;
  const std::string log = (fs::path(dir_) / "log").string();
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw io_error(log, "cannot open");
  const std::string line = std::to_string(item) + "\n";
  const ssize_t n = ::write(fd, line.data(), line.size());  // one short append: whole or absent
  ::close(fd);
  if (n != static_cast<ssize_t>(line.size())) throw io_error(log, "cannot append");
}

std::map<std::size_t, std::string> Journal::read_items(const std::string& dir) {
  return read_folder(dir, "items", false);
}

std::map<std::size_t, std::string> Journal::read_lanes(const std::string& dir) {
  return read_folder(dir, "lanes", false);
}

}  // namespace clothsim::analysis
