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

struct Cheapest {
  std::string method;
  std::optional<Row> row;  // empty: no run of this method met the target
  double error = 0;        // m, judged_error of row (compare.hpp)
};

// For each method in the rows of `scene` (the exact name, or every scene
// named scene + "_" + resolution, e.g. "hanging_cloth" -> hanging_cloth_32
// and hanging_cloth_64): the run with status ok, judged error <= target (m)
// (judged_error under `judge`) and the smallest median wall time per frame; ties go to fewer projections.
// Methods in the order they first appear; the reference rows are not a method.
std::vector<Cheapest> cheapest(const std::vector<Row>& rows, const std::string& scene, double target,
                               Judge judge);

}  // namespace xpbd_compare
