#include "demos/compare/cheapest.hpp"

#include <cmath>

namespace xpbd_compare {

std::vector<Cheapest> cheapest(const std::vector<Row>& rows, const std::string& scene, double target,
                               Judge judge) {
  auto matches = [&](const std::string& s) {
    return s == scene || (s.size() > scene.size() + 1 && s.compare(0, scene.size(), scene) == 0 &&
                          s[scene.size()] == '_');
  };
  std::vector<Cheapest> out;
  for (const Row& r : rows) {
    if (!matches(r.scene) || r.method == "reference") continue;
    Cheapest* c = nullptr;
    for (Cheapest& x : out)
      if (x.method == r.method) c = &x;
    if (!c) {
      out.push_back(Cheapest{r.method, std::nullopt, 0});
      c = &out.back();
    }
    if (r.status != "ok") continue;
    const double e = judged_error(r, judge);
    if (!(e <= target)) continue;  // also rejects NaN
    const bool better = !c->row || r.wall_ms_median < c->row->wall_ms_median ||
                        (r.wall_ms_median == c->row->wall_ms_median &&
                         r.projections_per_frame < c->row->projections_per_frame);
    if (better) {
      c->row = r;
      c->error = e;
    }
  }
  return out;
}

}  // namespace xpbd_compare
