// The bodies file (docs/output-format.md, "Bodies and shapes"): every body and shape of
// a built scene, the poses of the given state, numbers that read back bit for bit, one
// body or shape per line, written atomically.
#include "ratchet/io/bodies_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/test_files.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "ratchet/world/world.hpp"

namespace ratchet {
namespace {
using test::bits;

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;

// Four generated spheres, then a fixed sphere with a velocity, a box and a tetrahedron.
SceneDef sample_scene() {
  return build_scene(json::parse(R"({
    "name": "bodies_sample", "seed": 5, "time": {"dt": 0.01, "duration": 0.1},
    "materials": {"density": 2.0},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {
      "generate": {"count": 4, "shape": "sphere", "radius_range": [0.3, 0.7],
                   "region": {"min": [0, 0, 0], "max": [6, 6, 6]}},
      "bodies": [
        {"shape": "sphere", "radius": 0.5, "position": [10, 0, 1], "velocity": [1, 2, 3], "fixed": true},
        {"shape": "box", "half_extents": [0.5, 0.25, 1.0], "position": [12, 0, 1],
         "orientation": [0.9, 0.1, 0.3, 0.2], "velocity": [0.5, 0, 0], "angular_velocity": [0, 0, 0.25]},
        {"shape": "polyhedron", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "position": [14, 0, 1]}
      ]}
  })"),
                     "sample.json");
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() /
                     ("ratchet_bodies_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void expect_vec(const json& j, const Vec3& v, const std::string& what) {
  ASSERT_TRUE(j.is_array()) << what;
  ASSERT_EQ(j.size(), 3u) << what;
  for (int a = 0; a < 3; ++a) EXPECT_EQ(bits(j[a].get<double>()), bits(v[a])) << what << "[" << a << "]";
}

TEST(BodiesFile, EveryBodyWithItsKindPoseAndMassProperties) {
  const SceneDef scene = sample_scene();
  const World world(scene);
  const json doc = json::parse(bodies_document(world.scene(), world.state()).dump());
  EXPECT_EQ(doc.at("format"), "ratchet-bodies");
  EXPECT_EQ(doc.at("version"), 1);
  EXPECT_EQ(doc.at("scene_name"), "bodies_sample");
  EXPECT_EQ(doc.at("scene_file"), "sample.json");
  EXPECT_EQ(doc.at("seed"), 5);
  EXPECT_EQ(doc.at("density"), 2.0);
  EXPECT_EQ(doc.at("step"), 0);
  EXPECT_EQ(doc.at("t"), 0.0);
  const json& bodies = doc.at("bodies");
  ASSERT_EQ(bodies.size(), 7u);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const json& b = bodies[i];
    const BodyDef& d = scene.bodies[i];
    const std::string what = "body " + std::to_string(i);
    EXPECT_EQ(b.at("index"), i) << what;
    expect_vec(b.at("position"), world.state().x[i], what + " position");
    const Quat& q = world.state().q[i];
    ASSERT_EQ(b.at("orientation").size(), 4u);
    EXPECT_EQ(bits(b.at("orientation")[0].get<double>()), bits(q.w())) << what;  // w first
    expect_vec(json::array({b["orientation"][1], b["orientation"][2], b["orientation"][3]}), q.vec(), what + " q");
    expect_vec(b.at("velocity"), world.state().v[i], what + " velocity");
    expect_vec(b.at("angular_velocity"), world.state().w[i], what + " angular velocity");
    EXPECT_EQ(bits(b.at("mass").get<double>()), bits(d.mass)) << what;
    expect_vec(b.at("principal_inertia"), d.principal_inertia, what + " inertia");
    EXPECT_EQ(bits(b.at("bounding_radius").get<double>()), bits(d.bounding_radius)) << what;
    EXPECT_EQ(b.at("fixed"), d.fixed) << what;
    if (i < 5) {
      EXPECT_EQ(b.at("kind"), "sphere") << what;
      EXPECT_EQ(bits(b.at("radius").get<double>()), bits(d.radius)) << what;
      EXPECT_TRUE(b.at("shape").is_null()) << what;
    } else {
      EXPECT_EQ(b.at("kind"), "polyhedron") << what;  // a box is a polyhedron of 8 vertices
      EXPECT_TRUE(b.at("radius").is_null()) << what;
      EXPECT_EQ(b.at("shape"), i - 5) << what;
    }
  }
  // Generated spheres: radii from the range; sphere mass properties.
  for (int i = 0; i < 4; ++i) {
    const double r = bodies[i].at("radius");
    EXPECT_GE(r, 0.3);
    EXPECT_LE(r, 0.7);
    EXPECT_DOUBLE_EQ(bodies[i].at("mass").get<double>(), 2.0 * 4.0 / 3.0 * M_PI * r * r * r);
  }
  // The state's values, as the run starts: a fixed body does not move.
  EXPECT_TRUE(bodies[4].at("fixed").get<bool>());
  EXPECT_EQ(bodies[4].at("velocity"), json::array({0.0, 0.0, 0.0}));
  expect_vec(bodies[5].at("velocity"), Vec3(0.5, 0.0, 0.0), "box velocity");
  expect_vec(bodies[5].at("angular_velocity"), Vec3(0.0, 0.0, 0.25), "box angular velocity");
}

TEST(BodiesFile, ShapesWithBodyFrameVerticesFacesAndVolume) {
  const SceneDef scene = sample_scene();
  const World world(scene);
  const json doc = json::parse(bodies_document(world.scene(), world.state()).dump());
  const json& shapes = doc.at("shapes");
  ASSERT_EQ(shapes.size(), 2u);
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const ConvexPolyhedron& s = scene.shapes[k];
    EXPECT_EQ(shapes[k].at("index"), k);
    ASSERT_EQ(shapes[k].at("vertices").size(), s.vertices.size());
    for (std::size_t v = 0; v < s.vertices.size(); ++v)
      expect_vec(shapes[k]["vertices"][v], s.vertices[v], "shape " + std::to_string(k) + " vertex");
    EXPECT_EQ(shapes[k].at("faces").get<std::vector<std::vector<int>>>(), s.faces);
    EXPECT_EQ(bits(shapes[k].at("volume").get<double>()), bits(s.volume));
    expect_vec(shapes[k].at("principal_inertia_per_density"), s.principal_inertia, "inertia per density");
    EXPECT_EQ(bits(shapes[k].at("bounding_radius").get<double>()), bits(s.bounding_radius));
  }
  // The box: 8 vertices at +-half extents, 6 faces, volume 8 abc; mass = density x volume.
  EXPECT_EQ(shapes[0].at("vertices").size(), 8u);
  EXPECT_EQ(shapes[0].at("faces").size(), 6u);
  EXPECT_DOUBLE_EQ(shapes[0].at("volume").get<double>(), 8.0 * 0.5 * 0.25 * 1.0);
  EXPECT_DOUBLE_EQ(doc["bodies"][5].at("mass").get<double>(), 2.0);
  // The tetrahedron: 4 triangles, volume 1/6.
  EXPECT_EQ(shapes[1].at("faces").size(), 4u);
  EXPECT_DOUBLE_EQ(shapes[1].at("volume").get<double>(), 1.0 / 6.0);
}

TEST(BodiesFile, WrittenAtomicallyOneBodyPerLineAndReadsBackBitForBit) {
  const fs::path d = temp_dir();
  SceneDef scene = sample_scene();
  World world(scene);
  State& s = world.mutable_state();  // another state than the initial one: its values are written
  s.step = 42;
  s.t = 0.1 + 0.2;
  s.s_p = 1.0 + 1e-16 * 3;
  s.x[0] = Vec3(1.0 / 3.0, -2.5e-300, 1e300);
  const std::string path = (d / "sub" / "b.json").string();
  fs::create_directories(d / "sub");
  write_bodies_file(path, world.scene(), world.state());
  EXPECT_FALSE(fs::exists(path + ".partial"));
  const std::string text = slurp(path);
  const json doc = json::parse(text);
  EXPECT_EQ(doc.at("step"), 42);
  EXPECT_EQ(bits(doc.at("t").get<double>()), bits(0.1 + 0.2));
  EXPECT_EQ(bits(doc.at("s_p").get<double>()), bits(s.s_p));
  expect_vec(doc["bodies"][0].at("position"), s.x[0], "written position");
  // Layout: the header keys in order, then one line per body and per shape.
  EXPECT_EQ(text.rfind("{\n  \"format\": \"ratchet-bodies\",\n  \"version\": 1,\n", 0), 0u) << text.substr(0, 200);
  std::istringstream lines(text);
  std::string line;
  int body_lines = 0, shape_lines = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("    {\"index\":", 0) != 0) continue;
    if (line.find("\"kind\":") != std::string::npos) ++body_lines;
    else if (line.find("\"vertices\":") != std::string::npos) ++shape_lines;
  }
  EXPECT_EQ(body_lines, 7);
  EXPECT_EQ(shape_lines, 2);
  // Keys in the documented order within a body.
  EXPECT_THAT(text, HasSubstr("{\"index\":4,\"kind\":\"sphere\",\"radius\":0.5,\"shape\":null,"
                              "\"position\":[10.0,0.0,1.0],\"orientation\":[1.0,0.0,0.0,0.0],\"velocity\":[0.0,0.0,0.0],"
                              "\"angular_velocity\":[0.0,0.0,0.0],\"mass\":"));
  fs::remove_all(d);
}

TEST(BodiesFile, AStateOfAnotherSceneOrAnUnwritablePathIsRefused) {
  const SceneDef scene = sample_scene();
  State other;
  other.x.resize(2);
  other.v.resize(2);
  other.w.resize(2);
  other.q.resize(2);
  EXPECT_THROW(bodies_document(scene, other), std::invalid_argument);
  const World world(scene);
  const fs::path d = temp_dir();
  EXPECT_THROW(write_bodies_file((d / "missing" / "b.json").string(), world.scene(), world.state()),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(d / "missing"));
  fs::remove_all(d);
}

}  // namespace
}  // namespace ratchet
