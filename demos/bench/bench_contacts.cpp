// Contact generation benchmark of the Bullet bridge (docs/design.md sections 4 and 7).
//
// Scene: a 64 x 64 cloth (2 m x 2 m, 1 kg, no pins; xpbd::add_cloth_grid)
// draped over 100 static rigid bodies on a 10 x 10 grid 0.2 m apart:
// spheres (radius 7 cm) and boxes (half extent 6 cm) alternating, their
// centres at y = 0.1 m, in a btDiscreteDynamicsWorld with a DBVT broadphase.
// The cloth is dropped from y = 0.35 m and warmed up for 45 steps (0.75 s at
// 60 Hz), so that it lies on the bodies; that State, without the contacts of
// the last warm-up step, is the snapshot, and every timed call starts from
// it (docs/design.md principle 7). The summary prints the fastest particle's
// speed in it, as a check that the cloth lies still. The bodies are static,
// so nothing else in the Bullet world changes between calls.
//
// Benchmarks (each reports ns_per_particle_step = time / 4096 particles):
//   xpbd_step/no_contacts    one xpbd::step() of the cloth (10 substeps,
//                            1 iteration), no bodies and no contacts: the
//                            reference cost of the cloth itself;
//   xpbd_step/with_contacts  the same step with the contacts (and body
//                            shadows) the bridge generated from the snapshot:
//                            the cost of solving them;
//   bridge_step/brute_force  XpbdWorld::pre_solve + updateAction, i.e. what Bullet runs
//                            per internal step (broadphase candidates,
//                            particle-body queries, the step, the coupling),
//                            with ContactSettings::cull = false: every
//                            (particle, candidate) pair is queried, as before
//                            the culling existed;
//   bridge_step/culled       the same with cull = true (the default);
//   bridge_step/culled_no_refresh  the same with ContactSettings::refresh
//                            off: the difference is the refresh's per-substep
//                            pass over the particles (and its queries: the
//                            summary prints how many particles it passed);
//   bridge_step/culled_no_surface_edges  culled with
//                            ContactSettings::surface_edge_contacts off (on
//                            by default since 2026-11-29): the cloth's edges
//                            against the 50 boxes' edges are what the
//                            difference costs, search and solve;
//   contact_generation/...   the time pre_solve spends finding the
//                            contacts (XpbdWorld measures it around that
//                            code: StepStats::contact_seconds, wall clock),
//                            and as a cross-check bridge_step/... minus
//                            xpbd_step/with_contacts (medians), printed in
//                            the summary.
// Before timing, the program runs one bridge step from the snapshot in each
// mode and checks that both produce the same contacts (every field, in the
// same order) and the same body shadows; it exits with status 1 if not.
// The timed sections are measured in CPU time of the benchmark's thread
// (see thread_seconds). The summary prints every value as ns per particle
// per step and as a ratio to xpbd_step/no_contacts measured in the same run.
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

namespace {

// ContactSettings::cull, refresh and surface_edge_contacts of system id
// (settings are replaced as a whole).
void set_cull(xpbd_bullet::XpbdWorld& xw, xpbd_bullet::SystemId id, bool cull, bool refresh = true,
              bool surface_edges = xpbd_bullet::ContactSettings{}.surface_edge_contacts) {
  xpbd_bullet::SystemSettings s = xw.settings(id);
  s.contacts.cull = cull;
  s.contacts.refresh = refresh;
  s.contacts.surface_edge_contacts = surface_edges;
  xw.set_settings(id, s);
}

using namespace xpbd;
// The timed section is measured in CPU time of this thread, not wall time:
// the machine these numbers come from is shared with other builds, and a
// preempted step would otherwise count the other processes' time too.
double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

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
  xpbd_bullet::SystemId id;
  std::shared_ptr<const Model> model;
  State snapshot;       // cloth after the warm-up
  State with_contacts;  // snapshot + the bodies and contacts of one bridge step from it
  xpbd_bullet::StepStats culled, brute;  // stats of one bridge step from the snapshot, per mode
  bool same_contacts = false;            // both modes gave the same contacts and shadows
  Real vmax = 0;                         // m/s, fastest particle of the snapshot
  int edge_contacts = 0;                 // edge contacts of the culled bridge step (surface edges)

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
    // The State still holds the last warm-up step's contacts and body
    // shadows: without them it is the contact-free reference (a bridge step
    // rebuilds them from scratch anyway).
    snapshot.bodies.clear();
    snapshot.contacts.clear();
    snapshot.attachments.clear();
    snapshot.triangle_contacts.clear();
    snapshot.edge_contacts.clear();
    for (const Vec3& v : snapshot.v) vmax = std::max(vmax, v.norm());

    // One bridge step from the snapshot in each mode: their contacts, body
    // shadows and stats.
    auto bridge_step = [&](bool cull, xpbd_bullet::StepStats& stats) {
      xw->state(id) = snapshot;
      set_cull(*xw, id, cull);
      xw->pre_solve(kDt);
      xw->updateAction(&world, kDt);
      stats = xw->last_stats();
      State out = xw->state(id);
      xw->state(id) = snapshot;
      return out;
    };
    const State a = bridge_step(true, culled);
    const State b = bridge_step(false, brute);
    same_contacts = equal_contacts(a, b) && culled.shadows == brute.shadows &&
                    culled.contacts == brute.contacts && culled.candidates == brute.candidates;
    set_cull(*xw, id, true);
    with_contacts = snapshot;
    with_contacts.bodies = a.bodies;
    with_contacts.contacts = a.contacts;
    with_contacts.attachments = a.attachments;
    with_contacts.edge_contacts = a.edge_contacts;
    edge_contacts = int(a.edge_contacts.size());
  }

  // Field by field, exactly: both modes run the same narrowphase on the same
  // inputs, so any difference is a pair the culling dropped (or added).
  static bool equal_contacts(const State& a, const State& b) {
    if (a.contacts.size() != b.contacts.size() || a.bodies.size() != b.bodies.size() ||
        a.edge_contacts.size() != b.edge_contacts.size())
      return false;
    for (std::size_t k = 0; k < a.edge_contacts.size(); ++k) {
      const BodyEdgeContact &p = a.edge_contacts[k], &q = b.edge_contacts[k];
      if (p.p != q.p || p.a != q.a || p.b != q.b || p.out != q.out || p.thickness != q.thickness) return false;
    }
    for (std::size_t k = 0; k < a.contacts.size(); ++k) {
      const BodyContact &p = a.contacts[k], &q = b.contacts[k];
      if (p.particle != q.particle || p.body != q.body || p.r != q.r || p.n != q.n ||
          p.thickness != q.thickness || p.static_friction != q.static_friction ||
          p.dynamic_friction != q.dynamic_friction || p.restitution != q.restitution ||
          p.compliance != q.compliance)
        return false;
    }
    for (std::size_t k = 0; k < a.bodies.size(); ++k)
      if (a.bodies[k].x != b.bodies[k].x || a.bodies[k].q.coeffs() != b.bodies[k].q.coeffs() ||
          a.bodies[k].v != b.bodies[k].v || a.bodies[k].w != b.bodies[k].w)
        return false;
    return true;
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
  bs.counters["contacts"] = s.culled.contacts;
  bs.counters["candidates"] = s.culled.candidates;
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
    const double t0 = thread_seconds();
    step(*s.model, st, cfg);
    benchmark::ClobberMemory();
    const double dt = thread_seconds() - t0;
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  finish(bs, ns);
}

// XpbdWorld::pre_solve + updateAction: what Bullet calls once per internal step, with
// ContactSettings::cull on or off. Also reports the contact generation time
// XpbdWorld measures itself (StepStats::contact_seconds, wall clock).
void BM_bridge_step(benchmark::State& bs, bool cull, bool refresh, bool surface_edges) {
  Scene& s = scene();
  set_cull(*s.xw, s.id, cull, refresh, surface_edges);
  double ns = 0, generation = 0;
  long refreshed = 0;
  for (auto _ : bs) {
    s.xw->state(s.id) = s.snapshot;  // restore (untimed): same sizes, no allocation
    const double t0 = thread_seconds();
    s.xw->pre_solve(kDt);
    s.xw->updateAction(&s.world, kDt);
    benchmark::ClobberMemory();
    const double dt = thread_seconds() - t0;
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
    generation += s.xw->last_stats().contact_seconds * 1e9;
    refreshed += s.xw->last_stats().refreshed;
  }
  s.xw->state(s.id) = s.snapshot;
  set_cull(*s.xw, s.id, true);
  finish(bs, ns);
  bs.counters["queries"] = cull ? s.culled.queries : s.brute.queries;
  bs.counters["refreshed_per_step"] = double(refreshed) / double(bs.iterations());
  bs.counters["generation_ns_per_particle_step"] =
      generation / (double(s.model->num_particles()) * double(bs.iterations()));
}

// Console output as usual, plus a summary in ns per particle per step
// (median of repetitions when asked for), the contact generation cost, and
// the ratio of each to the contact-free xpbd::step of this run.
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
      if (median || !e.median) {
        const auto g = r.counters.find("generation_ns_per_particle_step");
        e = Entry{it->second.value, g == r.counters.end() ? -1.0 : g->second.value, median};
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void summary() const {
    const auto get = [&](const char* n, bool generation = false) {
      const auto it = results_.find(n);
      if (it == results_.end()) return -1.0;
      return generation ? it->second.generation : it->second.value;
    };
    const double ref = get("xpbd_step/no_contacts");
    const double with = get("xpbd_step/with_contacts");
    const double brute = get("bridge_step/brute_force");
    const double culled = get("bridge_step/culled");
    const double no_refresh = get("bridge_step/culled_no_refresh");
    const double no_edges = get("bridge_step/culled_no_surface_edges");
    if (ref <= 0 || with <= 0) return;
    const Scene& s = scene();
    std::printf("\n64 x 64 cloth over 100 static bodies (fastest particle of the snapshot: %.2f m/s)\n"
                "  %d candidates, %d contacts and %d surface edge contacts per step; narrowphase queries: %d brute "
                "force, %d culled\n"
                "ns per particle per step (medians) and ratio to xpbd_step/no_contacts (same run)\n",
                double(s.vmax), s.culled.candidates, s.culled.contacts, s.edge_contacts, s.brute.queries,
                s.culled.queries);
    const auto row = [&](const char* n, double v) {
      std::printf("%-58s %10.1f %8.3f\n", n, v, v / ref);
    };
    row("xpbd_step/no_contacts", ref);
    row("xpbd_step/with_contacts", with);
    row("contact_solve (with - no_contacts)", with - ref);
    if (brute > 0) row("bridge_step/brute_force", brute);
    if (culled > 0) row("bridge_step/culled", culled);
    if (no_refresh > 0) row("bridge_step/culled_no_refresh", no_refresh);
    if (no_edges > 0) row("bridge_step/culled_no_surface_edges", no_edges);
    if (culled > 0 && no_refresh > 0)
      std::printf("bridge step with the contact refresh / without: %.3f\n", culled / no_refresh);
    if (culled > 0 && no_edges > 0)
      std::printf("bridge step with surface edge contacts / without: %.3f\n", culled / no_edges);
    // Measured inside pre_solve, around the contact search only.
    const double gen_brute = get("bridge_step/brute_force", true);
    const double gen_culled = get("bridge_step/culled", true);
    if (gen_brute > 0) row("contact_generation/brute_force (timed, wall)", gen_brute);
    if (gen_culled > 0) row("contact_generation/culled (timed, wall)", gen_culled);
    const double gen_no_edges = get("bridge_step/culled_no_surface_edges", true);
    if (gen_no_edges > 0) row("contact_generation/culled_no_surface_edges (timed, wall)", gen_no_edges);
    // Cross-check: the difference of two whole steps (noisy when small).
    if (brute > 0) row("contact_generation/brute_force (bridge - with)", brute - with);
    if (culled > 0) row("contact_generation/culled (bridge - with)", culled - with);
    if (gen_brute > 0 && gen_culled > 0)
      std::printf("contact generation (timed), brute force / culled: %.1f\n", gen_brute / gen_culled);
  }

 private:
  struct Entry {
    double value = 0;        // ns per particle per step, thread CPU time
    double generation = -1;  // ns per particle per step spent finding contacts (wall), or -1
    bool median = false;
  };
  std::map<std::string, Entry> results_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  const Scene& s = scene();
  std::printf("contacts from the snapshot: %d culled, %d brute force (%d and %d narrowphase queries)\n",
              s.culled.contacts, s.brute.contacts, s.culled.queries, s.brute.queries);
  if (!s.same_contacts) {
    std::fprintf(stderr, "bench_contacts: the culled contacts differ from the brute-force ones\n");
    return 1;
  }
  std::printf("contact sets identical (every field, same order)\n");

  benchmark::RegisterBenchmark("xpbd_step/no_contacts", BM_xpbd_step, false)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("xpbd_step/with_contacts", BM_xpbd_step, true)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  const bool edges = xpbd_bullet::ContactSettings{}.surface_edge_contacts;  // the default
  benchmark::RegisterBenchmark("bridge_step/brute_force", BM_bridge_step, false, true, edges)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("bridge_step/culled", BM_bridge_step, true, true, edges)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("bridge_step/culled_no_refresh", BM_bridge_step, true, false, edges)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("bridge_step/culled_no_surface_edges", BM_bridge_step, true, true, false)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.summary();
  benchmark::Shutdown();
  return 0;
}
