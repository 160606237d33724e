#pragma once
// "Model no more than a scene needs" (issue 6): given a sweep (the CSV of
// xpbd-compare run) and an error target, the cheapest setting of each method
// that meets it -- budget (substeps x iterations) and, where the sweep holds
// the scene at several resolutions (hanging_cloth_32, hanging_cloth_64), the
// resolution.
#include <optional>
#include <string>
#include <vector>

#include "demos/compare/compare.hpp"

namespace xpbd_compare {

// The error a sweep row is judged by (m): the RMS position error at time
// error_time (s), or at the final frame if error_time <= 0 or for the scenes
// with a static closed-form reference (static_reference: the chain, the
// catenary). NaN if the row has no
// sample at that time.
double judged_error(const Row& r, double error_time);

struct Cheapest {
  std::string method;
  std::optional<Row> row;  // empty: no run of this method met the target
  double error = 0;        // m, judged_error of row
};

// For each method in the rows of `scene` (the exact name, or every scene
// named scene + "_" + resolution, e.g. "hanging_cloth" -> hanging_cloth_32
// and hanging_cloth_64): the run with status ok, judged error <= target (m)
// and the smallest median wall time per frame; ties go to fewer projections.
// Methods in the order they first appear; the reference rows are not a method.
std::vector<Cheapest> cheapest(const std::vector<Row>& rows, const std::string& scene, double target,
                               double error_time);

}  // namespace xpbd_compare
