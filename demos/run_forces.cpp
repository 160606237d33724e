#include "demos/run_forces.hpp"

#include <algorithm>
#include <numeric>

#include <nlohmann/json.hpp>

#include "demos/scene_spec.hpp"

namespace xpbd_demos {

using nlohmann::json;
using xpbd::Vec3;

RunForces read_forces(const SceneSpec& spec, const xpbd::Model& model, const xpbd::State& state,
                      const Vec3& gravity, std::vector<std::string>& notes) {
  RunForces f;
  f.substep = double(state.last_substep);
  f.pins = xpbd::pin_reactions(model, state, gravity);
  f.max_by_type = xpbd::max_constraint_forces(model, state);
  const auto att = xpbd::attachment_forces(model, state);
  bool match = att.size() == spec.attachments.size();
  for (std::size_t k = 0; match && k < att.size(); ++k) match = att[k].particle == spec.attachments[k].particle;
  if (!match) {
    notes.push_back("forces: the solver's attachments (" + std::to_string(att.size()) +
                    ") do not match the scene's (" + std::to_string(spec.attachments.size()) +
                    "); attachment forces left out");
    return f;
  }
  for (std::size_t k = 0; k < att.size(); ++k) {
    RunAttachmentForce a;
    a.attachment = static_cast<int>(k);
    a.particle = att[k].particle;
    a.body = spec.attachments[k].body;
    if (a.body >= 0 && static_cast<std::size_t>(a.body) < spec.bodies.size())
      a.body_name = spec.bodies[static_cast<std::size_t>(a.body)].name;
    a.on_body = att[k].on_body;
    f.attachments.push_back(a);
  }
  return f;
}

namespace {

json vec(const Vec3& v) { return json::array({double(v.x()), double(v.y()), double(v.z())}); }

// {"count", "total", "listed": "all" | "largest", "items"}: every item, or the
// kForcesListed largest by magnitude when there are more than kForcesListedMax.
template <class T, class ForceOf, class ItemOf>
json bounded_list(const std::vector<T>& v, ForceOf force_of, ItemOf item_of) {
  Vec3 total = Vec3::Zero();
  for (const T& e : v) total += force_of(e);
  std::vector<std::size_t> idx(v.size());
  std::iota(idx.begin(), idx.end(), std::size_t(0));
  const bool all = v.size() <= kForcesListedMax;
  if (!all) {
    const auto n = static_cast<std::ptrdiff_t>(kForcesListed);
    std::partial_sort(idx.begin(), idx.begin() + n, idx.end(), [&](std::size_t a, std::size_t b) {
      return force_of(v[a]).norm() > force_of(v[b]).norm();
    });
    idx.resize(kForcesListed);
  }
  json items = json::array();
  for (std::size_t k : idx) items.push_back(item_of(v[k]));
  return {{"count", v.size()}, {"total", vec(total)}, {"listed", all ? "all" : "largest"}, {"items", items}};
}

}  // namespace

json forces_json(const RunForces& f) {
  json pins = bounded_list(
      f.pins, [](const xpbd::PinReaction& p) { return p.force; },
      [](const xpbd::PinReaction& p) {
        return json{{"particle", p.particle},
                    {"pin", p.pin},
                    {"force", vec(p.force)},
                    {"magnitude", double(p.force.norm())},
                    {"from_balance", p.from_balance}};
      });
  json atts = bounded_list(
      f.attachments, [](const RunAttachmentForce& a) { return a.on_body; },
      [](const RunAttachmentForce& a) {
        json e = {{"attachment", a.attachment},
                  {"particle", a.particle},
                  {"body", a.body},
                  {"on_body", vec(a.on_body)},
                  {"on_particle", vec(-a.on_body)},
                  {"magnitude", double(a.on_body.norm())}};
        if (!a.body_name.empty()) e["body_name"] = a.body_name;
        return e;
      });
  json types = json::object();
  for (const xpbd::MaxConstraintForce& m : f.max_by_type) {
    if (m.count == 0) continue;
    types[m.type] = {{"max", double(m.force)}, {"unit", m.unit}, {"element", m.element}, {"count", m.count}};
  }
  return {{"substep", f.substep}, {"pins", pins}, {"attachments", atts}, {"max_constraint_force", types}};
}

}  // namespace xpbd_demos
