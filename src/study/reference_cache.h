// A reference computed once: what a reference served, kept on disk and served again by the next
// run that asks for the same one (#49). The reference of a barrier drape is most of a compare's
// simulation CPU (5.5 of the README clip's 8.2 s) and the same for every rerun of the scene.
//
// An entry is named by its key, a text the caller composes from everything the served numbers
// depend on: the Model's content (model_digest: the physics of the scene as built, after --set,
// not its YAML text, so a comment or a key's spelling does not miss and a changed value cannot
// hit), the reference's method and tolerances, the times asked, and the build (build_identity:
// another binary may round differently, and the payload is written in its memory layout). The
// key's text is stored in the entry and compared on read, so two keys whose digests collide
// never serve each other.
//
// Entries are written atomically (a hidden temporary renamed over the name: a reader sees a whole
// entry or none, and two writers of one key each rename a whole file) and checked on read: a header, the
// payload's length and a 64-bit FNV-1a checksum over it. A truncated, damaged or foreign entry
// is removed and recomputed, never trusted. The folder is bounded: after each write the least
// recently used entries (a hit touches its file) are removed until the total is within the cap.
//
// Where: $XDG_CACHE_HOME/clothsim, else ~/.cache/clothsim (the XDG base directory spec). The cap:
// CLOTHSIM_REFERENCE_CACHE_MAX (bytes, or with K, M or G), 1 GiB by default; 0 turns the cache
// off, as compare's --no-reference-cache does for one run.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/model/model.h"

namespace clothsim::analysis {

// 64-bit FNV-1a (Fowler, Noll, Vo), fed piece by piece: a checksum and a key's digest, not a
// defence against anyone forging an entry (the cache is the user's own folder).
class Digest {
 public:
  Digest& bytes(const void* data, std::size_t size);
  Digest& text(const std::string& s);  // its length, then its bytes (no two texts run together)
  Digest& number(double x);            // its bits: -0.0 and 0.0, or two NaNs, differ
  Digest& integer(std::int64_t n);
  std::uint64_t value() const { return h_; }
  std::string hex() const;  // 16 hex digits

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

// The digest of what a Model's motion depends on: bodies, masses, initial state, springs,
// spheres, ground, contact, gravity, drag, the timeline, the divergence bounds and the method
// settings a run reads from it (implicit, solvers, adaptive, methods). Not its name, source
// path, triangles (drawing only) or render settings.
std::string model_digest(const Model& model);

// The build serving a reference: the version, the SIMD target its kernels run on, and the file
// holding this code (the executable or the Python module) by path, size and modification time.
// A rebuilt binary misses.
std::string build_identity();

struct ReferenceCacheSettings {
  std::string dir;                          // "" : no cache
  std::uint64_t max_bytes = 1ull << 30;     // the folder's cap
};

// From the environment (above). Throws std::invalid_argument naming CLOTHSIM_REFERENCE_CACHE_MAX
// when its value is not a size.
ReferenceCacheSettings reference_cache_settings();
// "1G", "512M", "1048576": bytes. nullopt when not a size.
std::optional<std::uint64_t> parse_cache_size(const std::string& text);

class ReferenceCache {
 public:
  explicit ReferenceCache(ReferenceCacheSettings settings) : settings_(std::move(settings)) {}
  bool enabled() const { return !settings_.dir.empty() && settings_.max_bytes > 0; }
  const std::string& dir() const { return settings_.dir; }

  // The payload stored under `key`, whole and checked; nullopt when there is none, or when the
  // entry is damaged (then it is removed). A hit marks the entry used now (eviction order).
  std::optional<std::string> load(const std::string& key) const;
  // Stores `payload` under `key` (atomically; an entry larger than the cap is not kept) and
  // evicts the least recently used entries past the cap. False, with `why` set, when it could
  // not be written (a read-only or full disk): the run goes on without it.
  bool store(const std::string& key, const std::string& payload, std::string* why = nullptr) const;
  // The file an entry of `key` has.
  std::string path_of(const std::string& key) const;

  struct Contents {
    long entries = 0;
    std::uint64_t bytes = 0;
  };
  Contents contents() const;  // the entries now in the folder
  Contents clear() const;     // removes every entry (and a writer's leftover temporaries); what was removed

 private:
  void evict() const;
  ReferenceCacheSettings settings_;
};

}  // namespace clothsim::analysis
