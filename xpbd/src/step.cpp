#include "xpbd/step.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <string>
#include <type_traits>

#include "xpbd/error.hpp"
#include "xpbd/rigid_solve.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/spatial_hash.hpp"
#include "xpbd/special_constraints.hpp"
#include "chains_solve.hpp"
#include "trees_solve.hpp"
#include "hierarchy.hpp"
#include "predict_kernel.hpp"
#include "refresh_paths.hpp"
#include "stream.hpp"

namespace xpbd {
namespace {

// The shortest text that reads back as the same number, e.g. "-2.5e-07"
// (std::to_string prints fixed 6 decimals, so that dt would read
// "-0.000000"; a stream with 9 digits would print float's -2.49999999e-07).
std::string num(Real v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

void check_state_matches(const Model& m, const State& s) {
  const auto n = static_cast<std::size_t>(m.num_particles());
  if (s.x.size() != n || s.x_prev.size() != n || s.v.size() != n)
    throw ConfigError("state: particle arrays have " + std::to_string(s.x.size()) +
                      " entries, model has " + std::to_string(n) + " (use make_state)");
  if (!s.f_ext.empty() && s.f_ext.size() != n)
    throw ConfigError("state.f_ext: has " + std::to_string(s.f_ext.size()) +
                      " entries, expected 0 or " + std::to_string(n));
  const std::size_t pins = m.get<Pin>().size();
  if (s.pin_target.size() != pins || s.pin_target_prev.size() != pins ||
      s.pin_target_now.size() != pins)
    throw ConfigError("state.pin_target: has " + std::to_string(s.pin_target.size()) +
                      " entries, model has " + std::to_string(pins) + " pins");
  bool ok = true;
  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    ok = ok && s.lambdas<T>().size() == m.get<T>().size();
  });
  if (!ok) throw ConfigError("state.lambda: sizes do not match the model (use make_state)");
}

// StepConfig::coloured needs a schedule covering every Distance,
// DihedralBending and Tether element (compile() makes one; a Model edited
// afterwards may not have it).
void check_colours(const Model& m) {
  const ColourSchedule& c = m.distance_colours;
  const std::size_t n = m.get<Distance>().size();
  if (c.order.size() != n || m.distance_by_colour.size() != n || m.distance_stream.size() != n ||
      c.begin.empty() ||
      c.begin.front() != 0 || static_cast<std::size_t>(c.begin.back()) != n)
    throw ConfigError("StepConfig.coloured: model.distance_colours covers " +
                      std::to_string(c.order.size()) + " elements, the model has " +
                      std::to_string(n) + " Distance elements (use compile)");
  const ColourSchedule& h = m.dihedral_colours;
  const std::size_t nh = m.get<DihedralBending>().size();
  if (h.order.size() != nh || m.dihedral_stream.size() != nh || h.begin.empty() || h.begin.front() != 0 ||
      static_cast<std::size_t>(h.begin.back()) != nh)
    throw ConfigError("StepConfig.coloured: model.dihedral_colours covers " + std::to_string(h.order.size()) +
                      " elements, the model has " + std::to_string(nh) + " DihedralBending elements (use compile)");
  const ColourSchedule& tc = m.tether_colours;
  const std::size_t nt = m.get<Tether>().size();
  if (tc.order.size() != nt || m.tether_stream.size() != nt || tc.begin.empty() || tc.begin.front() != 0 ||
      static_cast<std::size_t>(tc.begin.back()) != nt)
    throw ConfigError("StepConfig.coloured: model.tether_colours covers " + std::to_string(tc.order.size()) +
                      " elements, the model has " + std::to_string(nt) + " Tether elements (use compile)");
  detail::check_inv_mass_sums(m, "StepConfig.coloured");
}

// Pin targets at fraction t in [0, 1] of the step.
void interpolate_pin_targets(State& s, Real t) {
  for (std::size_t i = 0; i < s.pin_target.size(); ++i)
    // (1-t) a + t b rather than a + t (b - a): exact at t = 1, so a kinematic
    // pin ends every step exactly on the target the user set.
    s.pin_target_now[i] = (Real(1) - t) * s.pin_target_prev[i] + t * s.pin_target[i];
}

// v = (x - x_prev)/h, then optional drag.
//
// A time step that shrinks: the positions a step starts from carry the
// constraint and contact errors the previous steps left (what a sweep per
// substep does not remove, contacts within their slack). A substep removes
// part of that error and v = (x - x_prev)/h turns the removed distance into
// velocity, at 1/h: the same error removed in a substep 1000 times shorter
// gives 1000 times the speed (a draped cloth stepped once at 1e-4 s after
// 1/60 s flew up at 35 m/s). So while the step is shorter than
// State::velocity_step (the last step's dt, shortened as time passes:
// max(dt, ref - h, 0.99 ref) after each substep), a movable particle's
// velocity is its predicted one plus only blend = (dt / ref)^2 of the
// change the solve made: the residual's removal adds almost no speed, and
// the forces of the short substeps lose at most about the impulse of the
// window. blend = 1 (a step as long as the last, or longer) is the plain
// update. Kinematic particles take (x - x_prev)/h.
// (Split over cfg.workers when set.)
//
// As numbers: mode 0 = none, 1 = the plain update, 2 = the blended one.
struct VelocityUpdate {
  int mode = 0;
  Real scale = 0, inv_h = 0, keep = 1, blend = 1;
};

VelocityUpdate velocity_update(const StepConfig& cfg, Real h, Real blend) {
  VelocityUpdate u;
  u.mode = blend >= Real(1) ? 1 : 2;
  u.inv_h = Real(1) / h;
  u.keep = cfg.drag > Real(0) ? std::exp(-cfg.drag * h) : Real(1);
  u.scale = u.inv_h * u.keep;
  u.blend = blend;
  return u;
}

// One particle's new velocity from its substep's start xp, its end x, its
// velocity v and inverse mass w.
template <int kMode>
Vec3 updated_velocity(const Vec3& x, const Vec3& xp, const Vec3& v, Real w, const VelocityUpdate& u) {
  if constexpr (kMode == 1) {
    return (x - xp) * u.scale;
  } else {
    const Vec3 measured = (x - xp) * u.inv_h;
    return (w > Real(0) ? Vec3(v + u.blend * (measured - v)) : measured) * u.keep;
  }
}

// Pointers and values as arguments: predict_range says why.
template <int kMode>
void velocity_range(const Vec3* x, const Vec3* x_prev, const Real* inv_mass, Vec3* v, VelocityUpdate u,
                    std::size_t lo, std::size_t hi) {
  for (std::size_t i = lo; i < hi; ++i) v[i] = updated_velocity<kMode>(x[i], x_prev[i], v[i], inv_mass[i], u);
}

void update_velocities(const Model& m, State& s, const StepConfig& cfg, const VelocityUpdate& u) {
  const Vec3* const x = s.x.data();
  const Vec3* const x_prev = s.x_prev.data();
  const Real* const inv_mass = m.inv_mass.data();
  Vec3* const v = s.v.data();
  detail::split(cfg.workers, s.x.size(), 1, [=](std::size_t lo, std::size_t hi) {
    if (u.mode == 1)
      velocity_range<1>(x, x_prev, inv_mass, v, u, lo, hi);
    else
      velocity_range<2>(x, x_prev, inv_mass, v, u, lo, hi);
  }, detail::kMinParticlesPerTask);
}

// Symplectic Euler prediction: x_prev = x, v += h (g + f/m), x += h v.
// Kinematic particles (inverse mass 0) keep their velocity; a kinematic
// particle with a pin is placed on the pin's current target.
// Per particle, so split over cfg.workers when set (the same bits).
//
// `before` (mode 1 or 2): first the previous substep's velocity update,
// which step() leaves to this pass when nothing between the two reads or
// writes a particle's velocity: one pass over the particles instead of two,
// the same arithmetic per particle, the same bits.
//
// With `rec` (and `rec_prev`) it also writes the particle records of the
// coloured stream kernels (State::stream_x, stream_x_prev: x, y, z, inverse
// mass) with the predicted positions (and the substep's start), as
// pack_records would before the first sweep. The same bits either way.
void put_record(Real* r, const Vec3& x, Real w) { r[0] = x.x(), r[1] = x.y(), r[2] = x.z(), r[3] = w; }

// The loop over [lo, hi). Its pointers and values are arguments, so that
// they stay in registers: captured in the lambda that split() hands to the
// threads, they live in that closure, whose address escapes, and since any
// store through x, x_prev or v could change them, the compiler loaded them
// again in every iteration (11.7 % of a 64^2 cloth's step at 20 x 1 on one
// thread, measured with perf).
template <int kBefore, bool kRec, bool kRecPrev>
void predict_range(Vec3* x, Vec3* x_prev, Vec3* v, const Real* inv_mass, const Vec3* f, Vec3 g, Real h,
                   VelocityUpdate before, Real* rec, Real* rec_prev, std::size_t lo, std::size_t hi) {
  for (std::size_t i = lo; i < hi; ++i) {
    const Vec3 xi = x[i];
    const Real w = inv_mass[i];
    Vec3 vi;
    if constexpr (kBefore == 0)
      vi = v[i];
    else
      vi = updated_velocity<kBefore>(xi, x_prev[i], v[i], w, before);
    x_prev[i] = xi;
    if (w > Real(0)) {
      Vec3 a = g;
      if (f != nullptr) a += w * f[i];
      vi += h * a;
    }
    v[i] = vi;
    const Vec3 xn = xi + h * vi;
    x[i] = xn;
    if constexpr (kRec) put_record(rec + 4 * i, xn, w);
    if constexpr (kRecPrev) put_record(rec_prev + 4 * i, xi, w);
  }
}

template <int kBefore>
void predict_records(Vec3* x, Vec3* x_prev, Vec3* v, const Real* inv_mass, const Vec3* f, Vec3 g, Real h,
                     const VelocityUpdate& before, Real* rec, Real* rec_prev, std::size_t lo, std::size_t hi) {
  if (rec == nullptr)
    predict_range<kBefore, false, false>(x, x_prev, v, inv_mass, f, g, h, before, rec, rec_prev, lo, hi);
  else if (rec_prev == nullptr)
    predict_range<kBefore, true, false>(x, x_prev, v, inv_mass, f, g, h, before, rec, rec_prev, lo, hi);
  else
    predict_range<kBefore, true, true>(x, x_prev, v, inv_mass, f, g, h, before, rec, rec_prev, lo, hi);
}

void predict(const Model& m, State& s, const StepConfig& cfg, Real h, const VelocityUpdate& before, Real* rec,
             Real* rec_prev) {
  Vec3* const x = s.x.data();
  Vec3* const x_prev = s.x_prev.data();
  Vec3* const v = s.v.data();
  const Real* const inv_mass = m.inv_mass.data();
  const Vec3* const f = s.f_ext.empty() ? nullptr : s.f_ext.data();
  const Vec3 g = cfg.gravity;
  // The AVX-512 kernel (predict_avx512.cpp, the same bits) takes whole
  // batches of particles, this loop the rest.
#if XPBD_HAVE_AVX512_KERNEL
  const bool wide = detail::simd_level(cfg.simd) == detail::Simd::avx512 && !s.x.empty();
  detail::PredictArgs args;
  if (wide) {  // (no particles: no arrays to point into)
    args.x = x->data();
    args.x_prev = x_prev->data();
    args.v = v->data();
    args.inv_mass = inv_mass;
    args.f = f != nullptr ? f->data() : nullptr;
    for (int c = 0; c < 3; ++c) args.g[c] = g[c];
    args.h = h;
    args.before = before.mode;
    args.scale = before.scale, args.inv_h = before.inv_h, args.keep = before.keep, args.blend = before.blend;
    args.rec = rec;
    args.rec_prev = rec_prev;
  }
#endif
  detail::split(cfg.workers, s.x.size(), 1, [=](std::size_t lo, std::size_t hi) {
#if XPBD_HAVE_AVX512_KERNEL
    if (wide) lo = detail::predict_avx512(args, lo, hi);
#endif
    if (before.mode == 0)
      predict_records<0>(x, x_prev, v, inv_mass, f, g, h, before, rec, rec_prev, lo, hi);
    else if (before.mode == 1)
      predict_records<1>(x, x_prev, v, inv_mass, f, g, h, before, rec, rec_prev, lo, hi);
    else
      predict_records<2>(x, x_prev, v, inv_mass, f, g, h, before, rec, rec_prev, lo, hi);
  }, detail::kMinParticlesPerTask);
  const auto& pins = m.get<Pin>();
  for (std::size_t k = 0; k < pins.size(); ++k) {
    const Index i = pins[k].p[0];
    if (m.inv_mass[i] == Real(0)) {
      s.x[i] = s.pin_target_now[k];
      if (rec != nullptr) put_record(rec + 4 * std::size_t(i), s.x[i], m.inv_mass[i]);
    }
  }
}

void reset_multipliers(State& s, bool skip_distance, bool skip_dihedral, bool skip_tether) {
  for (std::size_t k = 0; k < s.lambda.size(); ++k)
    if (!(skip_distance && k == type_index_v<Distance>) && !(skip_dihedral && k == type_index_v<DihedralBending>) &&
        !(skip_tether && k == type_index_v<Tether>))
      std::fill(s.lambda[k].begin(), s.lambda[k].end(), Real(0));
  std::fill(s.self_collision.lambda.begin(), s.self_collision.lambda.end(), Real(0));
}

// Fewest elements per level, on average, for the array order to run over
// its levels (uses_levels). A rope (1 per level) stepped 0.89-0.94
// times as fast over its levels; cloths and tet boxes with 3.6 per level
// 1.2-1.3 times (docs/bench-levels.md).
constexpr std::size_t kMinPerLevel = 3;

// True where an XPBD array-order sweep of n elements runs over array
// order's levels `l` (Model::distance_levels, tether_levels) and their
// stream `st` with the vector kernel (StepConfig::levels): the same bits as
// the element-by-element kernel (model.hpp), faster. Not with the coloured
// sweep (its own order), nor PBD (no stream), nor simd off (the scalar
// kernels), nor on a CPU without a vector kernel; and only where the levels
// hold kMinPerLevel elements on average. A Model whose schedule does not
// cover its elements (edited after compile) takes the element-by-element
// kernel. (The Distance sweep also not with direct_chains, whose solve
// reads the coloured stream's multipliers: step() below.)
bool levels_apply(const ColourSchedule& l, const DistanceStream& st, std::size_t n, const StepConfig& cfg) {
  if (!cfg.levels || cfg.coloured || cfg.method != Method::xpbd || !cfg.simd) return false;
  if (n == 0 || l.order.size() != n || st.size() != n || st.inv_mass_sum.size() != n || l.begin.empty() ||
      l.begin.front() != 0 || static_cast<std::size_t>(l.begin.back()) != n)
    return false;
  if (detail::simd_level(true) == detail::Simd::scalar) return false;
  return n >= kMinPerLevel * static_cast<std::size_t>(l.num_colours());
}
bool distance_levels_apply(const Model& m, const StepConfig& cfg) {
  return !cfg.direct_chains && levels_apply(m.distance_levels, m.distance_level_stream, m.get<Distance>().size(), cfg);
}
bool tether_levels_apply(const Model& m, const StepConfig& cfg) {
  return levels_apply(m.tether_levels, m.tether_level_stream, m.get<Tether>().size(), cfg);
}

// One Gauss-Seidel sweep over every constraint type, in ConstraintTypes order
// (each type with elements is a stage of its own in StepConfig::times).
// StepConfig::coloured: Distance in the order of m.distance_colours, with
// XPBD over the compiled stream (stream.hpp; on cfg.workers when set), and
// with XPBD DihedralBending and Tether over their own streams in the order
// of m.dihedral_colours and m.tether_colours. `levels`, `tether_levels`
// (uses_levels): the array-order XPBD Distance or Tether sweep over the
// stream of m.distance_levels or m.tether_levels.
void solve_constraints(const Model& m, State& s, const SolveContext& sc, const StepConfig& cfg, bool levels,
                       bool tether_levels, bool first, StageTimes* times, int records_in) {
  const bool coloured = cfg.coloured;
  // What the particle records (State::stream_x, stream_x_prev) hold: after
  // a stream stage has copied them back, the positions (and the substep's
  // start, if that stage was damped), until an array-order stage moves a
  // particle. A stream stage then need not copy the particles in again:
  // 0 = stale, 1 = positions, 2 = positions and the substep's start.
  // records_in: what they hold as the sweep starts (predict writes them).
  int records = records_in;
  auto stream_stage = [&](bool damped, auto&& sweep) {
    const int need = damped ? 2 : 1;
    sweep(records < need);
    records = std::max(records, need);
  };
  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    const auto& cs = m.get<T>();
    if (cs.empty()) return;
    timed(times, stage::of<T>, true, [&] {
      if constexpr (!is_generic_constraint_v<T>) {
        solve_global_volumes(m, s, sc);  // GlobalVolume: variable arity, own kernel
        records = 0;
      } else {
        std::span<const T> span(cs);
        const bool damped = m.has_damping[type_index_v<T>];
        if constexpr (std::is_same_v<T, Distance>) {
          if (levels) {
            stream_stage(damped, [&](bool pack) {
              detail::stream_sweep(m, s, sc, damped, cfg.simd, first, pack, cfg.workers, true);
            });
            return;
          }
        } else if constexpr (std::is_same_v<T, Tether>) {
          if (tether_levels) {
            stream_stage(damped, [&](bool pack) {
              detail::tether_sweep(m, s, sc, damped, cfg.simd, first, pack, cfg.workers, true);
            });
            return;
          }
        }
        if (coloured && sc.method == Method::xpbd) {
          if constexpr (std::is_same_v<T, Distance>) {
            stream_stage(damped,
                         [&](bool pack) { detail::stream_sweep(m, s, sc, damped, cfg.simd, first, pack, cfg.workers); });
            return;
          } else if constexpr (std::is_same_v<T, DihedralBending>) {
            stream_stage(damped, [&](bool pack) {
              detail::dihedral_sweep(m, s, sc, damped, cfg.simd, first, pack, cfg.workers);
            });
            return;
          } else if constexpr (std::is_same_v<T, Tether>) {
            stream_stage(damped,
                         [&](bool pack) { detail::tether_sweep(m, s, sc, damped, cfg.simd, first, pack, cfg.workers); });
            return;
          }
        }
        records = 0;
        if constexpr (std::is_same_v<T, Distance>) {
          if (coloured) {
            const std::span<const T> by_colour(m.distance_by_colour);
            const std::span<const Index> order(m.distance_colours.order);
            if (damped)
              project_all_coloured<T, true>(by_colour, order, s.lambdas<T>(), sc);
            else
              project_all_coloured<T, false>(by_colour, order, s.lambdas<T>(), sc);
            return;
          }
        }
        if (damped)
          project_all<T, true>(span, s.lambdas<T>(), sc);
        else
          project_all<T, false>(span, s.lambdas<T>(), sc);
      }
    });
  });
}

}  // namespace

bool uses_levels(const Model& m, const StepConfig& cfg) {
  return distance_levels_apply(m, cfg) || tether_levels_apply(m, cfg);
}

void validate(const StepConfig& cfg) {
  if (!(cfg.dt > Real(0)) || !std::isfinite(cfg.dt))
    throw ConfigError("StepConfig.dt: must be finite and > 0, got " + num(cfg.dt));
  if (cfg.substeps < 1)
    throw ConfigError("StepConfig.substeps: must be >= 1, got " + std::to_string(cfg.substeps));
  if (cfg.iterations < 1)
    throw ConfigError("StepConfig.iterations: must be >= 1, got " +
                      std::to_string(cfg.iterations));
  if (!cfg.gravity.allFinite()) throw ConfigError("StepConfig.gravity: must be finite");
  if (!(cfg.drag >= Real(0)) || !std::isfinite(cfg.drag))
    throw ConfigError("StepConfig.drag: must be finite and >= 0, got " + num(cfg.drag));
  if (!(cfg.contact_margin >= Real(0)) || !std::isfinite(cfg.contact_margin))
    throw ConfigError("StepConfig.contact_margin: must be finite and >= 0, got " +
                      num(cfg.contact_margin));
  if (cfg.workers != nullptr && !cfg.coloured)
    throw ConfigError("StepConfig.workers: the threads split the coloured sweep; set coloured = true");
  if (cfg.direct_chains && cfg.method != Method::xpbd)
    throw ConfigError("StepConfig.direct_chains: needs method xpbd (the direct solve is XPBD's linearised system)");
  if (cfg.chain_passes < 1)
    throw ConfigError("StepConfig.chain_passes: must be >= 1, got " + std::to_string(cfg.chain_passes));
  if (!(cfg.chain_tolerance >= Real(0)) || !std::isfinite(cfg.chain_tolerance))
    throw ConfigError("StepConfig.chain_tolerance: must be finite and >= 0, got " + num(cfg.chain_tolerance));
  if (!(cfg.hierarchy_slack >= Real(0)) || !std::isfinite(cfg.hierarchy_slack))
    throw ConfigError("StepConfig.hierarchy_slack: must be finite and >= 0, got " + num(cfg.hierarchy_slack));
  if (cfg.contact_sweeps < 0)
    throw ConfigError("StepConfig.contact_sweeps: must be >= 0, got " +
                      std::to_string(cfg.contact_sweeps));
  if (!(cfg.contact_tolerance >= Real(0)) || !std::isfinite(cfg.contact_tolerance))
    throw ConfigError("StepConfig.contact_tolerance: must be finite and >= 0, got " +
                      num(cfg.contact_tolerance));
}

void step(const Model& m, State& s, const StepConfig& cfg) {
  // Each stage runs inside timed(t, stage, has_work, ...) (profile.hpp),
  // which only times it when cfg.times is set and the stage has work.
  StageTimes* const t = cfg.times;
  // The coloured XPBD Distance sweep runs over the compiled stream, and so
  // does the array order where its levels pay; the coloured XPBD hinges and
  // tethers over theirs.
  const bool levels = distance_levels_apply(m, cfg), tether_levels = tether_levels_apply(m, cfg);
  const bool stream = (cfg.coloured && cfg.method == Method::xpbd && !m.get<Distance>().empty()) || levels;
  const bool hinges = cfg.coloured && cfg.method == Method::xpbd && !m.get<DihedralBending>().empty();
  const bool tethers = (cfg.coloured && cfg.method == Method::xpbd && !m.get<Tether>().empty()) || tether_levels;
  timed(t, stage::step_setup, true, [&] {
    validate(cfg);
    check_state_matches(m, s);
    if (cfg.coloured) check_colours(m);
    // Per-step constraint data: the side each penetration point starts on.
    begin_step_constraints(m, s);
    // Host-supplied rigid bodies, contacts and attachments: checked and sized.
    rigid::begin_step(m, s);
    if (cfg.direct_chains) {
      if (m.chains.num_distance != m.get<Distance>().size() ||
          !(m.chains.end_of.empty() || m.chains.end_of.size() == static_cast<std::size_t>(m.num_particles())))
        throw ConfigError("StepConfig.direct_chains: model.chains was found in " +
                          std::to_string(m.chains.num_distance) + " Distance elements, the model has " +
                          std::to_string(m.get<Distance>().size()) + " (or the particles changed; use compile)");
      if (m.trees.num_distance != m.get<Distance>().size() ||
          m.trees.num_particles != static_cast<std::size_t>(m.num_particles()))
        throw ConfigError("StepConfig.direct_chains: model.trees was found in " +
                          std::to_string(m.trees.num_distance) + " Distance elements and " +
                          std::to_string(m.trees.num_particles) + " particles, the model has " +
                          std::to_string(m.get<Distance>().size()) + " and " +
                          std::to_string(m.num_particles()) + " (use compile)");
      detail::chains_begin_step(m, s);
    }
    // The streams' factors for this step's substep (the h below).
    const Real sub_h = cfg.dt / Real(cfg.substeps);
    if (stream) detail::stream_begin_step(m, s, sub_h, cfg.workers, levels);
    if (hinges) detail::dihedral_begin_step(m, s, sub_h, cfg.workers);
    if (tethers) detail::tether_begin_step(m, s, sub_h, cfg.workers, tether_levels);
  });
  const bool refresh = cfg.contact_margin > Real(0) && static_cast<bool>(cfg.refresh_contacts);
  if (refresh) detail::begin_paths(m, s);
  // Opt-in particle-particle collision: candidate pairs within the contact
  // distance plus the step's travel, from a spatial hash (spatial_hash.hpp).
  timed(t, stage::self_collision_search, m.self_collision.enabled,
        [&] { find_self_collisions(m, s, cfg); });
  const Real h = cfg.dt / Real(cfg.substeps);

  SolveContext sc;
  sc.x = s.x.data();
  sc.x_prev = s.x_prev.data();
  sc.inv_mass = m.inv_mass.data();
  sc.h = h;
  sc.method = cfg.method;
  sc.eval.x = s.x.data();
  sc.eval.pin_target = s.pin_target_now.data();
  sc.eval.planes = m.planes.data();
  sc.eval.penetration_side = s.penetration_side.data();

  // The prediction writes the stream kernels' particle records (predict);
  // the substep's start too if a stream stage is damped.
  const std::size_t n4 = 4 * s.x.size();
  const bool any_stream = (stream || hinges || tethers) && s.stream_x.size() == n4;
  const bool damped_stream = (stream && m.has_damping[type_index_v<Distance>]) ||
                             (hinges && m.has_damping[type_index_v<DihedralBending>]) ||
                             (tethers && m.has_damping[type_index_v<Tether>]);
  Real* const rec = any_stream ? s.stream_x.data() : nullptr;
  Real* const rec_prev = any_stream && damped_stream && s.stream_x_prev.size() == n4 ? s.stream_x_prev.data() : nullptr;
  const bool chains = cfg.direct_chains && m.chains.size() > 0;
  const bool trees = cfg.direct_chains && m.trees.size() > 0;
  std::uint64_t sweeps = 0;  // in this step
  // The particles' velocity update that the next prediction runs (predict):
  // left to it when no stage in between touches a particle's velocity.
  VelocityUpdate pending;
  for (int sub = 0; sub < cfg.substeps; ++sub) {
    // What the records hold for the first sweep (solve_constraints).
    int records = rec == nullptr ? 0 : rec_prev == nullptr ? 1 : 2;
    timed(t, stage::predict, true, [&] {
      // 1. Move kinematic targets to where they are at the end of this substep.
      interpolate_pin_targets(s, Real(sub + 1) / Real(cfg.substeps));
      // 2. Predict: external forces and inertia; rigid bodies move with their velocity.
      predict(m, s, cfg, h, pending, rec, rec_prev);
      pending = VelocityUpdate{};
      // Particles that left the path their contacts cover get new ones
      // from the host (bodies it adds are at this substep's start, as the
      // others are until predict_bodies below). The host is not asked to
      // keep the records: they are written again after it ran.
      if (refresh) {
        const std::size_t contacts = s.contacts.size(), bodies = s.bodies.size();
        if (detail::refresh_escaped(m, s, cfg, sub, h)) {
          rigid::contacts_added(m, s, contacts, bodies);
          records = 0;
        }
      }
      // After predict: restitution's reference is the normal velocity with
      // this substep's gravity included (Mueller et al. 2020), not before it.
      rigid::begin_substep(m, s);
      rigid::predict_bodies(s.bodies, h);
      // Lambda starts at zero every substep (Algorithm 2, line 6).
      // (The coloured XPBD sweeps' first sweep takes its multipliers as 0
      // and writes them all; State::lambda of Distance, DihedralBending and
      // Tether is written at the end of the step.)
      reset_multipliers(s, stream, hinges, tethers);
    });
    // StepConfig::hierarchy: the coarse levels' one-sided pass.
    if (cfg.hierarchy) {
      timed(t, stage::of<Distance>, true, [&] { detail::hierarchy_pass(m, s, cfg.hierarchy_slack); });
      records = 0;
    }
    // 3. Solve: `iterations` Gauss-Seidel sweeps over all constraints, then
    // up to `contact_sweeps` more while a contact is violated when the
    // contacts' turn comes in the sweep (after the first sweep: the
    // prediction; after later ones: what the other constraints did to the
    // positions the contacts left; after the contacts' own projection the
    // violation is always about 0 and tells nothing).
    const bool check =
        cfg.contact_sweeps > 0 && (!s.contacts.empty() || !s.triangle_contacts.empty() || !s.edge_contacts.empty());
    Real violation = 0, before = 0;
    for (int it = 0; it < cfg.iterations + cfg.contact_sweeps; ++it) {
      if (it >= cfg.iterations &&
          !(violation > cfg.contact_tolerance && (it == 1 || violation < Real(0.9) * before)))
        break;
      before = violation;
      // StepConfig::alternate_sweeps: every other sweep, counted across
      // substeps and across steps (State::sweeps; so that one iteration per
      // substep, and one substep per step, alternate too), runs last to first.
      sc.reverse = cfg.alternate_sweeps && ((s.sweeps + sweeps) & 1) != 0;
      ++sweeps;
      solve_constraints(m, s, sc, cfg, levels, tether_levels, it == 0, t, it == 0 ? records : 0);
      if (chains) timed(t, stage::of<Distance>, true, [&] { detail::chains_solve(m, s, h, stream, cfg.chain_passes, cfg.chain_tolerance); });
      if (trees) timed(t, stage::of<Distance>, true, [&] { detail::trees_solve(m, s, h, stream, cfg.chain_passes, cfg.chain_tolerance); });
      timed(t, stage::self_collision_solve, !s.self_collision.pairs.empty(),
            [&] { solve_self_collisions(m, s, sc); });
      timed(t, stage::body_attachments, !s.attachments.empty(),
            [&] { rigid::solve_attachments(m, s, h); });
      // The bodies' contacts with the static world first: the particle
      // contacts, last, then leave no particle inside a body.
      timed(t, stage::body_contacts, !s.world_contacts.empty(), [&] { rigid::solve_world_contacts(s); });
      if (check) violation = rigid::worst_contact_violation(m, s, h);
      timed(t, stage::body_contacts, !s.contacts.empty(), [&] { rigid::solve_contacts(m, s, h); });
      timed(t, stage::triangle_contacts, !s.triangle_contacts.empty(),
            [&] { rigid::solve_triangle_contacts(m, s, h); });
      timed(t, stage::triangle_contacts, !s.edge_contacts.empty(), [&] { rigid::solve_edge_contacts(m, s, h); });
    }
    // The bodies' contacts with the static world once more: the particle
    // contacts above may have pushed a body into it, and an overlap a body
    // ends the step with is taken as the next step's starting overlap
    // (world_contact_slack), which XPBD then never removes.
    timed(t, stage::body_contacts, !s.world_contacts.empty(), [&] { rigid::solve_world_contacts(s); });
    rigid::collect_contact_impulses(s, h);
    // 4. Velocities from the position change.
    timed(t, stage::velocity_update, true, [&] {
      // A step shorter than the last (update_velocities). The step length,
      // not the substep: more substeps in the same step (the bridge's
      // tolerance controller) take the plain update.
      const Real r = cfg.dt < s.velocity_step ? cfg.dt / s.velocity_step : Real(1);
      const Real blend = r * r;
      // Left to the next substep's prediction if that comes next for the
      // particles: not after the last substep, nor before the contacts'
      // friction and restitution (stage 5).
      const VelocityUpdate u = velocity_update(cfg, h, blend);
      if (sub + 1 < cfg.substeps && s.contacts.empty() && s.triangle_contacts.empty() && s.edge_contacts.empty())
        pending = u;
      else
        update_velocities(m, s, cfg, u);
      rigid::update_body_velocities(s.bodies, h, blend);
      s.velocity_step = std::max({cfg.dt, s.velocity_step - h, Real(0.99) * s.velocity_step});
    });
    // 5. Contact friction and restitution on the new velocities.
    timed(t, stage::contact_velocities,
          !s.contacts.empty() || !s.triangle_contacts.empty() || !s.edge_contacts.empty(), [&] {
            if (!s.contacts.empty()) rigid::contact_velocities(m, s, h, cfg.gravity.norm());
            if (!s.triangle_contacts.empty()) rigid::triangle_contact_velocities(m, s, h);
            if (!s.edge_contacts.empty()) rigid::edge_contact_velocities(m, s, h);
          });
    timed(t, stage::contact_velocities, !s.world_contacts.empty(),
          [&] { rigid::world_contact_velocities(s, h); });
  }
  if (stream) detail::stream_end_step(m, s, levels);
  if (hinges) detail::dihedral_end_step(m, s);
  if (tethers) detail::tether_end_step(m, s, tether_levels);
  s.pin_target_prev = s.pin_target;  // same size: no allocation
  s.sweeps += sweeps;
  s.time += cfg.dt;
  s.last_substep = h;
  if (t != nullptr) ++t->steps;
}

}  // namespace xpbd
