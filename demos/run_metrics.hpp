#pragma once
// The run's summaries and metrics.json (docs/metrics.md): what run_scene
// accumulates frame by frame, the stage breakdown, and the JSON.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "demos/scene_runner.hpp"
#include "xpbd/health.hpp"
#include "xpbd_bullet/world.hpp"

namespace xpbd_demos::detail {

// ms per frame of every stage with work (SystemTimes order: xpbd::step()'s
// stages, then the bridge's), and "other" = the frames' stepping time not in
// any stage, over `frames` timed frames whose stepping took mean_ms on
// average.
std::vector<std::pair<std::string, double>> stage_breakdown(const xpbd_bullet::SystemTimes& t, double frames,
                                                            double mean_ms);

// The run's summaries, accumulated frame by frame (RunOptions::keep_series
// = false keeps nothing else).
class Summary {
 public:
  // The initial state (frame 0): the energy budget's start.
  void start(const FrameMetrics& f0) {
    health_.kinetic0 = f0.kinetic_energy;
    health_.potential0 = health_.potential_min = f0.potential_energy;
    if (!std::isfinite(f0.kinetic_energy) || !std::isfinite(f0.potential_energy)) health_.finite = false;
  }
  // J: energy the scene can put in from outside over the run (moving
  // kinematic bodies), added to the budget.
  void set_energy_input(double e) { health_.energy_input = e; }
  // Frame k >= 1; a non-finite last frame is skipped (a run that went
  // non-finite keeps the values of its finite frames).
  void add(const FrameMetrics& f) {
    if (!std::isfinite(f.max_strain) || !std::isfinite(f.kinetic_energy) || !std::isfinite(f.potential_energy)) {
      health_.finite = false;
      return;
    }
    if (f.substeps) {
      substeps_sum_ += *f.substeps;
      substeps_max_ = std::max(substeps_max_, *f.substeps);
      ++substeps_count_;
    }
    if (!f.tolerance_met) ++missed_;
    health_.max_strain = std::max(health_.max_strain, f.max_strain);
    health_.kinetic_max = std::max(health_.kinetic_max, f.kinetic_energy);
    health_.potential_min = std::min(health_.potential_min, f.potential_energy);
    max_strain_ = std::max(max_strain_, f.max_strain);
    max_penetration_ = std::max(max_penetration_, f.max_penetration);
    mean_sum_ += f.mean_strain;
    ++counted_;
    if (f.min_particle_distance)
      min_distance_ = min_distance_ ? std::min(*min_distance_, *f.min_particle_distance) : *f.min_particle_distance;
  }
  void add_ms(double ms) {
    ms_sum_ += ms;
    ++ms_count_;
    const double b = std::floor(std::log(std::max(ms, kLowMs) / kLowMs) / std::log(kBinRatio));
    ++bins_[std::size_t(std::clamp(b, 0.0, double(kBins - 1)))];
  }
  void apply(RunResult& r) const {
    if (ms_count_ > 0) {
      r.wall_ms_mean = ms_sum_ / double(ms_count_);
      r.wall_ms_median = r.frame_ms.empty() ? histogram_median() : exact_median(r.frame_ms);
    }
    r.max_strain = max_strain_;
    r.max_penetration = max_penetration_;
    if (counted_ > 0) r.mean_strain = mean_sum_ / counted_;
    r.min_particle_distance = min_distance_;
    if (substeps_count_ > 0) {
      r.mean_substeps = substeps_sum_ / double(substeps_count_);
      r.max_substeps_used = substeps_max_;
      // projections_per_frame was counted at the starting substeps.
      r.projections_per_frame = static_cast<long long>(std::llround(
          double(r.projections_per_frame) / double(r.options.substeps) * r.mean_substeps));
    }
    r.frames_tolerance_missed = missed_;
    xpbd::HealthObservation h = health_;
    h.finite = h.finite && r.finite;
    r.status = xpbd::health_name(xpbd::classify(h, r.options.health));
    r.energy_ratio = h.kinetic_max / xpbd::energy_budget(h, r.options.health);
  }

 private:
  // Log-spaced bins of 1% from 1e-4 ms (everything below in the first,
  // above 1e5 ms in the last); the median is its bin's geometric centre.
  static constexpr double kLowMs = 1e-4, kBinRatio = 1.01;
  static constexpr int kBins = 2090;
  static double exact_median(std::vector<double> t) {
    std::sort(t.begin(), t.end());
    const std::size_t n = t.size();
    return n % 2 ? t[n / 2] : (t[n / 2 - 1] + t[n / 2]) / 2;
  }
  double histogram_median() const {
    const std::uint64_t half = (ms_count_ + 1) / 2;
    std::uint64_t seen = 0;
    for (int b = 0; b < kBins; ++b) {
      seen += bins_[std::size_t(b)];
      if (seen >= half) return kLowMs * std::pow(kBinRatio, double(b) + 0.5);
    }
    return kLowMs * std::pow(kBinRatio, double(kBins));
  }
  double max_strain_ = 0, max_penetration_ = 0, mean_sum_ = 0, ms_sum_ = 0;
  int counted_ = 0;
  std::uint64_t ms_count_ = 0;
  std::optional<double> min_distance_;
  xpbd::HealthObservation health_;
  double substeps_sum_ = 0;
  int substeps_max_ = 0, substeps_count_ = 0, missed_ = 0;
  std::array<std::uint64_t, kBins> bins_{};
};

}  // namespace xpbd_demos::detail
