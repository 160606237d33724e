#include "demos/run_metrics.hpp"

#include <nlohmann/json.hpp>

#include "demos/run_forces.hpp"

namespace xpbd_demos {

using xpbd::Real;

namespace detail {

std::vector<std::pair<std::string, double>> stage_breakdown(const xpbd_bullet::SystemTimes& t, double frames,
                                                            double mean_ms) {
  std::vector<std::pair<std::string, double>> out;
  double staged = 0;
  auto add = [&](const char* name, std::int64_t ns, std::int64_t calls) {
    if (calls == 0) return;  // no work: not part of this scene's cost
    const double ms = double(ns) * 1e-6 / frames;
    out.emplace_back(name, ms);
    staged += ms;
  };
  for (std::size_t k = 0; k < xpbd::stage::count; ++k) add(xpbd::stage_name(k), t.step.ns[k], t.step.calls[k]);
  for (std::size_t k = 0; k < xpbd_bullet::SystemTimes::count; ++k)
    add(xpbd_bullet::SystemTimes::name(k), t.ns[k], t.calls[k]);
  out.emplace_back("other", mean_ms - staged);  // stages nest inside the frame: >= 0
  return out;
}

}  // namespace detail

nlohmann::json frame_json(int frame, const FrameMetrics& f, std::optional<double> wall_ms) {
  nlohmann::json e = {{"frame", frame},
                      {"time", f.time},
                      {"kinetic_energy", f.kinetic_energy},
                      {"potential_energy", f.potential_energy},
                      {"max_strain", f.max_strain},
                      {"mean_strain", f.mean_strain},
                      {"max_penetration", f.max_penetration}};
  if (f.min_particle_distance) e["min_particle_distance"] = *f.min_particle_distance;
  if (f.substeps) e["substeps"] = *f.substeps;
  if (wall_ms) e["wall_ms"] = *wall_ms;
  return e;
}

nlohmann::json to_json(const RunResult& r) {
  using nlohmann::json;
  auto opt_num = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  json frames = json::array();
  for (std::size_t k = 0; k < r.series.size(); ++k)
    frames.push_back(frame_json(int(k), r.series[k],
                                k >= 1 && k - 1 < r.frame_ms.size() ? std::optional<double>(r.frame_ms[k - 1])
                                                                    : std::nullopt));
  json j = {{"schema", "xpbd-demo/metrics/1"},
            {"scene", r.scene},
            {"solver", solver_name(r.options.solver)},
            {"scalar", sizeof(Real) == 8 ? "double" : "float"},
            {"dt", double(r.options.dt)},
            {"substeps", r.options.substeps},
            {"iterations", r.options.iterations},
            {"frames", r.options.frames},
            {"frames_completed", r.frames_completed},
            {"gravity", {double(r.gravity.x()), double(r.gravity.y()), double(r.gravity.z())}},
            {"particles", r.particles},
            {"bodies", r.bodies},
            {"distance_constraints", r.distance_constraints},
            {"wall_ms_per_frame", {{"median", r.wall_ms_median}, {"mean", r.wall_ms_mean}}},
            {"projections_per_frame", r.projections_per_frame},
            {"max_strain", r.max_strain},
            {"mean_strain", r.mean_strain},
            {"max_penetration", r.max_penetration},
            {"finite", r.finite},
            {"status", r.status},
            {"energy_ratio", r.energy_ratio},
            {"status_thresholds",
             {{"max_strain", r.options.health.max_strain}, {"energy_factor", r.options.health.energy_factor},
              {"energy_floor", r.options.health.energy_floor}}},
            {"solver_settings", r.solver_settings},
            {"notes", r.notes}};
  if (!r.series.empty()) j["per_frame"] = std::move(frames);
  if (r.particle_collision) j["min_particle_distance"] = opt_num(r.min_particle_distance);
  if (!r.stage_ms_per_frame.empty()) {
    json stages = json::object();
    for (const auto& [name, ms] : r.stage_ms_per_frame) stages[name] = ms;
    j["stage_ms_per_frame"] = std::move(stages);
  }
  if (r.forces) j["forces"] = forces_json(*r.forces);
  if (r.options.tolerance_on())
    j["tolerance"] = {{"strain", r.options.tolerance},
                      {"measure", r.options.tolerance_measure == ToleranceMeasure::residual ? "residual" : "strain"},
                      {"penetration", r.options.penetration_tolerance},
                      {"max_substeps", r.options.max_substeps},
                      {"mean_substeps", r.mean_substeps},
                      {"max_substeps_used", r.max_substeps_used},
                      {"frames_missed", r.frames_tolerance_missed}};
  return j;
}

}  // namespace xpbd_demos
