// Rigid features against a cloth's collision triangles: the loop over every
// triangle against the hierarchy of the triangles (built by FCL, refitted
// every step) with a grid per body
// (ContactSettings::triangle_bvh_from; docs/feature-contacts.md).
//
// Scene, per cloth size n x n (the arguments; by default 4 .. 128): a 2 m x 2 m cloth (1 kg, the
// compliances of bench_contacts' cloth) with collision triangles, dropped
// from 0.35 m onto 50 static boxes (half extent 6 cm: 8 corners as
// features, and 12 edges against the cloth's edges; docs/edge-contacts.md)
// on the black squares of a
// 10 x 10 grid 0.2 m apart, at 60 Hz with 10 substeps x 1 iteration. After
// 45 steps it lies on them; that state is the snapshot every timed call
// starts from. Per size and mode (loop, hierarchy), one bridge step from the
// snapshot (XpbdWorld::pre_solve + updateAction, what Bullet runs per
// internal step) is repeated, and the contact generation time the bridge
// measures itself (StepStats::contact_seconds: broadphase, particle and
// triangle contacts) is kept; the cloth's own step (xpbd::step from the
// snapshot, no bodies, no contacts) is timed the same way. Printed: medians
// in ms, and each contact time over the cloth's step measured in the same
// run; then the hierarchy's whole bridge step (its contacts and the XPBD
// solve with them, wall clock); last, the cloth's step element by element
// (StepConfig::levels off: what the cloth step cost before the array order
// ran over its levels, docs/bench-levels.md) and the hierarchy's contacts
// over it. Before timing, both modes must give the same triangle and edge contacts, or
// the program exits with status 1.
//
//   cmake --build build/double --target bench_triangles && build/double/demos/bench/bench_triangles [n ...]
//
// `--threads T` (first) adds columns: the hierarchy's contact generation
// with a pool of T threads (SystemSettings::workers, which the contact
// search and the coloured sweep share), and the cloth's coloured step on the
// same pool, each against the one-thread figures of the same run.
//
// For a profiler: `bench_triangles --profile n` runs only the hierarchy's
// bridge step on the n x n cloth, 300 times, and prints nothing else (the
// loop mode would dominate a profile of the whole program):
//   perf record -g build/double/demos/bench/bench_triangles --profile 64
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

namespace {

using namespace xpbd;

constexpr Real kDt = Real(1) / Real(60);
constexpr int kRepeats = 15;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A bridge step's contacts of the rigid features and edges.
struct Found {
  std::vector<BodyTriangleContact> triangle;
  std::vector<BodyEdgeContact> edge;
};

struct Scene {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  btBoxShape box{btVector3(Real(0.06), Real(0.06), Real(0.06))};
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::unique_ptr<xpbd_bullet::XpbdWorld> xw;
  xpbd_bullet::SystemId id;
  std::shared_ptr<const Model> model;
  State snapshot;
  int triangles = 0;
  std::unique_ptr<Workers> pool;  // --threads

  explicit Scene(int n, int threads = 1) {
    if (threads > 1) pool = std::make_unique<Workers>(threads);
    world.setGravity(btVector3(0, Real(-9.81), 0));
    for (int i = 0; i < 10; ++i)
      for (int k = 0; k < 10; ++k) {
        if ((i + k) % 2) continue;
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, &box);
        info.m_startWorldTransform.setOrigin(
            btVector3((Real(i) - Real(4.5)) * Real(0.2), Real(0.1), (Real(k) - Real(4.5)) * Real(0.2)));
        bodies.emplace_back(new btRigidBody(info));
        world.addRigidBody(bodies.back().get());
      }
    SceneDesc scene;
    ClothGridDesc d;
    d.nx = d.ny = n;
    d.size_u = d.size_v = 2;
    d.u = Vec3::UnitX();
    d.v = Vec3::UnitZ();
    d.origin = Vec3(-1, Real(0.35), -1);
    d.mass = 1;
    d.stretch.compliance = Real(1e-6);
    d.shear_mat.compliance = Real(1e-5);
    d.bend_mat.compliance = Real(1e-4);
    d.collision_triangles = true;
    add_cloth_grid(scene, d);
    model = std::make_shared<Model>(compile(scene));
    triangles = int(model->collision_triangles.size());
    xw = std::make_unique<xpbd_bullet::XpbdWorld>(world);
    id = xw->add_system(model, make_state(*model), settings(0));
    for (int i = 0; i < 45; ++i) world.stepSimulation(kDt, 1, kDt);
    snapshot = xw->state(id);
  }
  ~Scene() {
    xw.reset();
    for (auto& b : bodies) world.removeRigidBody(b.get());
  }

  // pool: threads for the contact search (and the coloured sweep they need).
  static xpbd_bullet::SystemSettings settings(int bvh_from, Workers* pool = nullptr) {
    xpbd_bullet::SystemSettings s;  // 10 substeps x 1 iteration, default contacts
    s.contacts.triangle_bvh_from = bvh_from;
    s.workers = pool;
    s.coloured = pool != nullptr;
    return s;
  }

  // One bridge step from the snapshot; returns the contact generation time (s).
  // contacts: if given, gets the step's triangle and edge contacts.
  // threaded: on the pool. whole: if given, gets the whole step's time (s):
  // the contacts and the XPBD solve with them.
  double bridge_step(bool bvh, Found* contacts = nullptr, bool threaded = false, double* whole = nullptr) {
    xw->set_settings(id, settings(bvh ? 0 : std::numeric_limits<int>::max(), threaded ? pool.get() : nullptr));
    xw->state(id) = snapshot;
    const auto t0 = std::chrono::steady_clock::now();
    xw->pre_solve(kDt);
    if (contacts) *contacts = {xw->state(id).triangle_contacts, xw->state(id).edge_contacts};
    xw->updateAction(&world, kDt);
    if (whole) *whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double s = xw->last_stats().contact_seconds;
    xw->state(id) = snapshot;
    return s;
  }

  // threaded: coloured, on the pool. levels: StepConfig::levels (off: the
  // array order element by element, the cloth step before the levels).
  double cloth_step(bool threaded = false, bool levels = true) {
    State st = snapshot;
    st.bodies.clear();
    st.contacts.clear();
    st.attachments.clear();
    st.triangle_contacts.clear();
    st.edge_contacts.clear();
    StepConfig c;
    c.dt = kDt;
    c.substeps = 10;
    c.gravity = Vec3(0, Real(-9.81), 0);
    c.coloured = threaded;
    c.levels = levels;
    c.workers = threaded ? pool.get() : nullptr;
    const auto t0 = std::chrono::steady_clock::now();
    step(*model, st, c);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
};

bool same(const Found& x, const Found& y) {
  const auto& a = x.triangle;
  const auto& b = y.triangle;
  if (a.size() != b.size() || x.edge.size() != y.edge.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].body != b[k].body || a[k].r != b[k].r || a[k].tri != b[k].tri || a[k].side != b[k].side ||
        a[k].thickness != b[k].thickness)
      return false;
  for (std::size_t k = 0; k < x.edge.size(); ++k) {
    const BodyEdgeContact &e = x.edge[k], &f = y.edge[k];
    if (e.body != f.body || e.a != f.a || e.b != f.b || e.p != f.p || e.out != f.out || e.thickness != f.thickness ||
        e.reach != f.reach || e.closing_speed != f.closing_speed)
      return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 1;
  int first = 1;
  if (argc >= 3 && std::string(argv[1]) == "--threads") {
    threads = std::atoi(argv[2]);
    if (threads < 2) {
      std::fprintf(stderr, "bench_triangles: --threads '%s' is not an integer >= 2\n", argv[2]);
      return 2;
    }
    first = 3;
  }
  // Cloth sizes: the arguments (each >= 2), or the default ladder.
  if (argc == first + 2 && std::string(argv[first]) == "--profile") {
    const int n = std::atoi(argv[first + 1]);
    if (n < 2) {
      std::fprintf(stderr, "bench_triangles: cloth size '%s' is not an integer >= 2\n", argv[first + 1]);
      return 2;
    }
    Scene s(n, threads);
    double total = 0;
    for (int r = 0; r < 300; ++r) total += s.bridge_step(true, nullptr, threads > 1);
    std::printf("%d x %d: 300 hierarchy steps on %d thread(s), contact generation %.3f ms each\n", n, n, threads,
                total / 300 * 1e3);
    return 0;
  }
  std::vector<int> sizes = {4, 8, 16, 32, 64, 128};
  if (argc > first) sizes.clear();
  for (int i = first; i < argc; ++i) {
    const int n = std::atoi(argv[i]);
    if (n < 2) {
      std::fprintf(stderr, "bench_triangles: cloth size '%s' is not an integer >= 2\n", argv[i]);
      return 2;
    }
    sizes.push_back(n);
  }
  std::printf("| cloth | triangles | triangle contacts | cloth step (ms) | contacts, loop (ms) | contacts, hierarchy (ms) "
              "| loop / cloth step | hierarchy / cloth step | loop / hierarchy | bridge step, hierarchy (ms) "
              "| cloth step, element by element (ms) | hierarchy / that step |");
  if (threads > 1)
    std::printf(" hierarchy, %d threads (ms) | cloth step, coloured, %d threads (ms) | hierarchy / its %d threads "
                "| hierarchy, %d threads / cloth step | the same / coloured step, %d threads |",
                threads, threads, threads, threads, threads);
  std::printf("\n|---|---|---|---|---|---|---|---|---|---|---|---|%s\n", threads > 1 ? "---|---|---|---|---|" : "");
  for (const int n : sizes) {
    Scene s(n, threads);
    Found a, b, c;
    s.bridge_step(false, &a);
    s.bridge_step(true, &b);
    if (threads > 1) s.bridge_step(true, &c, true);
    if (!same(a, b) || (threads > 1 && !same(b, c))) {
      std::fprintf(stderr, "bench_triangles: %d x %d: the hierarchy's triangle or edge contacts differ from the loop's%s\n", n,
                   n, threads > 1 ? " (or the threads' from one thread's)" : "");
      return 1;
    }
    std::vector<double> loop, bvh, cloth, cloth_e, bvh_t, cloth_t, whole;
    for (int r = 0; r < kRepeats; ++r) {  // interleaved, so that load hits all of them alike
      loop.push_back(s.bridge_step(false));
      double w = 0;
      bvh.push_back(s.bridge_step(true, nullptr, false, &w));
      whole.push_back(w);
      cloth.push_back(s.cloth_step());
      cloth_e.push_back(s.cloth_step(false, false));
      if (threads > 1) {
        bvh_t.push_back(s.bridge_step(true, nullptr, true));
        cloth_t.push_back(s.cloth_step(true));
      }
    }
    const double l = median(loop) * 1e3, h = median(bvh) * 1e3, cs = median(cloth) * 1e3;
    const double ce = median(cloth_e) * 1e3;
    std::printf("| %d x %d | %d | %zu | %.3f | %.3f | %.3f | %.2f | %.2f | %.1f | %.3f | %.3f | %.2f |", n, n,
                s.triangles, a.triangle.size(), cs, l, h, l / cs, h / cs, l / h, median(whole) * 1e3, ce, h / ce);
    if (threads > 1) {
      const double ht = median(bvh_t) * 1e3, ct = median(cloth_t) * 1e3;
      std::printf(" %.3f | %.3f | %.2f | %.2f | %.2f |", ht, ct, h / ht, ht / cs, ht / ct);
    }
    std::printf("\n");
  }
  return 0;
}
