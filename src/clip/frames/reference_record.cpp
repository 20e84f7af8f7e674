#include "reference_record.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <sstream>

#include "core/integrators/integrator_kind.h"
#include "study/reference.h"
#include "study/reference_cache.h"

namespace clothsim::clip {

namespace {

// Native bytes: a record is read only by the build that wrote it (the key names the build).
template <typename T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
void put_text(std::string& out, const std::string& s) {
  put(out, static_cast<std::uint64_t>(s.size()));
  out += s;
}

class Reader {
 public:
  explicit Reader(const std::string& in) : in_(in) {}
  template <typename T>
  bool get(T& v) {
    if (in_.size() - at_ < sizeof v) return false;
    std::memcpy(&v, in_.data() + at_, sizeof v);
    at_ += sizeof v;
    return true;
  }
  bool get_text(std::string& s) {
    std::uint64_t n = 0;
    if (!get(n) || in_.size() - at_ < n) return false;
    s.assign(in_, at_, n);
    at_ += n;
    return true;
  }
  bool get_doubles(std::vector<double>& v) {
    std::uint64_t n = 0;
    if (!get(n) || (in_.size() - at_) / sizeof(double) < n) return false;
    v.resize(n);
    std::memcpy(v.data(), in_.data() + at_, n * sizeof(double));
    at_ += n * sizeof(double);
    return true;
  }
  bool done() const { return at_ == in_.size(); }

 private:
  const std::string& in_;
  std::size_t at_ = 0;
};

// The totals a reference's frames and result carry (a fixed-step explicit run or the adaptive
// solve: no Newton, solver or contact work).
void put_totals(std::string& out, const RunTotals& t) {
  put(out, t.steps), put(out, t.force_evals), put(out, t.projected_steps), put(out, t.rejected_steps);
  put(out, t.max_strain), put(out, t.last_step), put(out, t.smallest_step), put(out, t.largest_step);
  put(out, t.sim_seconds), put(out, t.cpu_seconds);
}
bool get_totals(Reader& in, RunTotals& t) {
  return in.get(t.steps) && in.get(t.force_evals) && in.get(t.projected_steps) && in.get(t.rejected_steps) &&
         in.get(t.max_strain) && in.get(t.last_step) && in.get(t.smallest_step) && in.get(t.largest_step) &&
         in.get(t.sim_seconds) && in.get(t.cpu_seconds);
}

void put_divergence(std::string& out, const std::optional<Divergence>& d) {
  put(out, static_cast<std::uint8_t>(d.has_value()));
  if (!d) return;
  put(out, d->step), put(out, d->t);
  put_text(out, d->reason);
}
bool get_divergence(Reader& in, std::optional<Divergence>& d) {
  std::uint8_t has = 0;
  if (!in.get(has)) return false;
  if (!has) return true;
  d.emplace();
  return in.get(d->step) && in.get(d->t) && in.get_text(d->reason);
}

// Whether a reference of this method reads nothing of the model but its physics.
bool cacheable(const Lane& spec, double adaptive_tolerance) {
  if (adaptive_tolerance > 0.0) return true;  // the dopri5 solve of accelerations() alone
  const IntegratorInfo& info = integrator_info(spec.kind);
  return info.iterations == IterationControl::None && !info.adaptive && !spec.fixed_point && spec.params.empty();
}

}  // namespace

std::optional<std::string> reference_cache_key(const Model& model, const Lane& spec, double adaptive_tolerance,
                                               const std::vector<double>& lane_steps, const std::vector<bool>& serves,
                                               double energy_every, const TargetPlan& targets) {
  if (!cacheable(spec, adaptive_tolerance)) return std::nullopt;
  std::ostringstream key;
  key.precision(17);
  key << "model " << analysis::model_digest(model) << "\n";
  key << "reference " << spec.spelling() << " dt " << spec.dt;
  if (adaptive_tolerance > 0.0)
    key << " dopri5 tolerance " << adaptive_tolerance << " check " << adaptive_tolerance / analysis::kCheckTightening
        << " factor " << analysis::kEstimateFactor;
  key << "\nlanes";
  for (double h : lane_steps) key << " " << h;
  key << "\nserves";
  for (bool s : serves) key << " " << s;
  key << "\nenergy " << energy_every << "\n";
  analysis::Digest times;  // every target's time, hashed (a long clip has many)
  TargetPlan::Cursor cursor(targets);
  long count = 0;
  for (Target t; cursor.next(t); ++count) times.number(t.t);
  key << "targets " << count << " " << times.hex() << "\n";
  key << "build " << analysis::build_identity() << "\n";
  return key.str();
}

void ReferenceRecorder::add(const LaneFrame& f) {
  if (overflowed_) return;
  put(body_, f.t), put(body_, f.step), put(body_, f.shown_t);
  put_totals(body_, f.totals);
  put(body_, static_cast<std::uint64_t>(f.energy.size()));
  for (const auto& [t, e] : f.energy) put(body_, t), put(body_, e);
  put_divergence(body_, f.divergence);
  put(body_, static_cast<std::uint8_t>(f.frozen));
  put(body_, f.reference_error);
  // Positions per lane, each distinct copy once (lanes of one step share theirs): an index per
  // lane (-1: none), then the copies.
  std::vector<const std::vector<double>*> distinct;
  put(body_, static_cast<std::uint64_t>(f.x_for.size()));
  for (const auto& x : f.x_for) {
    std::int64_t index = -1;
    if (x) {
      const auto at = std::find(distinct.begin(), distinct.end(), x.get());
      index = at - distinct.begin();
      if (at == distinct.end()) distinct.push_back(x.get());
    }
    put(body_, index);
  }
  for (const std::vector<double>* x : distinct) {
    put(body_, static_cast<std::uint64_t>(x->size()));
    body_.append(reinterpret_cast<const char*>(x->data()), x->size() * sizeof(double));
  }
  ++frames_;
  if (body_.size() > limit_) {
    overflowed_ = true;
    std::string().swap(body_);
  }
}

std::string ReferenceRecorder::finish(const LaneResult& r) {
  if (overflowed_) return {};
  std::string out;
  put(out, static_cast<std::uint64_t>(frames_));
  out += body_;
  put(out, r.t);
  put_totals(out, r.totals);
  put_divergence(out, r.divergence);
  put(out, r.adaptive_tolerance), put(out, r.check_tolerance), put(out, r.check_dt), put(out, r.estimated_error);
  return out;
}

std::optional<ReferenceRecord> decode_reference_record(const std::string& payload) {
  Reader in(payload);
  ReferenceRecord rec;
  std::uint64_t frames = 0;
  if (!in.get(frames)) return std::nullopt;
  for (std::uint64_t k = 0; k < frames; ++k) {
    LaneFrame f;
    std::uint64_t samples = 0, lanes = 0;
    std::uint8_t frozen = 0;
    if (!in.get(f.t) || !in.get(f.step) || !in.get(f.shown_t) || !get_totals(in, f.totals) || !in.get(samples))
      return std::nullopt;
    for (std::uint64_t i = 0; i < samples; ++i) {
      double t = 0.0, e = 0.0;
      if (!in.get(t) || !in.get(e)) return std::nullopt;
      f.energy.emplace_back(t, e);
    }
    if (!get_divergence(in, f.divergence) || !in.get(frozen) || !in.get(f.reference_error) || !in.get(lanes))
      return std::nullopt;
    f.frozen = frozen != 0;
    std::vector<std::int64_t> index(lanes);
    std::int64_t copies = 0;
    for (std::int64_t& i : index) {
      if (!in.get(i) || i < -1 || i > copies) return std::nullopt;
      copies = std::max(copies, i + 1);
    }
    std::vector<std::shared_ptr<const std::vector<double>>> distinct;
    for (std::int64_t c = 0; c < copies; ++c) {
      auto x = std::make_shared<std::vector<double>>();
      if (!in.get_doubles(*x)) return std::nullopt;
      distinct.push_back(std::move(x));
    }
    for (std::int64_t i : index) f.x_for.push_back(i < 0 ? nullptr : distinct[static_cast<std::size_t>(i)]);
    rec.frames.push_back(std::move(f));
  }
  LaneResult& r = rec.result;
  if (!in.get(r.t) || !get_totals(in, r.totals) || !get_divergence(in, r.divergence) || !in.get(r.adaptive_tolerance) ||
      !in.get(r.check_tolerance) || !in.get(r.check_dt) || !in.get(r.estimated_error) || !in.done())
    return std::nullopt;
  return rec;
}

double reference_record_bytes(int particles, const std::vector<double>& lane_steps, long targets) {
  std::vector<double> distinct;
  for (double h : lane_steps)
    if (std::find(distinct.begin(), distinct.end(), h) == distinct.end()) distinct.push_back(h);
  const double bytes = 24.0 * particles * static_cast<double>(distinct.size()) * static_cast<double>(targets);
  return std::min(bytes, kReferenceRecordLimit);
}

}  // namespace clothsim::clip
