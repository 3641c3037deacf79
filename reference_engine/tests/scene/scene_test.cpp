// Scene reading: defaults, derived fields, generation, and the error messages for
// malformed input (file, field and expectation named; nothing built).
#include "ratchet/scene/scene.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace ratchet {
namespace {

using nlohmann::json;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

json minimal_scene() {
  return json::parse(R"({
    "name": "t", "time": {"dt": 0.01, "duration": 1.0},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 2], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 1]}]}
  })");
}

std::string error_of(const json& j) {
  try {
    build_scene(j, "scene.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, MinimalSceneGetsDefaults) {
  const SceneDef s = build_scene(minimal_scene(), "scene.json");
  EXPECT_EQ(s.steps, 100);
  EXPECT_DOUBLE_EQ(s.solver.tolerance, 1e-4);
  EXPECT_DOUBLE_EQ(s.materials.friction, 0.5);
  EXPECT_FALSE(s.thermal.enabled);
  ASSERT_EQ(s.container.walls.size(), 1u);
  EXPECT_DOUBLE_EQ(s.container.walls[0].normal.z(), 1.0);  // normalised
  EXPECT_NEAR(s.bodies[0].mass, 4.0 / 3.0 * M_PI * 0.125, 1e-15);
  EXPECT_EQ(s.hash.size(), 16u);
}

TEST(Scene, DurationDefaultsToTheThermalProtocol) {
  json j = minimal_scene();
  j["time"].erase("duration");
  j["thermal"] = {{"heat_time", 2.0}, {"hold_time", 1.0}, {"cool_time", 3.0}, {"cycles", 2}, {"start_time", 0.5}};
  const SceneDef s = build_scene(j, "scene.json");
  EXPECT_DOUBLE_EQ(s.duration, 0.5 + 2 * (2.0 + 1.0 + 3.0 + 1.0));
  EXPECT_EQ(s.steps, 1450);
}

TEST(Scene, ConeHasABottomAndSegmentsLeaningOutByTheOpeningAngle) {
  json j = minimal_scene();
  j["container"] = {{"type", "cone"}, {"bottom_radius", 8.5}, {"opening_angle_deg", 6.0}, {"segments", 16}};
  const SceneDef s = build_scene(j, "scene.json");
  ASSERT_EQ(s.container.walls.size(), 17u);
  EXPECT_EQ(s.container.walls[0].role, WallRole::Bottom);
  for (std::size_t k = 1; k < 17; ++k) {
    const WallDef& w = s.container.walls[k];
    EXPECT_NEAR(w.normal.norm(), 1.0, 1e-15);
    EXPECT_NEAR(std::asin(w.normal.z()), 6.0 * M_PI / 180.0, 1e-14);  // leans outward
    EXPECT_NEAR(std::hypot(w.point.x(), w.point.y()), 8.5, 1e-12);    // middle of the segment
    EXPECT_GT(w.normal.dot(Vec3::Zero() - w.point), 0.0);               // the axis is inside
  }
}

TEST(Scene, ConeFloorExpandsUnlessTheSceneSaysOtherwise) {
  json j = minimal_scene();
  j["container"] = {{"type", "cone"}};
  const SceneDef s = build_scene(j, "scene.json");
  EXPECT_TRUE(s.container.floor_expands);
  EXPECT_TRUE(s.container.walls[0].expands);
  j["container"]["floor_expands"] = false;
  const SceneDef t = build_scene(j, "scene.json");
  EXPECT_FALSE(t.container.walls[0].expands);
  for (std::size_t k = 1; k < t.container.walls.size(); ++k) EXPECT_TRUE(t.container.walls[k].expands);
}

TEST(Scene, GeneratedParticlesAreFixedBySeedAndDoNotOverlap) {
  json j = minimal_scene();
  j["particles"] = {{"generate", {{"count", 50}, {"vertices", 12}}}};
  j["container"] = {{"type", "cone"}};
  const SceneDef a = build_scene(j, "scene.json"), b = build_scene(j, "scene.json");
  ASSERT_EQ(a.bodies.size(), 50u);
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(a.bodies[i].position, b.bodies[i].position);
    EXPECT_EQ(a.shapes[i].vertices, b.shapes[i].vertices);
    for (std::size_t k = 0; k < i; ++k)
      EXPECT_GT((a.bodies[i].position - a.bodies[k].position).norm(),
                a.bodies[i].bounding_radius + a.bodies[k].bounding_radius);
  }
  j["seed"] = 2;
  const SceneDef c = build_scene(j, "scene.json");
  EXPECT_NE(a.shapes[0].vertices, c.shapes[0].vertices);
}

TEST(Scene, ListedPolyhedronIsCentredAtItsCentroid) {
  json j = minimal_scene();
  j["particles"]["bodies"] = json::array({{{"shape", "polyhedron"},
                                           {"vertices", {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}}},
                                           {"position", {1, 2, 3}}}});
  const SceneDef s = build_scene(j, "scene.json");
  EXPECT_NEAR(s.bodies[0].mass, 8.0 / 6.0, 1e-14);  // tetrahedron volume, density 1
  // World vertices: position + R v; their centroid (of the solid) is the position.
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : s.shapes[0].vertices) mean += s.bodies[0].orientation * v;
  EXPECT_NEAR((mean / 4.0).norm(), 0.0, 1e-14);  // the vertex mean is the centroid for a tetrahedron
}

struct BadCase {
  const char* what;
  const char* path;      // json pointer to change
  const char* value;     // JSON text
  const char* field;     // expected in the message
  const char* expected;  // expected in the message
};

class MalformedScene : public ::testing::TestWithParam<BadCase> {};

TEST_P(MalformedScene, NamesFileFieldAndExpectation) {
  const BadCase& c = GetParam();
  json j = minimal_scene();
  j[json::json_pointer(c.path)] = json::parse(c.value);
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json"), HasSubstr(c.field), HasSubstr(c.expected))) << c.what;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedScene,
    ::testing::Values(
        BadCase{"unknown top-level field", "/colour", "1", "'colour'", "unknown field"},
        BadCase{"unknown nested field", "/solver/tolerence", "1e-4", "'solver.tolerence'", "known fields here"},
        BadCase{"negative radius", "/particles/bodies/0/radius", "-0.5", "particles.bodies[0].radius",
                "positive number"},
        BadCase{"NaN as text", "/time/dt", "\"nan\"", "'time.dt'", "finite positive number"},
        BadCase{"p_gap out of range", "/solver/p_gap", "1.5", "'solver.p_gap'", "(0, 1]"},
        BadCase{"theta out of range", "/solver/theta", "0.2", "'solver.theta'", "[0.5, 1]"},
        BadCase{"negative compliance", "/solver/compliance", "-0.01", "'solver.compliance'", "[0, 1]"},
        BadCase{"compliance as text", "/solver/compliance", "\"0.03\"", "'solver.compliance'", "[0, 1]"},
        BadCase{"reuse beyond the margin", "/solver/manifold_reuse", "0.06", "'solver.manifold_reuse'",
                "[0, solver.contact_margin]"},
        BadCase{"negative reuse", "/solver/manifold_reuse", "-0.001", "'solver.manifold_reuse'", "a length"},
        BadCase{"bad vector", "/gravity", "[0, 1]", "'gravity'", "3 finite numbers"},
        BadCase{"unknown shape", "/particles/bodies/0/shape", "\"cube\"", "particles.bodies[0].shape", "\"sphere\""},
        BadCase{"bad container type", "/container/type", "\"box\"", "'container.type'", "\"cone\" or \"planes\""},
        BadCase{"floor_expands as text", "/container", "{\"type\": \"cone\", \"floor_expands\": \"no\"}",
                "'container.floor_expands'", "true or false"},
        BadCase{"zero normal", "/container/planes/0/normal", "[0, 0, 0]", "container.planes[0].normal",
                "non-zero"},
        BadCase{"negative friction", "/materials/friction", "-0.1", "'materials.friction'", ">= 0"},
        BadCase{"fractional count", "/outputs", "{\"timeseries_every\": 2.5}", "'outputs.timeseries_every'",
                "an integer"},
        BadCase{"settled profile without bands", "/outputs", "{\"settled_profile_time\": 2}",
                "'outputs.settled_profile_time'", "outputs.wall_profile_bins > 0 as well"},
        BadCase{"negative settled profile time", "/outputs", "{\"wall_profile_bins\": 4, \"settled_profile_time\": -1}",
                "'outputs.settled_profile_time'", ">= 0"}));

TEST(Scene, MissingRequiredFieldsAreNamed) {
  json j = minimal_scene();
  j.erase("time");
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("'time'"), HasSubstr("required")));
  j = minimal_scene();
  j["particles"]["bodies"][0].erase("radius");
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("particles.bodies[0].radius"), HasSubstr("required")));
}

// outputs.vtk_every: steps between VTK snapshots in any scene, 0 (the default) for none;
// outputs.vtk_cycles names thermal cycles, so a scene without any is refused rather than
// silently writing nothing.
TEST(Scene, VtkOutputsAreChecked) {
  json j = minimal_scene();
  EXPECT_EQ(build_scene(j, "scene.json").outputs.vtk_every, 0);
  j["outputs"] = {{"vtk_every", 25}};
  EXPECT_EQ(build_scene(j, "scene.json").outputs.vtk_every, 25);
  for (const char* bad : {"-1", "2.5", "\"10\"", "true"}) {
    j["outputs"] = {{"vtk_every", json::parse(bad)}};
    EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json: field 'outputs.vtk_every'"), HasSubstr("an integer in [0,")))
        << bad;
  }
  j["outputs"] = {{"vtk_cycles", {0}}};
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json: field 'outputs.vtk_cycles'"),
                                 HasSubstr("without thermal cycles"), HasSubstr("outputs.vtk_every"),
                                 HasSubstr("got [0]")));
  j["outputs"] = {{"vtk_cycles", json::array()}};  // asks for nothing: fine
  EXPECT_TRUE(build_scene(j, "scene.json").outputs.vtk_cycles.empty());
  j["outputs"] = {{"vtk_cycles", {1}}};
  j["thermal"] = {{"heat_time", 1.0}, {"cycles", 0}};  // a protocol without cycles
  EXPECT_THAT(error_of(j), HasSubstr("field 'outputs.vtk_cycles'"));
  j["thermal"]["cycles"] = 2;
  EXPECT_EQ(build_scene(j, "scene.json").outputs.vtk_cycles, std::vector<int>{1});
  // Through --set: the message names the option.
  const auto dir = std::filesystem::temp_directory_path() / "ratchet_scene_vtk_cycles";
  std::filesystem::create_directories(dir);
  const auto file = (dir / "scene.json").string();
  std::ofstream(file) << minimal_scene().dump();
  try {
    load_scene(file, {"outputs.vtk_cycles=[0]"});
    ADD_FAILURE() << "vtk_cycles without thermal cycles was accepted";
  } catch (const SceneError& e) {
    EXPECT_THAT(std::string(e.what()), AllOf(HasSubstr("--set outputs.vtk_cycles=[0]"),
                                             HasSubstr("field 'outputs.vtk_cycles'")));
  }
  std::filesystem::remove_all(dir);
}

TEST(Scene, VtkFormatIsBinaryUnlessAsciiIsAsked) {
  json j = minimal_scene();
  EXPECT_FALSE(build_scene(j, "scene.json").outputs.vtk_ascii);
  j["outputs"] = {{"vtk_format", "ascii"}};
  EXPECT_TRUE(build_scene(j, "scene.json").outputs.vtk_ascii);
  j["outputs"] = {{"vtk_format", "binary"}};
  EXPECT_FALSE(build_scene(j, "scene.json").outputs.vtk_ascii);
  for (const char* bad : {"\"xml\"", "\"ASCII\"", "1", "true"}) {
    j["outputs"] = {{"vtk_format", json::parse(bad)}};
    EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'outputs.vtk_format': expected")) << bad;
  }
  j["outputs"] = {{"vtk_format", "xml"}};
  EXPECT_THAT(error_of(j), HasSubstr("expected \"binary\" or \"ascii\", got \"xml\""));
}

// The effective scene: every default the reader took, written in, so that a run.json
// says everything the run used (a generated bed's seed, the solver's tolerance ...);
// what the scene wrote is kept as written; read back, it is the same scene.
TEST(Scene, EffectiveSceneFillsEveryDefaultAndReadsBackTheSame) {
  json j = minimal_scene();
  j["particles"] = {{"generate", {{"count", 30}}}};
  j["container"] = {{"type", "cone"}};
  j["solver"] = {{"tolerance", 1e-6}};
  j["thermal"] = {{"heat_time", 1.0}, {"cycles", 4}};
  j.erase("time");
  j["time"] = {{"dt", 0.01}};  // the duration comes from the protocol
  const SceneDef s = build_scene(j, "scene.json");
  const json& e = s.effective;
  EXPECT_EQ(s.as_run, j);  // the scene as run is left alone
  EXPECT_EQ(e.at("seed"), 1);
  EXPECT_EQ(e.at("gravity"), json({0.0, 0.0, -1.0}));
  EXPECT_EQ(e.at("time").at("duration"), s.duration);
  EXPECT_EQ(e.at("solver").at("tolerance"), 1e-6);  // as written
  EXPECT_EQ(e.at("solver").at("max_iterations"), 1000);
  EXPECT_EQ(e.at("solver").at("criterion"), "impulse");
  EXPECT_EQ(e.at("solver").at("acceleration"), "anderson");  // with the rigid law bounded (method.md s. 7)
  EXPECT_EQ(s.solver.acceleration, Acceleration::Anderson);
  EXPECT_EQ(s.solver.compliance, 0.0);  // the rigid law, the paper's
  EXPECT_EQ(e.at("materials").at("friction"), 0.5);
  EXPECT_EQ(e.at("effects").at("rotation"), true);
  EXPECT_EQ(e.at("container").at("segments"), 16);
  EXPECT_EQ(e.at("container").at("bottom_radius"), 8.5);
  EXPECT_EQ(e.at("thermal").at("cool_time"), 1.0);  // the heating time, its default
  EXPECT_EQ(e.at("thermal").at("T1"), 100.0);
  EXPECT_EQ(e.at("particles").at("generate").at("vertices"), 20);
  EXPECT_EQ(e.at("particles").at("generate").at("shape"), "polyhedron");
  EXPECT_EQ(e.at("particles").at("generate").at("radius_range"), json({0.5, 1.0}));
  EXPECT_EQ(e.at("particles").at("generate").at("spacing"), 2.5);
  EXPECT_EQ(e.at("outputs").at("vtk_format"), "binary");
  EXPECT_EQ(e.at("outputs").at("checkpoint_every"), kDefaultCheckpointEvery);
  EXPECT_EQ(e.at("outputs").at("steady_cycles"), json({2, 3}));  // the second half of 4 cycles
  EXPECT_EQ(e.at("outputs").at("vtk_cycles"), json::array());
  EXPECT_FALSE(e.contains("settle"));                         // absent means none
  EXPECT_FALSE(e.at("outputs").contains("displacement"));
  EXPECT_FALSE(e.at("particles").at("generate").contains("region"));
  // Read back: the same effective scene and the same bodies, to the bit.
  const SceneDef back = build_scene(e, "effective.json");
  EXPECT_EQ(back.effective, e);
  ASSERT_EQ(back.bodies.size(), s.bodies.size());
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    EXPECT_EQ(back.bodies[i].position, s.bodies[i].position);
    EXPECT_EQ(back.bodies[i].orientation.coeffs(), s.bodies[i].orientation.coeffs());
    EXPECT_EQ(back.shapes[i].vertices, s.shapes[i].vertices);
  }
  EXPECT_EQ(back.steps, s.steps);
  EXPECT_EQ(back.solver.tolerance, s.solver.tolerance);
  // Listed bodies get their defaults too, each at its own index.
  const SceneDef listed = build_scene(minimal_scene(), "scene.json");
  const json& body = listed.effective.at("particles").at("bodies").at(0);
  EXPECT_EQ(body.at("velocity"), json({0.0, 0.0, 0.0}));
  EXPECT_EQ(body.at("orientation"), json({1.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(body.at("fixed"), false);
  EXPECT_EQ(listed.effective.at("container").at("planes").at(0).at("expands"), false);
  EXPECT_FALSE(listed.effective.contains("thermal"));
  EXPECT_FALSE(listed.effective.at("outputs").contains("steady_cycles"));  // no cycles to average
  EXPECT_EQ(build_scene(listed.effective, "effective.json").effective, listed.effective);
}

// outputs.displacement.stages: off unless asked (scenes that do not ask pay nothing).
TEST(Scene, DisplacementStagesIsABooleanOffByDefault) {
  json j = minimal_scene();
  j["outputs"] = {{"displacement", {{"cell", 1.0}, {"windows", {{0, 1}}}}}};
  EXPECT_FALSE(build_scene(j, "scene.json").outputs.displacement_stages);
  j["outputs"]["displacement"]["stages"] = true;
  EXPECT_TRUE(build_scene(j, "scene.json").outputs.displacement_stages);
  j["outputs"]["displacement"]["stages"] = "yes";
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json: field 'outputs.displacement.stages'"),
                                 HasSubstr("true or false")));
}

TEST(Scene, SettleSectionIsCheckedStrictly) {
  json j = minimal_scene();
  j["thermal"] = {{"start_time", 0.5}, {"heat_time", 1.0}, {"cycles", 2}};
  j["time"].erase("duration");
  j["settle"] = {{"ke_ratio", 1e-6}, {"max_time", 3.0}};
  const SceneDef s = build_scene(j, "scene.json");
  EXPECT_TRUE(s.settle.enabled);
  EXPECT_DOUBLE_EQ(s.settle.ke_ratio, 1e-6);
  EXPECT_DOUBLE_EQ(s.settle.max_time, 3.0);
  EXPECT_FALSE(build_scene(minimal_scene(), "scene.json").settle.enabled);  // absent: no settle section
  for (const char* bad : {"-0.001", "0", "1", "2.5", "\"nan\"", "true", "null"}) {
    j["settle"]["ke_ratio"] = json::parse(bad);
    EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json: field 'settle.ke_ratio': expected a number in (0, 1), got"),
                                   HasSubstr(bad)))
        << bad;
  }
  j["settle"]["ke_ratio"] = 1e-6;
  for (const char* bad : {"-1", "0", "\"inf\"", "null"}) {
    j["settle"]["max_time"] = json::parse(bad);
    EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'settle.max_time': expected a finite positive number")) << bad;
  }
  j["settle"] = {{"ke_ratio", 1e-6}, {"max_time", 3.0}, {"peak", 1}};
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("'settle.peak': unknown field"), HasSubstr("known fields here: ke_ratio, max_time")));
  j["settle"] = {{"ke_ratio", 1e-6}};
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("'settle.max_time'"), HasSubstr("required")));
  j["settle"] = json::object();
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("'settle.ke_ratio'"), HasSubstr("required")));
  j["settle"] = 1e-6;
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("'settle'"), HasSubstr("an object")));
  j["settle"] = {{"ke_ratio", 1e-6}, {"max_time", 3.0}};
  j.erase("thermal");
  j["time"]["duration"] = 1.0;
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("field 'settle'"), HasSubstr("thermal section")));
}

// With a settle section the written times count from the end of the settle stage;
// until it is known the scene holds the latest values (settle end = max_time).
TEST(Scene, SettleSectionMovesTheProtocolAfterTheSettleStage) {
  json j = minimal_scene();
  j["time"] = {{"dt", 0.01}};
  j["thermal"] = {{"start_time", 0.5}, {"heat_time", 1.0}, {"hold_time", 0.25}, {"cool_time", 1.0}, {"cycles", 2}};
  const SceneDef fixed = build_scene(j, "fixed.json");
  EXPECT_DOUBLE_EQ(fixed.thermal.start_time, 0.5);
  EXPECT_DOUBLE_EQ(fixed.duration, 0.5 + 2 * 2.5);
  EXPECT_EQ(fixed.steps, 550);
  j["settle"] = {{"ke_ratio", 1e-6}, {"max_time", 3.0}};
  const SceneDef s = build_scene(j, "settle.json");
  EXPECT_DOUBLE_EQ(s.settle.rest_time, 0.5);
  EXPECT_DOUBLE_EQ(s.settle.run_time, 0.5 + 2 * 2.5);
  EXPECT_DOUBLE_EQ(s.thermal.start_time, 3.5);
  EXPECT_DOUBLE_EQ(s.duration, 8.5);
  EXPECT_EQ(s.steps, 300 + 550);
  j["time"]["duration"] = 2.0;  // the run after settling
  EXPECT_DOUBLE_EQ(build_scene(j, "d.json").settle.run_time, 2.0);
  EXPECT_EQ(build_scene(j, "d.json").steps, 500);
}

TEST(Scene, SolverCriterionIsImpulseOrVelocity) {
  json j = minimal_scene();
  EXPECT_EQ(build_scene(j, "s.json").solver.criterion, Criterion::Impulse);  // the default
  j["solver"] = {{"criterion", "velocity"}};
  EXPECT_EQ(build_scene(j, "s.json").solver.criterion, Criterion::Velocity);
  j["solver"]["criterion"] = "Quad";
  EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'solver.criterion': expected \"impulse\" or \"velocity\", got \"Quad\""));
  // solver.method: one method so far, named; any other is refused with the names known.
  j["solver"] = json::object();
  EXPECT_EQ(build_scene(j, "s.json").solver.method, SolverMethod::Nsgs);  // the default
  j["solver"]["method"] = "nsgs";
  EXPECT_EQ(build_scene(j, "s.json").solver.method, SolverMethod::Nsgs);
  j["solver"]["method"] = "pgs";
  EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'solver.method': expected \"nsgs\", got \"pgs\""));
}

TEST(Scene, SolverTangentialLawIsCreepOrSpringAndTheSpringNeedsTheWarmStart) {
  json j = minimal_scene();
  const SceneDef plain = build_scene(j, "s.json");
  EXPECT_EQ(plain.solver.tangential_law, TangentialLaw::Creep);  // the default
  EXPECT_EQ(plain.effective.at("solver").at("tangential_law"), "creep");
  j["solver"] = {{"tangential_law", "spring"}, {"compliance", 0.1}};
  EXPECT_EQ(build_scene(j, "s.json").solver.tangential_law, TangentialLaw::Spring);
  j["solver"]["tangential_law"] = "elastic";
  EXPECT_THAT(error_of(j),
              HasSubstr("scene.json: field 'solver.tangential_law': expected \"creep\" or \"spring\", got \"elastic\""));
  j["solver"] = {{"tangential_law", "spring"}, {"warm_start", false}};
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json: field 'solver.tangential_law'"),
                                 HasSubstr("while solver.warm_start is false")));
}

TEST(Scene, SolverStallFallbackIsPlainOrApgdAndApgdIsForTheRigidLaw) {
  json j = minimal_scene();
  const SceneDef plain = build_scene(j, "s.json");
  EXPECT_EQ(plain.solver.stall_fallback, StallFallback::Plain);  // the default: the bits of every scene before it
  EXPECT_EQ(plain.effective.at("solver").at("stall_fallback"), "plain");
  j["solver"] = {{"stall_fallback", "apgd"}};
  EXPECT_EQ(build_scene(j, "s.json").solver.stall_fallback, StallFallback::Apgd);
  j["solver"]["stall_fallback"] = "cg";
  EXPECT_THAT(error_of(j),
              HasSubstr("scene.json: field 'solver.stall_fallback': expected \"plain\" or \"apgd\", got \"cg\""));
  j["solver"] = {{"stall_fallback", "apgd"}, {"compliance", 0.01}};
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json: field 'solver.stall_fallback'"),
                                 HasSubstr("while solver.compliance > 0")));
}

TEST(Scene, SolverSlideNewtonStepsIsABudgetFromZeroToThirty) {
  json j = minimal_scene();
  const SceneDef exact = build_scene(j, "s.json");
  EXPECT_EQ(exact.solver.slide_newton_steps, 0);  // the default: the exact slide, the bits of every scene before it
  EXPECT_EQ(exact.effective.at("solver").at("slide_newton_steps"), 0);
  j["solver"] = {{"slide_newton_steps", 1}};
  EXPECT_EQ(build_scene(j, "s.json").solver.slide_newton_steps, 1);
  j["solver"]["slide_newton_steps"] = 31;
  EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'solver.slide_newton_steps'"));
  j["solver"]["slide_newton_steps"] = -1;
  EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'solver.slide_newton_steps'"));
  j["solver"]["slide_newton_steps"] = 1.5;
  EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'solver.slide_newton_steps'"));
}

TEST(Scene, DegeneratePolyhedronIsRefusedWithItsField) {
  json j = minimal_scene();
  j["particles"]["bodies"] = json::array(
      {{{"shape", "polyhedron"}, {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}}, {"position", {0, 0, 1}}}});
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("scene.json"), HasSubstr("particles.bodies[0].vertices")));
}

TEST(Scene, OverridesSetNestedFieldsAndAreChecked) {
  json j = minimal_scene();
  apply_override(j, "solver.p_gap=0.25", "scene.json");
  apply_override(j, "effects.friction=false", "scene.json");  // a section the scene did not have
  apply_override(j, "name=renamed", "scene.json");              // not JSON: taken as a string
  const SceneDef s = build_scene(j, "scene.json");
  EXPECT_DOUBLE_EQ(s.solver.p_gap, 0.25);
  EXPECT_DOUBLE_EQ(s.solver.compliance, 0.0);  // rigid unless a scene asks
  apply_override(j, "solver.compliance=0.03", "scene.json");
  EXPECT_DOUBLE_EQ(build_scene(j, "scene.json").solver.compliance, 0.03);
  EXPECT_DOUBLE_EQ(s.solver.manifold_reuse, 0.0);  // rebuilt every step unless a scene asks
  EXPECT_FALSE(s.effects.friction);
  EXPECT_EQ(s.name, "renamed");
  EXPECT_THROW(apply_override(j, "solver.p_gap", "scene.json"), SceneError);
  EXPECT_THROW(apply_override(j, "name.x=1", "scene.json"), SceneError);
}

TEST(Scene, UnknownFieldSuggestsTheClosestKnownOne) {
  json j = minimal_scene();
  j["solver"] = {{"tolerence", 1e-6}};
  EXPECT_THAT(error_of(j), HasSubstr("scene.json: field 'solver.tolerence': unknown field, did you mean "
                                     "'solver.tolerance'? (known fields here: tolerance, criterion,"));
  j["solver"] = {{"toleracne", 1e-6}};  // a transposition is one edit
  EXPECT_THAT(error_of(j), HasSubstr("did you mean 'solver.tolerance'?"));
  j = minimal_scene();
  j["time"]["dtt"] = 1;
  EXPECT_THAT(error_of(j), HasSubstr("field 'time.dtt': unknown field, did you mean 'time.dt'?"));
  j = minimal_scene();
  j["colour"] = 1;  // nothing close: no guess
  EXPECT_THAT(error_of(j), AllOf(HasSubstr("field 'colour': unknown field (known fields here: name,"),
                                 Not(HasSubstr("did you mean"))));
}

TEST(Scene, ErrorInsideAListedBodyNamesItsOriginOnce) {
  json j = minimal_scene();
  j["particles"]["bodies"][0]["radius"] = -0.5;
  EXPECT_EQ(error_of(j), "scene.json: field 'particles.bodies[0].radius': expected a finite positive number, got -0.5");
}

// load_scene with --set overrides: an error in what a --set wrote names the --set.
class SceneFile : public ::testing::Test {
 protected:
  std::string path = (std::filesystem::temp_directory_path() / "ratchet_scene_origin.json").string();
  void SetUp() override { write(minimal_scene()); }
  void TearDown() override { std::filesystem::remove(path); }
  void write(const json& j) const { std::ofstream(path) << j.dump(); }
  std::string load_error(const std::vector<std::string>& overrides) const {
    try {
      load_scene(path, overrides);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  }
  std::string from_set(const std::string& assignment) const {
    return "--set " + assignment + " (command-line option, applied to " + path + "): ";
  }
};

TEST_F(SceneFile, UnknownFieldFromSetNamesTheSetAndSuggests) {
  EXPECT_EQ(load_error({"solver.tolerence=1e-6"}).rfind(from_set("solver.tolerence=1e-6") +
                                                          "field 'solver.tolerence': unknown field, did you mean "
                                                          "'solver.tolerance'? (known fields here: ",
                                                      0),
            0u)
      << load_error({"solver.tolerence=1e-6"});
}

TEST_F(SceneFile, BadValueFromSetNamesTheSet) {
  EXPECT_EQ(load_error({"solver.p_gap=0.5", "solver.theta=2"}),
            from_set("solver.theta=2") + "field 'solver.theta': expected a number in [0.5, 1], got 2");
  // A whole section replaced by a --set: what it lacks is the --set's too.
  EXPECT_THAT(load_error({"time={\"dt\": 0.1}"}),
              HasSubstr(from_set("time={\"dt\": 0.1}") + "field 'time.duration': expected a positive duration"));
  // A --set that makes a section the file has not: its missing required fields.
  EXPECT_EQ(load_error({"settle.max_time=5"}).rfind(from_set("settle.max_time=5") + "field 'settle.ke_ratio'", 0), 0u);
  // Below a field the --set made: solver.tolerence did not exist in the file.
  EXPECT_EQ(load_error({"solver.tolerence.x=1"}).rfind(from_set("solver.tolerence.x=1") + "field 'solver.tolerence'", 0),
            0u);
}

TEST_F(SceneFile, ErrorsOfTheFileStillNameTheFile) {
  json j = minimal_scene();
  j["solver"] = {{"theta", 2}};
  write(j);
  // A --set elsewhere, or inside the same section, does not take the blame.
  for (const char* set : {"solver.p_gap=0.5", "solver.tolerance=1e-6", "seed=3"})
    EXPECT_EQ(load_error({set}), path + ": field 'solver.theta': expected a number in [0.5, 1], got 2") << set;
  j = minimal_scene();
  j["solver"] = {{"tolerence", 1e-6}};
  write(j);
  EXPECT_EQ(load_error({"solver.p_gap=0.5"}).rfind(path + ": field 'solver.tolerence': unknown field, did you mean", 0),
            0u);
  // A required field the file lacks, next to a --set in the same section: the file's.
  j = minimal_scene();
  j["time"].erase("duration");
  write(j);
  EXPECT_EQ(load_error({"time.dt=0.02"}).rfind(path + ": field 'time.duration'", 0), 0u);
}

TEST(Scene, LoadReportsSyntaxErrorsAndMissingFiles) {
  EXPECT_THROW(load_scene("/nonexistent/scene.json"), SceneError);
}

// Inputs the scene fuzzer found (tests/fuzz_findings/README.md): each is a clear
// SceneError naming the file, never another exception or a hang.
TEST(SceneFuzzFindings, AreSceneErrors) {
  // file, and what its error must contain (the file and the field)
  const std::vector<std::pair<std::string, std::string>> findings{
      {"scene_json_number_overflow.json", "scene_json_number_overflow.json: not valid JSON"},
      {"scene_lattice_int_overflow.json", "field 'particles.generate.region': expected at most 10^6 lattice sites"},
      {"scene_derived_duration_overflow.json",
       "scene_derived_duration_overflow.json: field 'thermal': expected at most 1e15 time steps"},
      {"scene_flat_box_half_extents.json",
       "scene_flat_box_half_extents.json: field 'particles.bodies[0].half_extents': the smallest half extent"},
  };
  for (const auto& [file, expected] : findings) {
    try {
      load_scene(std::string(RATCHET_FUZZ_FINDINGS) + "/" + file);
      ADD_FAILURE() << file << ": accepted";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

// Step counts beyond int64 (std::llround undefined) or below one step are refused naming
// the field the span came from, also when it is derived from the thermal protocol.
TEST(Scene, StepCountsOutOfRangeNameTheirField) {
  const auto error = [](const json& j) {
    try {
      build_scene(j, "s.json");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const json base = {{"name", "s"}, {"time", {{"dt", 0.01}, {"duration", 1.0}}},
                     {"particles", {{"bodies", {{{"shape", "sphere"}, {"radius", 0.5}, {"position", {0, 0, 1}}}}}}}};
  json huge = base;
  huge["time"]["duration"] = 1e300;
  EXPECT_EQ(error(huge).rfind("s.json: field 'time.duration': expected at most 1e15 time steps", 0), 0u) << error(huge);
  json derived = base;
  derived["time"].erase("duration");
  derived["thermal"] = {{"T0", 0}, {"T1", 1}, {"heat_time", 1e-9}, {"hold_time", 0}, {"cool_time", 1e-9}, {"cycles", 1},
                        {"alpha_p", 1e-4}, {"alpha_c", 1e-4}};
  EXPECT_EQ(error(derived).rfind("s.json: field 'thermal': expected at least one time step", 0), 0u) << error(derived);
  json settle = derived;
  settle["thermal"]["heat_time"] = 1.0;
  settle["thermal"]["cool_time"] = 1.0;
  settle["settle"] = {{"ke_ratio", 1e-6}, {"max_time", 1e300}};
  EXPECT_EQ(error(settle).rfind("s.json: field 'settle.max_time': expected at most 1e15 time steps", 0), 0u)
      << error(settle);
}

}  // namespace
}  // namespace ratchet
