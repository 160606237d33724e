// Contact generation benchmark of the Bullet bridge (DESIGN.md sections 4 and 7).
//
// Scene: a 64 x 64 cloth (2 m x 2 m, 1 kg, no pins; xpbd::add_cloth_grid)
// draped over 100 static rigid bodies on a 10 x 10 grid 0.2 m apart:
// spheres (radius 7 cm) and boxes (half extent 6 cm) alternating, their
// centres at y = 0.1 m, in a btDiscreteDynamicsWorld with a DBVT broadphase.
// The cloth is dropped from y = 0.35 m and warmed up for 45 steps (0.75 s at
// 60 Hz), so that it lies on the bodies; that State is the snapshot, and
// every timed call starts from it (DESIGN.md principle 7). The bodies are
// static, so nothing else in the Bullet world changes between calls.
//
// Benchmarks (each reports ns_per_particle_step = time / 4096 particles):
//   xpbd_step/no_contacts    one xpbd::step() of the cloth (10 substeps,
//                            1 iteration), no bodies and no contacts: the
//                            reference cost of the cloth itself;
//   xpbd_step/with_contacts  the same step with the contacts (and body
//                            shadows) the bridge generated from the snapshot:
//                            the cost of solving them;
//   bridge_step              XpbdWorld::updateAction, i.e. what Bullet runs
//                            per internal step: broadphase candidates,
//                            particle-body queries, the step, the coupling;
//   contact_generation       bridge_step minus xpbd_step/with_contacts
//                            (medians), printed in the summary.
// The summary prints every value as ns per particle per step and as a ratio
// to xpbd_step/no_contacts measured in the same run.
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

namespace {

using namespace xpbd;
using Clock = std::chrono::steady_clock;

constexpr int kGrid = 64;
constexpr int kBodiesPerSide = 10;  // 100 bodies
constexpr Real kDt = Real(1) / Real(60);
constexpr int kWarmupSteps = 45;

// The Bullet world, the bodies and the XpbdWorld, built once.
struct Scene {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::unique_ptr<xpbd_bullet::XpbdWorld> xw;
  int id = -1;
  std::shared_ptr<const Model> model;
  State snapshot;       // cloth after the warm-up
  State with_contacts;  // snapshot + the bodies and contacts of one bridge step from it
  int candidates = 0, contacts = 0;

  Scene() {
    world.setGravity(btVector3(0, Real(-9.81), 0));
    const Real spacing = Real(0.2);
    for (int i = 0; i < kBodiesPerSide; ++i)
      for (int k = 0; k < kBodiesPerSide; ++k) {
        const Real x = (Real(i) - Real(kBodiesPerSide - 1) / 2) * spacing;
        const Real z = (Real(k) - Real(kBodiesPerSide - 1) / 2) * spacing;
        if ((i + k) % 2 == 0)
          shapes.emplace_back(new btSphereShape(Real(0.07)));
        else
          shapes.emplace_back(new btBoxShape(btVector3(Real(0.06), Real(0.06), Real(0.06))));
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shapes.back().get());
        info.m_startWorldTransform.setOrigin(btVector3(x, Real(0.1), z));
        bodies.emplace_back(new btRigidBody(info));
        world.addRigidBody(bodies.back().get());
      }

    SceneDesc scene;
    ClothGridDesc d;
    d.nx = d.ny = kGrid;
    d.size_u = d.size_v = 2;
    d.u = Vec3::UnitX();
    d.v = Vec3::UnitZ();
    d.origin = Vec3(-1, Real(0.35), -1);
    d.mass = 1;
    d.stretch.compliance = Real(1e-6);  // m/N, as bench_distance's compliant cloth
    d.shear_mat.compliance = Real(1e-5);
    d.bend_mat.compliance = Real(1e-4);
    add_cloth_grid(scene, d);
    auto m = std::make_shared<Model>(compile(scene));
    model = m;
    xw = std::make_unique<xpbd_bullet::XpbdWorld>(world);
    xpbd_bullet::SystemSettings set;  // 10 substeps, 1 iteration, default contact settings
    id = xw->add_system(model, make_state(*model), set);
    for (int i = 0; i < kWarmupSteps; ++i) world.stepSimulation(kDt, 1, kDt);
    snapshot = xw->state(id);
    // One bridge step from the snapshot: its contacts and body shadows.
    xw->updateAction(&world, kDt);
    candidates = xw->last_stats().candidates;
    contacts = xw->last_stats().contacts;
    with_contacts = snapshot;
    with_contacts.bodies = xw->state(id).bodies;
    with_contacts.contacts = xw->state(id).contacts;
    with_contacts.attachments = xw->state(id).attachments;
    xw->state(id) = snapshot;
  }

  ~Scene() {
    xw.reset();
    for (auto& b : bodies) world.removeRigidBody(b.get());
  }

  StepConfig step_config() const {
    StepConfig c;
    c.dt = kDt;
    c.substeps = 10;
    c.iterations = 1;
    c.gravity = Vec3(0, Real(-9.81), 0);
    return c;
  }
};

Scene& scene() {
  static Scene s;
  return s;
}

void finish(benchmark::State& bs, double ns) {
  const Scene& s = scene();
  const double n = double(s.model->num_particles());
  bs.counters["ns_per_particle_step"] = ns / (n * double(bs.iterations()));
  bs.counters["ms_per_step"] = ns * 1e-6 / double(bs.iterations());
  bs.counters["contacts"] = s.contacts;
  bs.counters["candidates"] = s.candidates;
}

// xpbd::step() alone, from `start` (restored, untimed, before every call).
void BM_xpbd_step(benchmark::State& bs, bool contacts) {
  Scene& s = scene();
  const State& start = contacts ? s.with_contacts : s.snapshot;
  State st = start;
  const StepConfig cfg = s.step_config();
  double ns = 0;
  for (auto _ : bs) {
    st = start;
    const auto t0 = Clock::now();
    step(*s.model, st, cfg);
    benchmark::ClobberMemory();
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  finish(bs, ns);
}

// XpbdWorld::updateAction: what Bullet calls once per internal step.
void BM_bridge_step(benchmark::State& bs) {
  Scene& s = scene();
  double ns = 0;
  for (auto _ : bs) {
    s.xw->state(s.id) = s.snapshot;  // restore (untimed): same sizes, no allocation
    const auto t0 = Clock::now();
    s.xw->updateAction(&s.world, kDt);
    benchmark::ClobberMemory();
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  s.xw->state(s.id) = s.snapshot;
  finish(bs, ns);
}

// Console output as usual, plus a summary in ns per particle per step
// (median of repetitions when asked for), the derived contact generation
// cost, and the ratio of each to the contact-free xpbd::step of this run.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const auto it = r.counters.find("ns_per_particle_step");
      if (it == r.counters.end()) continue;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (r.run_type == Run::RT_Aggregate && !median) continue;
      Entry& e = results_[r.run_name.function_name];
      if (median || !e.median) e = Entry{it->second.value, median};
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void summary() const {
    const auto get = [&](const char* n) {
      const auto it = results_.find(n);
      return it == results_.end() ? -1.0 : it->second.value;
    };
    const double ref = get("xpbd_step/no_contacts");
    const double with = get("xpbd_step/with_contacts");
    const double bridge = get("bridge_step");
    if (ref <= 0 || with <= 0 || bridge <= 0) return;
    const Scene& s = scene();
    std::printf("\n64 x 64 cloth over 100 static bodies: %d candidates, %d contacts per step\n"
                "ns per particle per step and ratio to xpbd_step/no_contacts (same run)\n",
                s.candidates, s.contacts);
    const auto row = [&](const char* n, double v) {
      std::printf("%-36s %10.1f %8.2f\n", n, v, v / ref);
    };
    row("xpbd_step/no_contacts", ref);
    row("xpbd_step/with_contacts", with);
    row("bridge_step", bridge);
    row("contact_generation (bridge - with)", bridge - with);
    row("contact_solve (with - no_contacts)", with - ref);
  }

 private:
  struct Entry {
    double value = 0;
    bool median = false;
  };
  std::map<std::string, Entry> results_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RegisterBenchmark("xpbd_step/no_contacts", BM_xpbd_step, false)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("xpbd_step/with_contacts", BM_xpbd_step, true)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("bridge_step", BM_bridge_step)->UseManualTime()->Unit(benchmark::kMillisecond);
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.summary();
  benchmark::Shutdown();
  return 0;
}
