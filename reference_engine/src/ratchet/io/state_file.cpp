#include "ratchet/io/state_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/io/json_file.hpp"

namespace ratchet {

// The layout below writes these structs field by field. If one of them changes (a new
// field in the state or the plane cache), the file would silently drop it and a restart
// would no longer be exact: update the format (and kStateFileVersion) first.
// The plane certificate is not written: it only lets a step skip a search whose result
// it proves (common_plane.hpp), so a restart without it gives the same results.
static_assert(sizeof(CommonPlaneCache) - sizeof(PlaneCertificate) == 72, "CommonPlaneCache changed: update io/state_file.cpp");
static_assert(sizeof(KeptImpulse) == 40, "KeptImpulse changed: update io/state_file.cpp");
static_assert(sizeof(KeptPlane) - sizeof(PlaneCertificate) == 80, "KeptPlane changed: update io/state_file.cpp");
static_assert(sizeof(State) == 8 + 4 * 8 + 7 * sizeof(std::vector<Vec3>), "State changed: update io/state_file.cpp");
static_assert(sizeof(KeptManifold) == 2 * 4 + sizeof(PairPose) + 8 + 4 + 4 + 3 * 8 + 24 * 8 + 8 * 4,
              "KeptManifold changed: update io/state_file.cpp");

namespace {

constexpr char kMagic[8] = {'R', 'A', 'T', 'C', 'H', 'E', 'T', 'S'};
constexpr std::size_t kHeaderBytes = 40;       // magic, version, meta length, bodies, key
constexpr std::size_t kBodyBytes = 13 * 8;     // x, v, w, q
constexpr std::size_t kImpulseBytes = 4 * 4 + 3 * 8;
constexpr std::size_t kPlaneBytes = 2 * 4 + 3 * 8 + 4 + 3 * 4 + 8 * 4;
constexpr int kMaxPlaneFeature = static_cast<int>(PlaneFeature::Axis);
constexpr std::size_t kManifoldBytes = 2 * 4 + 14 * 8 + 8 + 4 + 4 + 3 * 8 + 24 * 8 + 8 * 4;

std::uint64_t fnv1a(const char* data, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 1099511628211ull;
  }
  return h;
}

// Little-endian whatever the host: bytes are assembled by shifts, doubles by their bits.
struct Out {
  std::string b;
  void u64(std::uint64_t x) { for (int k = 0; k < 8; ++k) b.push_back(static_cast<char>((x >> (8 * k)) & 0xff)); }
  void u32(std::uint32_t x) { for (int k = 0; k < 4; ++k) b.push_back(static_cast<char>((x >> (8 * k)) & 0xff)); }
  void i64(std::int64_t x) { u64(static_cast<std::uint64_t>(x)); }
  void i32(std::int32_t x) { u32(static_cast<std::uint32_t>(x)); }
  void u8(std::uint8_t x) { b.push_back(static_cast<char>(x)); }
  void f64(double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, 8);
    u64(bits);
  }
  void vec(const Vec3& v) { f64(v.x()); f64(v.y()); f64(v.z()); }
};

struct In {
  const std::string& b;
  const std::string& source;
  std::size_t pos = 0, end = 0;
  [[noreturn]] void corrupt(const std::string& what) const {
    throw StateFileError(source + ": corrupt state file: " + what);
  }
  void need(std::size_t n, const char* what) const {
    if (n > end - pos) corrupt(std::string(what) + " runs past the end of the data");
  }
  std::uint64_t u64() {
    need(8, "a field");
    std::uint64_t x = 0;
    for (int k = 0; k < 8; ++k) x |= static_cast<std::uint64_t>(static_cast<unsigned char>(b[pos + k])) << (8 * k);
    pos += 8;
    return x;
  }
  std::uint32_t u32() {
    need(4, "a field");
    std::uint32_t x = 0;
    for (int k = 0; k < 4; ++k) x |= static_cast<std::uint32_t>(static_cast<unsigned char>(b[pos + k])) << (8 * k);
    pos += 4;
    return x;
  }
  std::int64_t i64() { return static_cast<std::int64_t>(u64()); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  std::uint8_t u8() {
    need(1, "a field");
    return static_cast<std::uint8_t>(b[pos++]);
  }
  double f64(const char* what) {
    const std::uint64_t bits = u64();
    double x;
    std::memcpy(&x, &bits, 8);
    if (!std::isfinite(x)) corrupt(std::string("non-finite value in ") + what);
    return x;
  }
  Vec3 vec(const char* what) {
    const double x = f64(what), y = f64(what), z = f64(what);
    return Vec3(x, y, z);
  }
};

}  // namespace

std::string encode_state_file(const StateFile& f) {
  const State& s = f.state;
  const std::size_t n = s.x.size();
  if (s.v.size() != n || s.w.size() != n || s.q.size() != n)
    throw std::invalid_argument("state file: the per-body arrays x, v, w, q differ in length");
  if (f.key.size() > 16) throw std::invalid_argument("state file: key longer than 16 characters: " + f.key);
  if (!f.meta.is_object()) throw std::invalid_argument("state file: meta must be a JSON object");
  const std::string meta = f.meta.dump();
  Out o;
  o.b.append(kMagic, 8);
  o.u32(kStateFileVersion);
  o.u32(static_cast<std::uint32_t>(meta.size()));
  o.u64(n);
  std::string key = f.key;
  key.resize(16, '\0');
  o.b.append(key);
  o.b.append(meta);
  o.i64(s.step);
  for (double x : {s.t, s.T, s.s_p, s.s_c}) o.f64(x);
  for (std::size_t i = 0; i < n; ++i) {
    o.vec(s.x[i]);
    o.vec(s.v[i]);
    o.vec(s.w[i]);
    for (double c : {s.q[i].w(), s.q[i].x(), s.q[i].y(), s.q[i].z()}) o.f64(c);
  }
  o.u64(s.impulses.size());
  for (const KeptImpulse& k : s.impulses) {
    o.i32(k.key.a);
    o.i32(k.key.b);
    o.i32(k.key.feature_a);
    o.i32(k.key.feature_b);
    o.vec(k.impulse);
  }
  // Only the entries that hold something (world/state.hpp).
  o.u64(static_cast<std::uint64_t>(
      std::count_if(s.planes.begin(), s.planes.end(), [](const KeptPlane& p) { return p.cache.valid; })));
  for (const KeptPlane& p : s.planes) {
    if (!p.cache.valid) continue;
    const CommonPlaneCache& c = p.cache;
    o.i32(p.a);
    o.i32(p.b);
    o.vec(c.normal);
    o.u8(c.valid ? 1 : 0);
    o.u8(static_cast<std::uint8_t>(static_cast<std::int8_t>(c.kind)));
    o.u8(0);
    o.u8(0);
    o.i32(c.index_a);
    o.i32(c.index_b);
    o.i32(c.simplex_count);
    for (const auto& pr : c.simplex) {
      o.i32(pr[0]);
      o.i32(pr[1]);
    }
  }
  o.u64(static_cast<std::uint64_t>(
      std::count_if(s.manifolds.begin(), s.manifolds.end(), [](const KeptManifold& m) { return m.count >= 0; })));
  for (const KeptManifold& m : s.manifolds) {
    if (m.count < 0) continue;
    o.i32(m.a);
    o.i32(m.b);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) o.f64(m.pose.rotation(r, c));
    o.vec(m.pose.offset);
    o.f64(m.pose.scale_a);
    o.f64(m.pose.scale_b);
    o.f64(m.gap_bound);
    o.i32(m.count);
    o.u8(m.normal_on_b ? 1 : 0);
    o.u8(0);
    o.u8(0);
    o.u8(0);
    o.vec(m.normal);
    for (const Vec3& p : m.on_a) o.vec(p);
    for (const Vec3& p : m.on_b) o.vec(p);
    for (std::int32_t f : m.feature_a) o.i32(f);
    for (std::int32_t f : m.feature_b) o.i32(f);
  }
  o.u64(fnv1a(o.b.data(), o.b.size()));
  return o.b;
}

StateFile decode_state_file(const std::string& bytes, const std::string& source) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
    throw StateFileError(source + ": not a ratchet state file (it does not start with 'RATCHETS')");
  if (bytes.size() < kHeaderBytes + 8)
    throw StateFileError(source + ": truncated state file (" + std::to_string(bytes.size()) +
                         " bytes; the header alone takes " + std::to_string(kHeaderBytes) + ")");
  In in{bytes, source, 8, bytes.size() - 8};
  const std::uint32_t version = in.u32();
  if (version < kOldestStateFileVersion || version > kStateFileVersion)
    throw StateFileError(source + ": state file format version " + std::to_string(version) + "; this build reads versions " +
                         std::to_string(kOldestStateFileVersion) + " to " + std::to_string(kStateFileVersion));
  // The checksum covers every byte before it: a cut or damaged file fails here, whole.
  In tail{bytes, source, bytes.size() - 8, bytes.size()};
  if (tail.u64() != fnv1a(bytes.data(), bytes.size() - 8))
    throw StateFileError(source + ": truncated or corrupt state file (checksum mismatch; " + std::to_string(bytes.size()) +
                         " bytes)");
  StateFile f;
  const std::uint32_t meta_len = in.u32();
  const std::uint64_t n = in.u64();
  in.need(16, "the key");
  f.key = bytes.substr(in.pos, 16);
  f.key.resize(std::strlen(f.key.c_str()));
  in.pos += 16;
  in.need(meta_len, "the metadata");
  f.meta = nlohmann::json::parse(bytes.substr(in.pos, meta_len), nullptr, false);
  if (f.meta.is_discarded() || !f.meta.is_object()) in.corrupt("the metadata is not a JSON object");
  in.pos += meta_len;
  State& s = f.state;
  s.step = in.i64();
  if (s.step < 0) in.corrupt("negative step count");
  s.t = in.f64("t");
  s.T = in.f64("T");
  s.s_p = in.f64("s_p");
  s.s_c = in.f64("s_c");
  if (n > (in.end - in.pos) / kBodyBytes) in.corrupt(std::to_string(n) + " bodies do not fit in the file");
  s.x.resize(n);
  s.v.resize(n);
  s.w.resize(n);
  s.q.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.x[i] = in.vec("a position");
    s.v[i] = in.vec("a velocity");
    s.w[i] = in.vec("an angular velocity");
    const double qw = in.f64("a quaternion"), qx = in.f64("a quaternion"), qy = in.f64("a quaternion"),
                 qz = in.f64("a quaternion");
    s.q[i] = Quat(qw, qx, qy, qz);
  }
  const auto body = [&](std::int64_t i) { return i >= 0 && static_cast<std::uint64_t>(i) < n; };
  const std::uint64_t ni = in.u64();
  if (ni > (in.end - in.pos) / kImpulseBytes) in.corrupt(std::to_string(ni) + " kept impulses do not fit in the file");
  s.impulses.resize(ni);
  for (std::size_t k = 0; k < ni; ++k) {
    KeptImpulse& ki = s.impulses[k];
    ki.key.a = in.i32();
    ki.key.b = in.i32();
    ki.key.feature_a = in.i32();
    ki.key.feature_b = in.i32();
    ki.impulse = in.vec("an impulse");
    if (!body(ki.key.a) || ki.key.b >= static_cast<std::int64_t>(n)) in.corrupt("a kept impulse names a body out of range");
    if (k > 0 && !(s.impulses[k - 1].key < ki.key)) in.corrupt("kept impulses not sorted by key");
  }
  const std::uint64_t np = in.u64();
  if (np > (in.end - in.pos) / kPlaneBytes) in.corrupt(std::to_string(np) + " kept planes do not fit in the file");
  s.planes.resize(np);
  for (std::size_t k = 0; k < np; ++k) {
    KeptPlane& p = s.planes[k];
    CommonPlaneCache& c = p.cache;
    p.a = in.i32();
    p.b = in.i32();
    c.normal = in.vec("a plane normal");
    const std::uint8_t valid = in.u8();
    const int kind = static_cast<std::int8_t>(in.u8());
    in.u8();
    in.u8();
    if (valid > 1 || kind < 0 || kind > kMaxPlaneFeature) in.corrupt("a kept plane has an unknown flag or feature kind");
    c.valid = valid == 1;
    c.kind = static_cast<PlaneFeature>(kind);
    c.index_a = in.i32();
    c.index_b = in.i32();
    c.simplex_count = in.i32();
    for (auto& pr : c.simplex) {
      pr[0] = in.i32();
      pr[1] = in.i32();
    }
    if (!body(p.a) || !body(p.b) || c.simplex_count < 0 || c.simplex_count > 4)
      in.corrupt("a kept plane names a body out of range or a bad simplex size");
    if (k > 0 && !(std::tie(s.planes[k - 1].a, s.planes[k - 1].b) < std::tie(p.a, p.b)))
      in.corrupt("kept planes not sorted by body pair");
  }
  const std::uint64_t nm = version >= 2 ? in.u64() : 0;
  if (nm > (in.end - in.pos) / kManifoldBytes) in.corrupt(std::to_string(nm) + " kept manifolds do not fit in the file");
  s.manifolds.resize(nm);
  for (std::size_t k = 0; k < nm; ++k) {
    KeptManifold& m = s.manifolds[k];
    m.a = in.i32();
    m.b = in.i32();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m.pose.rotation(r, c) = in.f64("a kept manifold's pose");
    m.pose.offset = in.vec("a kept manifold's pose");
    m.pose.scale_a = in.f64("a kept manifold's pose");
    m.pose.scale_b = in.f64("a kept manifold's pose");
    m.gap_bound = in.f64("a kept manifold's gap bound");
    m.count = in.i32();
    const std::uint8_t on_b = in.u8();
    in.u8();
    in.u8();
    in.u8();
    m.normal_on_b = on_b == 1;
    m.normal = in.vec("a kept manifold's normal");
    for (Vec3& p : m.on_a) p = in.vec("a kept manifold point");
    for (Vec3& p : m.on_b) p = in.vec("a kept manifold point");
    for (std::int32_t& f : m.feature_a) f = in.i32();
    for (std::int32_t& f : m.feature_b) f = in.i32();
    if (!body(m.a) || !body(m.b) || m.count < 0 || m.count > 4 || on_b > 1)
      in.corrupt("a kept manifold names a body out of range, a bad point count or an unknown flag");
    if (k > 0 && !(std::tie(s.manifolds[k - 1].a, s.manifolds[k - 1].b) < std::tie(m.a, m.b)))
      in.corrupt("kept manifolds not sorted by body pair");
  }
  if (in.pos != in.end) in.corrupt(std::to_string(in.end - in.pos) + " bytes left over after the state");
  return f;
}

void write_state_file(const std::string& path, const StateFile& f) { write_file_atomic(path, encode_state_file(f)); }

StateFile read_state_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw StateFileError(path + ": cannot open the state file (" + unreadable_reason(path) + ")");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw StateFileError(path + ": read error");
  return decode_state_file(bytes, path);
}

}  // namespace ratchet
