#include "ratchet/run/run_output.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "ratchet/core/build_info.hpp"
#include "ratchet/observe/bed_geometry.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/observe/wall_pressure.hpp"

namespace ratchet {

std::string format_double(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

namespace {

bool ends_with(const std::string& name, const std::string& tail) {
  return name.size() >= tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
}

// A file's name without the ".partial" of an unfinished atomic write.
std::string without_partial(const std::string& name) {
  return ends_with(name, ".partial") ? name.substr(0, name.size() - 8) : name;
}

// The files a run writes (docs/output-format.md), final and .partial: an earlier run's
// would sit beside this run's .partial files and make the folder look complete.
bool is_run_output(const std::string& name) {
  const std::string base = without_partial(name);
  if (base == "timeseries.csv" || base == "bodies.csv" || base == "cycles.csv" || base == "wall_profile.csv" ||
      base == "bodies_shapes.json" || base == "checkpoint.state" || base == "stage_fields.csv")
    return true;
  return base.rfind("displacement_", 0) == 0 && base.size() > 17 && ends_with(base, ".csv");
}

// vtk/: the snapshots (.vtp; .vtk of older versions) and the .pvd indexes, final or .partial.
bool is_vtk_output(const std::string& name) {
  const std::string base = without_partial(name);
  if (base == "particles.pvd" || base == "contacts.pvd" || base == "container.pvd" || base == "force_chains.pvd")
    return true;
  return (ends_with(base, ".vtp") || ends_with(base, ".vtk")) &&
         (base.rfind("particles_", 0) == 0 || base.rfind("contacts_", 0) == 0 || base.rfind("container_", 0) == 0 ||
          base.rfind("force_chains_", 0) == 0);
}

}  // namespace

std::vector<std::string> remove_previous_outputs(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> removed;
  if (fs::remove(dir + "/run.json")) removed.push_back(dir + "/run.json");  // first: no longer complete
  std::vector<fs::path> doomed;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && is_run_output(e.path().filename().string())) doomed.push_back(e.path());
  if (fs::is_directory(dir + "/vtk"))
    for (const auto& e : fs::directory_iterator(dir + "/vtk"))
      if (e.is_regular_file() && is_vtk_output(e.path().filename().string())) doomed.push_back(e.path());
  std::sort(doomed.begin(), doomed.end());
  for (const fs::path& p : doomed)
    if (fs::remove(p)) removed.push_back(p.string());
  return removed;
}

RunOutput::RunOutput(const std::string& dir, const std::vector<std::string>& extra_columns) : dir_(dir) {
  std::filesystem::create_directories(dir_);
  timeseries_ = std::make_unique<AtomicFile>(dir_ + "/timeseries.csv");
  bodies_ = std::make_unique<AtomicFile>(dir_ + "/bodies.csv");
  auto& ts = timeseries_->stream();
  ts << "step,t,T,s_p,s_c,kinetic_energy,contacts,iterations,residual,wall_force_side,wall_force_bottom,"
        "wall_force_total,bed_height,pressure,max_overlap";
  for (const char* name : kPhaseNames) ts << ",time_" << name;
  for (const std::string& name : extra_columns) ts << ',' << name;
  ts << "\n";
  bodies_->stream() << "step,t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,scale\n";
}

std::unique_ptr<RunOutput> RunOutput::resume(const std::string& dir, const nlohmann::json& sizes) {
  std::unique_ptr<RunOutput> out(new RunOutput(dir));
  out->timeseries_ = std::make_unique<AtomicFile>(dir + "/timeseries.csv", sizes.at("timeseries.csv").get<std::uintmax_t>());
  out->bodies_ = std::make_unique<AtomicFile>(dir + "/bodies.csv", sizes.at("bodies.csv").get<std::uintmax_t>());
  return out;
}

nlohmann::json RunOutput::flush_sizes() {
  return {{"timeseries.csv", timeseries_->flush_size()}, {"bodies.csv", bodies_->flush_size()}};
}

void RunOutput::interrupt(const World& world, const nlohmann::json& summary) {
  timeseries_->keep();
  bodies_->keep();
  write_run_json(world, summary);
}

void RunOutput::write_timeseries_row(const World& world, const std::vector<double>& extra) {
  const SceneDef& sc = world.scene();
  const State& s = world.state();
  const StepStats& st = world.stats();
  auto& o = timeseries_->stream();
  const double H = bed_height(sc, s);
  o << s.step << ',' << format_double(s.t) << ',' << format_double(s.T) << ',' << format_double(s.s_p) << ','
    << format_double(s.s_c) << ',' << format_double(kinetic_energy(sc, s)) << ',' << st.contacts << ','
    << st.iterations << ',' << format_double(st.residual) << ',' << format_double(st.wall_force_side) << ','
    << format_double(st.wall_force_bottom) << ',' << format_double(st.wall_force_total) << ',' << format_double(H)
    << ',' << format_double(side_wall_pressure(sc, s, st.wall_force_side, H)) << ',' << format_double(st.max_overlap);
  for (double t : world.timers().last_step) o << ',' << format_double(t);
  for (double v : extra) o << ',' << format_double(v);
  o << '\n';
}

void RunOutput::write_bodies(const World& world) {
  const State& s = world.state();
  auto& o = bodies_->stream();
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    const Quat& q = s.q[i];
    o << s.step << ',' << format_double(s.t) << ',' << i;
    for (double v : {s.x[i].x(), s.x[i].y(), s.x[i].z(), q.w(), q.x(), q.y(), q.z(), s.v[i].x(), s.v[i].y(),
                     s.v[i].z(), s.w[i].x(), s.w[i].y(), s.w[i].z(), world.body_scale(static_cast<int>(i))})
      o << ',' << format_double(v);
    o << '\n';
  }
}

void RunOutput::finish(const World& world, const nlohmann::json& summary) {
  timeseries_->commit();
  bodies_->commit();
  write_run_json(world, summary);
}

void RunOutput::write_run_json(const World& world, const nlohmann::json& summary) const {
  nlohmann::json meta = run_metadata(world);
  for (auto it = summary.begin(); it != summary.end(); ++it) meta[it.key()] = it.value();
  write_file_atomic(dir_ + "/run.json", meta.dump(2) + "\n");
}

nlohmann::json engine_record() {
  return {{"name", "ratchet"},
          {"version", RATCHET_VERSION},
          {"build_type", RATCHET_BUILD_TYPE},
          {"commit", engine_commit()},
          {"source_hash", engine_source_hash()}};
}

std::string other_engine(const nlohmann::json& recorded) {
  const nlohmann::json mine = engine_record();
  auto field = [&](const char* key) {
    return recorded.is_object() && recorded.contains(key) && recorded.at(key).is_string() ? recorded.at(key).get<std::string>()
                                                                                        : std::string("none");
  };
  const std::string version = field("version"), source = field("source_hash");
  if (version == mine.at("version") && source == mine.at("source_hash")) return "";
  return "made by engine " + version + " source " + source + ", this is " + mine.at("version").get<std::string>() +
         " source " + mine.at("source_hash").get<std::string>();
}

nlohmann::json run_metadata(const World& world) {
  const SceneDef& sc = world.scene();
  nlohmann::json j;
  j["engine"] = engine_record();
  j["scene_file"] = sc.source;
  j["scene_hash"] = sc.hash;
  j["scene"] = sc.as_run;
  j["effective_scene"] = sc.effective;
  j["effects"] = {{"gravity", sc.effects.gravity},
                  {"friction", sc.effects.friction},
                  {"rotation", sc.effects.rotation},
                  {"particle_expansion", sc.effects.particle_expansion},
                  {"container_expansion", sc.effects.container_expansion}};
  nlohmann::json phases = nlohmann::json::array();
  const auto& timers = world.timers();
  const auto plan = world.plan();
  for (std::size_t p = 0; p < plan.size(); ++p)
    phases.push_back({{"name", plan[p].name}, {"active", plan[p].active}, {"reason", plan[p].reason},
                      {"calls", timers.calls[p]}, {"seconds", timers.seconds[p]}});
  j["phases"] = phases;
  j["bodies"] = sc.bodies.size();
  j["steps"] = world.state().step;
  j["counters"] = {{"tangential_solves", world.totals().tangential_solves},
                   {"solver_iterations", world.totals().total_iterations},
                   {"unconverged_steps", world.totals().unconverged_steps},
                   {"jammed_steps", world.totals().jammed_steps},
                   {"relaxed_steps", world.totals().relaxed_steps}};
  return j;
}

}  // namespace ratchet
