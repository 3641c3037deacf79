// State files: bit-exact round trip, the fixed little-endian layout, and refusal of
// truncated, corrupt and foreign files as a whole.
#include "ratchet/io/state_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/test_files.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

namespace ratchet {
namespace {
using test::bits;

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Values whose bits a text round trip or a careless copy would change.
StateFile sample() {
  StateFile f;
  f.key = "0123456789abcdef";
  f.meta = {{"settle", {{"t_end", 3.25}, {"reached", true}}}, {"note", "sample"}};
  State& s = f.state;
  s.step = 123456789012LL;
  s.t = 0.1 + 0.2;
  s.T = -0.0;
  s.s_p = 1.0 + std::numeric_limits<double>::epsilon();
  s.s_c = std::numeric_limits<double>::denorm_min();
  for (int i = 0; i < 3; ++i) {
    s.x.emplace_back(1.0 / 3.0 + i, -2.5e-300, 1e300);
    s.v.emplace_back(-0.0, std::nextafter(1.0, 2.0), -i * 0.7);
    s.w.emplace_back(i, 0.5, -1e-17);
    s.q.push_back(Quat(0.5, -0.5, 0.5, -0.5 + 1e-16 * i));
  }
  s.impulses.push_back({{0, -1, 5, 0}, Vec3(0.1, -0.2, 0.3)});
  s.impulses.push_back({{0, 2, (2 << 24) | 7, (1 << 24) | 3}, Vec3(-0.0, 1e-200, 7.0)});
  s.impulses.push_back({{1, -17, 0, 0}, Vec3(1.0, 2.0, 3.0)});
  KeptPlane p;
  p.a = 0;
  p.b = 2;
  p.cache.normal = Vec3(0.6, 0.0, -0.8);
  p.cache.valid = true;
  p.cache.kind = PlaneFeature::Simplex;
  p.cache.index_a = 4;
  p.cache.index_b = -1;
  p.cache.simplex_count = 3;
  p.cache.simplex = {{{1, 2}, {3, 4}, {5, 6}, {7, 8}}};
  s.planes.push_back(p);
  p.a = 1;
  p.cache.kind = PlaneFeature::Axis;
  s.planes.push_back(p);
  KeptManifold m;
  m.a = 0;
  m.b = 1;
  m.pose.rotation << 0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0 + 1e-16;
  m.pose.offset = Vec3(0.1 + 0.2, -1e-300, 2.0);
  m.pose.scale_a = 1.0 + 2e-16;
  m.pose.scale_b = 0.999;
  m.gap_bound = -0.0;
  m.count = 2;
  m.normal_on_b = true;
  m.normal = Vec3(0.0, 0.6, 0.8);
  m.on_a = {Vec3(1, 2, 3), Vec3(-1e-17, 0.5, 0.25), Vec3::Zero(), Vec3::Zero()};
  m.on_b = {Vec3(3, 2, 1), Vec3(1.0 / 3.0, 0.5, -0.25), Vec3::Zero(), Vec3::Zero()};
  m.feature_a = {(2 << 24) | 5, 7, 0, 0};
  m.feature_b = {(1 << 24) | 2, (2 << 24) | 1, 0, 0};
  s.manifolds.push_back(m);
  m.b = 2;
  m.count = 0;
  m.normal_on_b = false;
  m.gap_bound = 0.0625;
  s.manifolds.push_back(m);
  return f;
}

void expect_bit_equal(const State& a, const State& b) {
  EXPECT_EQ(a.step, b.step);
  for (auto [x, y] : {std::pair{a.t, b.t}, {a.T, b.T}, {a.s_p, b.s_p}, {a.s_c, b.s_c}}) EXPECT_EQ(bits(x), bits(y));
  ASSERT_EQ(a.x.size(), b.x.size());
  for (std::size_t i = 0; i < a.x.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(bits(a.x[i][k]), bits(b.x[i][k]));
      EXPECT_EQ(bits(a.v[i][k]), bits(b.v[i][k]));
      EXPECT_EQ(bits(a.w[i][k]), bits(b.w[i][k]));
    }
  for (std::size_t i = 0; i < a.q.size(); ++i)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(bits(a.q[i].coeffs()[k]), bits(b.q[i].coeffs()[k]));  // x, y, z, w
  ASSERT_EQ(a.impulses.size(), b.impulses.size());
  for (std::size_t i = 0; i < a.impulses.size(); ++i) {
    EXPECT_TRUE(a.impulses[i].key == b.impulses[i].key);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(a.impulses[i].impulse[k]), bits(b.impulses[i].impulse[k]));
  }
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (std::size_t i = 0; i < a.planes.size(); ++i) {
    const CommonPlaneCache &c = a.planes[i].cache, &d = b.planes[i].cache;
    EXPECT_EQ(a.planes[i].a, b.planes[i].a);
    EXPECT_EQ(a.planes[i].b, b.planes[i].b);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(c.normal[k]), bits(d.normal[k]));
    EXPECT_EQ(c.valid, d.valid);
    EXPECT_EQ(c.kind, d.kind);
    EXPECT_EQ(c.index_a, d.index_a);
    EXPECT_EQ(c.index_b, d.index_b);
    EXPECT_EQ(c.simplex_count, d.simplex_count);
    EXPECT_EQ(c.simplex, d.simplex);
  }
  ASSERT_EQ(a.manifolds.size(), b.manifolds.size());
  for (std::size_t i = 0; i < a.manifolds.size(); ++i) {
    const KeptManifold &m = a.manifolds[i], &n = b.manifolds[i];
    EXPECT_EQ(m.a, n.a);
    EXPECT_EQ(m.b, n.b);
    for (int k = 0; k < 9; ++k) EXPECT_EQ(bits(m.pose.rotation.data()[k]), bits(n.pose.rotation.data()[k]));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(m.pose.offset[k]), bits(n.pose.offset[k]));
    EXPECT_EQ(bits(m.pose.scale_a), bits(n.pose.scale_a));
    EXPECT_EQ(bits(m.pose.scale_b), bits(n.pose.scale_b));
    EXPECT_EQ(bits(m.gap_bound), bits(n.gap_bound));
    EXPECT_EQ(m.count, n.count);
    EXPECT_EQ(m.normal_on_b, n.normal_on_b);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(m.normal[k]), bits(n.normal[k]));
    for (std::size_t p = 0; p < 4; ++p)
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(bits(m.on_a[p][k]), bits(n.on_a[p][k]));
        EXPECT_EQ(bits(m.on_b[p][k]), bits(n.on_b[p][k]));
      }
    EXPECT_EQ(m.feature_a, n.feature_a);
    EXPECT_EQ(m.feature_b, n.feature_b);
  }
}

fs::path scratch() {
  const fs::path d = fs::temp_directory_path() /
                     (std::string("ratchet_state_file_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(StateFile, RoundTripThroughAFileIsBitExact) {
  const fs::path d = scratch();
  const StateFile f = sample();
  write_state_file((d / "s.state").string(), f);
  EXPECT_FALSE(fs::exists(d / "s.state.partial"));
  const StateFile g = read_state_file((d / "s.state").string());
  EXPECT_EQ(g.key, f.key);
  EXPECT_EQ(g.meta, f.meta);
  expect_bit_equal(f.state, g.state);
  EXPECT_EQ(encode_state_file(g), encode_state_file(f));  // and back to the same bytes
  fs::remove_all(d);
}

// Between steps the state keeps an entry per candidate pair, most holding nothing (a
// plane not valid, a manifold of count -1: world/state.hpp); a file keeps only the others,
// so it has the bytes of the state without them, and reads back as that state.
TEST(StateFile, EntriesThatHoldNothingAreNotWritten) {
  const StateFile f = sample();
  StateFile g = f;
  KeptPlane empty_plane;
  empty_plane.a = 0;
  empty_plane.b = 1;
  empty_plane.cache.kind = PlaneFeature::Axis;  // left over: not valid, so nothing
  g.state.planes.insert(g.state.planes.begin(), empty_plane);
  KeptManifold none = f.state.manifolds[0];
  none.a = 1;
  none.b = 2;
  none.count = -1;
  g.state.manifolds.push_back(none);
  EXPECT_EQ(encode_state_file(g), encode_state_file(f));
  expect_bit_equal(decode_state_file(encode_state_file(g), "g.state").state, f.state);
}

TEST(StateFile, LayoutIsFixedLittleEndian) {
  const StateFile f = sample();
  const std::string b = encode_state_file(f);
  const std::string meta = f.meta.dump();
  EXPECT_EQ(b.substr(0, 8), "RATCHETS");
  EXPECT_EQ(b.substr(8, 4), std::string("\x02\x00\x00\x00", 4));                       // version 2
  EXPECT_EQ(static_cast<unsigned char>(b[12]), meta.size());                            // meta length
  EXPECT_EQ(b.substr(16, 8), std::string("\x03\x00\x00\x00\x00\x00\x00\x00", 8));     // 3 bodies
  EXPECT_EQ(b.substr(24, 16), f.key);
  EXPECT_EQ(b.substr(40, meta.size()), meta);
  // step (int64 LE) right after the metadata: 123456789012 = 0x1CBE991A14.
  EXPECT_EQ(b.substr(40 + meta.size(), 8), std::string("\x14\x1a\x99\xbe\x1c\x00\x00\x00", 8));
  const std::size_t expected = 40 + meta.size() + 8 + 4 * 8 + 3 * 13 * 8 + 8 + 3 * 40 + 8 + 2 * 80 + 8 + 2 * 384 + 8;
  EXPECT_EQ(b.size(), expected);
}

// FNV-1a over the bytes, the file's checksum (docs/output-format.md, "State files").
std::uint64_t checksum(const std::string& b) {
  std::uint64_t h = 1469598103934665603ull;
  for (char c : b) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

// Version 1 had no kept manifolds: its files (packings made before them) still load.
TEST(StateFile, AVersionOneFileReadsWithoutManifolds) {
  StateFile f = sample();
  f.state.manifolds.clear();
  std::string b = encode_state_file(f);
  b.resize(b.size() - 16);  // drop the checksum and the manifold count (0)
  b[8] = 1;
  const std::uint64_t h = checksum(b);
  for (int k = 0; k < 8; ++k) b.push_back(static_cast<char>((h >> (8 * k)) & 0xff));
  const StateFile g = decode_state_file(b, "old.state");
  expect_bit_equal(f.state, g.state);
  EXPECT_TRUE(g.state.manifolds.empty());
}

TEST(StateFile, EveryTruncationIsRefusedWhole) {
  const std::string b = encode_state_file(sample());
  for (std::size_t n = 0; n < b.size(); ++n) {
    try {
      (void)decode_state_file(b.substr(0, n), "cut.state");
      ADD_FAILURE() << "a file cut to " << n << " of " << b.size() << " bytes was accepted";
    } catch (const StateFileError& e) {
      EXPECT_THAT(e.what(), HasSubstr("cut.state"));
    }
  }
}

TEST(StateFile, EveryDamagedByteIsRefused) {
  const std::string b = encode_state_file(sample());
  for (std::size_t i = 0; i < b.size(); ++i) {
    std::string c = b;
    c[i] = static_cast<char>(c[i] ^ 0x10);
    EXPECT_THROW((void)decode_state_file(c, "bad.state"), StateFileError) << "byte " << i;
  }
  try {
    (void)decode_state_file(b.substr(0, b.size() - 20) + std::string(20, 'x'), "bad.state");
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.state: truncated or corrupt state file (checksum mismatch"));
  }
}

TEST(StateFile, ForeignFilesAndOtherVersionsAreNamed) {
  try {
    (void)decode_state_file("{\"name\": \"a scene, not a state\"}", "scene.json");
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("scene.json: not a ratchet state file"));
  }
  std::string b = encode_state_file(sample());
  b[8] = 3;  // version 3
  try {
    (void)decode_state_file(b, "new.state");
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("new.state: state file format version 3; this build reads versions 1 to 2"));
  }
  try {
    (void)read_state_file("/nonexistent/dir/p.state");
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/dir/p.state: cannot open"));
  }
}

TEST(StateFile, InconsistentStateIsNotWritten) {
  StateFile f = sample();
  f.state.q.pop_back();
  EXPECT_THROW((void)encode_state_file(f), std::invalid_argument);
  f = sample();
  f.key = std::string(17, 'a');
  EXPECT_THROW((void)encode_state_file(f), std::invalid_argument);
}

}  // namespace
}  // namespace ratchet
