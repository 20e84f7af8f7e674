#include "reference_cache.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "core/springs/spring_kernels.h"
#include "io/output_file.h"

namespace clothsim::analysis {

namespace fs = std::filesystem;

Digest& Digest::bytes(const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h_ = (h_ ^ p[i]) * 1099511628211ull;
  return *this;
}

Digest& Digest::text(const std::string& s) {
  integer(static_cast<std::int64_t>(s.size()));
  return bytes(s.data(), s.size());
}

Digest& Digest::number(double x) { return bytes(&x, sizeof x); }
Digest& Digest::integer(std::int64_t n) { return bytes(&n, sizeof n); }

std::string Digest::hex() const {
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h_));
  return out;
}

namespace {

template <typename Array>
void numbers(Digest& d, const Array& a) {
  d.integer(static_cast<std::int64_t>(a.size()));
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(a.size()); ++i) d.number(a.data()[i]);
}

template <typename T>
void pods(Digest& d, const std::vector<T>& v) {
  d.integer(static_cast<std::int64_t>(v.size()));
  for (const T& x : v) d.integer(static_cast<std::int64_t>(x));
}

constexpr char kMagic[] = "clothsim reference cache 1\n";
constexpr const char* kSuffix = ".ref";

bool read_u64(std::istream& in, std::uint64_t& v) { return static_cast<bool>(in.read(reinterpret_cast<char*>(&v), sizeof v)); }

}  // namespace

// What the motion depends on (reference_cache.h). The method settings (implicit, solvers,
// adaptive, methods) are not in it: only references of methods that read none are cached
// (clip/frames/reference_record.h says which).
std::string model_digest(const Model& m) {
  Digest d;
  d.integer(m.num_particles).integer(m.num_spheres).integer(m.grid_nx).integer(m.grid_ny);
  numbers(d, m.mass);
  numbers(d, m.initial_inv_mass);
  pods(d, m.gravity_on);
  numbers(d, m.initial_x);
  numbers(d, m.initial_v);
  pods(d, m.springs.a);
  pods(d, m.springs.b);
  numbers(d, m.springs.rest);
  numbers(d, m.springs.ks);
  numbers(d, m.springs.kd);
  d.integer(static_cast<std::int64_t>(m.springs.type.size()));
  for (SpringType t : m.springs.type) d.integer(static_cast<std::int64_t>(t));
  numbers(d, m.sphere_radius);
  numbers(d, m.sphere_restitution);
  numbers(d, m.sphere_friction);
  pods(d, m.sphere_kinematic);
  d.integer(m.has_ground).number(m.ground.height).number(m.ground.restitution).number(m.ground.friction);
  const CollisionDef& c = m.collision;
  d.integer(static_cast<std::int64_t>(c.model)).number(c.margin).integer(c.sphere_sphere).number(c.sphere_restitution);
  d.number(c.barrier_distance).number(c.barrier_stiffness).number(c.friction_velocity);
  d.number(m.gravity.x()).number(m.gravity.y()).number(m.gravity.z()).number(m.air_drag);
  d.integer(static_cast<std::int64_t>(m.timeline.size()));
  for (const TimedAction& a : m.timeline)
    d.integer(static_cast<std::int64_t>(a.kind)).number(a.t).integer(a.body)
        .number(a.velocity.x()).number(a.velocity.y()).number(a.velocity.z());
  d.number(m.divergence.max_strain).number(m.divergence.max_energy_factor).number(m.energy_scale);
  return d.hex();
}

std::string build_identity() {
  // The SIMD target the kernels dispatch to as well: one binary rounds differently on another
  // CPU (a home folder shared across machines).
  std::string id = std::string("clothsim " CLOTHSIM_VERSION " simd ") + spring_kernel_target();
  Dl_info info{};
  struct stat st{};
  if (::dladdr(reinterpret_cast<void*>(&build_identity), &info) && info.dli_fname &&
      ::stat(info.dli_fname, &st) == 0) {
    id += std::string(" ") + info.dli_fname + " " + std::to_string(st.st_size) + " " +
          std::to_string(st.st_mtim.tv_sec) + "." + std::to_string(st.st_mtim.tv_nsec);
  } else {
    id += " " __DATE__ " " __TIME__;  // (no file to name: the compile time at least)
  }
  return id;
}

std::optional<std::uint64_t> parse_cache_size(const std::string& text) {
  if (text.empty()) return std::nullopt;
  std::size_t used = 0;
  unsigned long long n = 0;
  try {
    if (text[0] == '-' || text[0] == '+') return std::nullopt;
    n = std::stoull(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  std::uint64_t scale = 1;
  if (used + 1 == text.size()) {
    switch (text[used]) {
      case 'K': case 'k': scale = 1ull << 10; break;
      case 'M': case 'm': scale = 1ull << 20; break;
      case 'G': case 'g': scale = 1ull << 30; break;
      default: return std::nullopt;
    }
  } else if (used != text.size()) {
    return std::nullopt;
  }
  return static_cast<std::uint64_t>(n) * scale;
}

ReferenceCacheSettings reference_cache_settings() {
  ReferenceCacheSettings s;
  if (const char* max = std::getenv("CLOTHSIM_REFERENCE_CACHE_MAX")) {
    const auto bytes = parse_cache_size(max);
    if (!bytes)
      throw std::invalid_argument(std::string("CLOTHSIM_REFERENCE_CACHE_MAX: '") + max +
                                  "' is not a size (bytes, or a number with K, M or G; 0 turns the cache off)");
    s.max_bytes = *bytes;
  }
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  if (xdg && *xdg == '/') s.dir = (fs::path(xdg) / "clothsim").string();  // (a relative one is ignored, per the spec)
  else if (home && *home) s.dir = (fs::path(home) / ".cache" / "clothsim").string();
  return s;
}

std::string ReferenceCache::path_of(const std::string& key) const {
  return (fs::path(settings_.dir) / (Digest().text(key).hex() + kSuffix)).string();
}

std::optional<std::string> ReferenceCache::load(const std::string& key) const {
  if (!enabled()) return std::nullopt;
  const std::string path = path_of(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  const auto damaged = [&]() -> std::optional<std::string> {
    in.close();
    std::error_code ignored;
    fs::remove(path, ignored);  // recomputed and stored again by this run
    return std::nullopt;
  };
  char magic[sizeof kMagic - 1];
  std::uint64_t key_size = 0, size = 0, checksum = 0;
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0) return damaged();
  if (!read_u64(in, key_size) || key_size != key.size()) return damaged();
  std::string stored_key(key_size, '\0');
  if (!in.read(stored_key.data(), static_cast<std::streamsize>(key_size)) || stored_key != key) return damaged();
  if (!read_u64(in, size) || !read_u64(in, checksum) || size > settings_.max_bytes) return damaged();
  std::string payload(size, '\0');
  if (!in.read(payload.data(), static_cast<std::streamsize>(size)) || in.peek() != std::char_traits<char>::eof())
    return damaged();  // short, or longer than it says
  if (Digest().bytes(payload.data(), payload.size()).value() != checksum) return damaged();
  ::utimensat(AT_FDCWD, path.c_str(), nullptr, 0);  // used now: the last to be evicted
  return payload;
}

bool ReferenceCache::store(const std::string& key, const std::string& payload, std::string* why) const {
  if (!enabled()) return false;
  const std::uint64_t header = sizeof kMagic - 1 + 3 * sizeof(std::uint64_t) + key.size();
  if (header + payload.size() > settings_.max_bytes) {
    if (why) *why = "larger than the cache's cap";
    return false;
  }
  // Written beside its name and renamed over it (a reader sees the old entry, the new one or
  // none; two writers of one key each rename a whole file). Not an OutputFile: -n/--no-overwrite
  // and the count of outputs a signal's message reports are the user's files', not the cache's.
  std::string temp;
  try {
    fs::create_directories(settings_.dir);
    temp = hidden_temp_name(path_of(key));
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot write " + temp + ": " + std::strerror(errno));
    const std::uint64_t key_size = key.size(), size = payload.size(),
                        checksum = Digest().bytes(payload.data(), payload.size()).value();
    const bool ok = write_all(fd, kMagic, sizeof kMagic - 1) && write_all(fd, &key_size, sizeof key_size) &&
                    write_all(fd, key.data(), key.size()) && write_all(fd, &size, sizeof size) &&
                    write_all(fd, &checksum, sizeof checksum) && write_all(fd, payload.data(), payload.size());
    const int error = errno;
    if (::close(fd) != 0 || !ok) throw std::runtime_error("cannot write " + temp + ": " + std::strerror(ok ? errno : error));
    if (std::rename(temp.c_str(), path_of(key).c_str()) != 0)
      throw std::runtime_error("cannot write " + path_of(key) + ": " + std::strerror(errno));
  } catch (const std::exception& e) {  // (a full or read-only disk): the run goes on without it
    if (!temp.empty()) ::unlink(temp.c_str());
    if (why) *why = e.what();
    return false;
  }
  evict();
  return true;
}

namespace {
struct Entry {
  fs::path path;
  std::uint64_t bytes;
  fs::file_time_type used;
};
std::vector<Entry> entries(const std::string& dir) {
  std::vector<Entry> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e;
    const std::string name = it->path().filename().string();
    if (it->path().extension() != kSuffix || name[0] == '.' || !it->is_regular_file(e)) continue;  // (a writer's temporary)
    const auto bytes = it->file_size(e);
    const auto used = it->last_write_time(e);
    if (!e) out.push_back({it->path(), bytes, used});
  }
  return out;
}
}  // namespace

// Oldest use first, until the rest fits. Another process evicting at once may remove the same
// file: harmless (remove() of a missing name is not an error here).
void ReferenceCache::evict() const {
  std::vector<Entry> all = entries(settings_.dir);
  std::uint64_t total = 0;
  for (const Entry& e : all) total += e.bytes;
  std::sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const Entry& e : all) {
    if (total <= settings_.max_bytes) break;
    std::error_code ignored;
    fs::remove(e.path, ignored);
    total -= e.bytes;
  }
}

ReferenceCache::Contents ReferenceCache::contents() const {
  Contents c;
  for (const Entry& e : entries(settings_.dir)) {
    ++c.entries;
    c.bytes += e.bytes;
  }
  return c;
}

ReferenceCache::Contents ReferenceCache::clear() const {
  Contents removed;
  std::vector<fs::path> names;
  std::error_code ec;
  for (fs::directory_iterator it(settings_.dir, ec), end; !ec && it != end; it.increment(ec)) names.push_back(it->path());
  for (const fs::path& p : names) {
    const std::string name = p.filename().string();
    const bool entry = p.extension() == kSuffix;
    const bool leftover = name.rfind(".", 0) == 0 && name.find(".partial-") != std::string::npos;  // a killed writer's
    if (!entry && !leftover) continue;  // (not ours: left alone)
    std::error_code e;
    const auto bytes = fs::is_regular_file(p, e) ? fs::file_size(p, e) : 0;
    if (fs::remove(p, e) && entry) {
      ++removed.entries;
      removed.bytes += bytes;
    }
  }
  return removed;
}

}  // namespace clothsim::analysis
