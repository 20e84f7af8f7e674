#include "journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
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

// DIR/FOLDER's item files, by item.
std::map<std::size_t, std::string> read_folder(const std::string& dir, const char* folder) {
  std::map<std::size_t, std::string> items;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(fs::path(dir) / folder, ec)) {
    std::size_t item = 0;
    if (item_number(e.path().filename().string(), item)) items[item] = read_whole_file(e.path().string());
  }
  if (ec) throw std::runtime_error(dir + ": cannot read the journal: " + ec.message());
  return items;
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& text) {
  const fs::path target(path);
  const std::string tmp = (target.parent_path() / ("." + target.filename().string() + ".tmp-" +
                                                   std::to_string(::getpid()) + "-" +
                                                   std::to_string(std::hash<std::string>{}(text) & 0xffffff)))
                              .string();
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw io_error(tmp, "cannot create");
  try {
    write_all(fd, text, tmp);
    if (::fsync(fd) != 0) throw io_error(tmp, "cannot sync");  // the rename must not outrun the bytes
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
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
  items_ = read_items(dir_);
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
  if (!lane.empty()) write_file_atomically((fs::path(dir_) / "lanes" / std::to_string(item)).string(), lane);
  write_file_atomically((fs::path(dir_) / "items" / std::to_string(item)).string(), payload);
  items_[item] = payload;
  const std::string log = (fs::path(dir_) / "log").string();
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw io_error(log, "cannot open");
  const std::string line = std::to_string(item) + "\n";
  const ssize_t n = ::write(fd, line.data(), line.size());  // one short append: whole or absent
  ::close(fd);
  if (n != static_cast<ssize_t>(line.size())) throw io_error(log, "cannot append");
}

std::map<std::size_t, std::string> Journal::read_items(const std::string& dir) { return read_folder(dir, "items"); }

std::map<std::size_t, std::string> Journal::read_lanes(const std::string& dir) { return read_folder(dir, "lanes"); }

}  // namespace clothsim::analysis
