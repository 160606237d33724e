#pragma once
#include <functional>
#include <span>

#include "xpbd/model.hpp"
#include "xpbd/profile.hpp"
#include "xpbd/state.hpp"

namespace xpbd {

class Workers;

enum class Method {
  xpbd,  // Algorithm 2 of the seed report: compliance alpha, lambda reset per substep
  pbd,   // Algorithm 1: stiffness k in [0, 1], iteration-dependent by design
};

struct StepConfig {
  Real dt = Real(1) / Real(60);  // s, length of one step (> 0)
  int substeps = 10;             // >= 1; substep h = dt / substeps
  int iterations = 1;            // >= 1, Gauss-Seidel sweeps per substep
  Method method = Method::xpbd;
  Vec3 gravity{Real(0), Real(-9.81), Real(0)};  // m/s^2
  // Velocity damping rate (1/s): v *= exp(-drag*h) every substep. 0 = none.
  Real drag = 0;
  // Symmetric Gauss-Seidel: every other sweep (counted across substeps and
  // across step() calls, State::sweeps) visits the elements of each
  // constraint type last to first. Off by
  // default. A fixed order lets the elements solved first win every sweep;
  // where the solve does not converge, that pushes the solution towards one
  // side of the mesh (a heavy ball on a grid cloth walks towards the rows
  // solved first). Alternating removes that bias but converges more slowly
  // on chains and hanging cloth pinned at the end solved first (measured:
  // Fig. 5's XPBD strain at 5 iterations rose from below 1% to 4%). With one
  // iteration per substep the direction flips from substep to substep, and
  // the correction bias that flips with it becomes velocity (v = dx/h):
  // stiff cloths explode at every budget from 10 x 1 to 160 x 1
  // (docs/convergence.md). Use it with iterations >= 2.
  bool alternate_sweeps = false;
  // Direct solve along chains (chains.hpp; XPBD only, off by default): in
  // every sweep, after the constraint types, each chain of Model::chains
  // (with the one body attachment at either end, if any) has its linearised
  // system solved exactly, in time linear in its length: a Newton pass.
  // Passes repeat, up to chain_passes, while some element's residual
  // |C + alpha/h^2 lambda| is above chain_tolerance times its rest length
  // (an attachment's: the chain's first element's); a chain already within
  // it gets no pass. One pass is not enough where the chain moves fast: on
  // heavy_rope at 10 x 1 one pass left 367 % strain, 16 passes to 1e-3
  // left 0.8 % (docs/convergence.md). A chain's elements are still swept
  // too. A chain whose system is singular (a taut straight chain between
  // two kinematic ends at compliance 0) is left to the sweep in that pass.
  // Then each tree of Model::trees (trees.hpp: branched, without loops) is
  // solved the same way, over the particles' moves and the multipliers.
  bool direct_chains = false;
  int chain_passes = 16;               // >= 1
  Real chain_tolerance = Real(1e-3);   // >= 0, relative to rest length
  // Hierarchical PBD (Mueller 2008; off by default; either method): coarse
  // levels over the Distance elements' graph, each a maximal independent
  // set of the finer one, joined by one-sided edges through the particles
  // they share. Before the sweeps of every substep, each coarse edge
  // stretched beyond its rest length times (1 + hierarchy_slack) is pulled
  // back to it, coarsest level first, and the finer particles follow their
  // coarse neighbours' displacement; then the sweeps run as without it. A
  // structure whose strain stays below the slack is stepped exactly as
  // without the hierarchy; beyond it, the pass's displacement is in no
  // multiplier (not in the forces read from lambda) and holds the coarse
  // strain near the slack whatever the material's compliance, so the slack
  // must exceed the elastic strain the material should reach. Built on the
  // first step that uses it (src/hierarchy.hpp). On the stiff cloths of
  // docs/convergence.md it added 20-50 % to the time per frame at 10 x 1.
  bool hierarchy = false;
  Real hierarchy_slack = Real(0.01);   // >= 0, strain
  // Coloured sweep of the Distance elements: they are projected in the order
  // of Model::distance_colours (model.hpp: colour by colour, no two elements
  // of a colour sharing a particle, so consecutive projections do not wait
  // for each other). With XPBD the elements are read from their compiled
  // form, Model::distance_stream (distance_stream.hpp), by a vector kernel
  // where the CPU has one (see simd); PBD runs the scalar kernel over
  // Model::distance_by_colour (solve.hpp, project_all_coloured), on the
  // calling thread. With XPBD the DihedralBending and Tether elements too
  // are swept colour by colour (Model::dihedral_colours, tether_colours)
  // over their compiled forms (dihedral_stream.hpp, distance_stream.hpp;
  // AVX2 where the CPU has it). Off by default: worse in depth where a heavy
  // body squeezes cloth (docs/bench-coloured.md, "The switch tried, and not
  // made"), and since the array order runs over its levels (levels, below)
  // no longer ahead per unit time on the 64 x 64 hanging cloth: about 0.9x
  // the array order's time per substep for 1.6x its strain
  // (docs/bench-levels.md). Every other type keeps the
  // array order. This is a different Gauss-Seidel order, so the result
  // differs from the array order's (both converge to the same solution, at
  // different rates). With alternate_sweeps, the reversed sweeps visit the
  // colours last to first. Measured on the 64 x 64 hanging cloth
  // (docs/bench-coloured.md, "Coloured sweep"): 12 colours; with the AVX2
  // kernel an XPBD step was 2.1-2.4x (double) and 2.6-3.1x (float) as fast
  // as the array order element by element (levels off); per sweep it
  // converges less (mean strain 1.3-1.7x the array order's at the same
  // budget). The same cloth tethered to its two pins ("bench_tethers"):
  // 1.9-2.2x in double.
  bool coloured = false;
  // XPBD's array-order Distance and Tether sweeps (coloured off) run over
  // array order's levels (Model::distance_levels, tether_levels) with the
  // vector kernels: the same results bit for bit as the element-by-element
  // kernels (but for the sign of a zero coordinate), 2.4-2.9 times as fast
  // per step on cloths from 32 x 32 to 256 x 256 and 2.0 times at 512 x 512
  // and 1024 x 1024 (docs/bench-levels.md). Each type's levels apply only
  // where they hold 3 elements or more on average (not on a single rope),
  // with simd on, on a CPU with a vector kernel; the Distance levels not
  // with direct_chains. Off = the element-by-element kernels; this exists
  // to measure one against the other.
  bool levels = true;
  // The coloured XPBD sweep runs the widest kernel this CPU has
  // (simd_kernel(): AVX-512, AVX2 or scalar; set_simd_kernel caps it), and
  // the prediction (every substep, in either order) runs an AVX-512 kernel
  // where that is the kernel. Off = the scalar kernels. All give the same
  // results bit for bit; this exists to measure one against the other.
  bool simd = true;
  // Threads for the coloured XPBD Distance, DihedralBending and Tether
  // sweeps and the per-particle stages (workers.hpp; needs coloured,
  // nullptr = the calling thread only). Each colour's elements are split
  // over the pool's threads, the colours in turn, and so are the copy of the
  // particles in and out of the stream, the prediction and the velocity
  // update: the result is bit for bit the single-threaded coloured step's.
  // Pieces below 512 elements or particles run on the calling thread. Every
  // other stage (the other constraint types, contacts) and PBD's coloured
  // sweep stay on the calling thread.
  Workers* workers = nullptr;
  // Extra sweeps where contacts need them (off by default): after the
  // `iterations` sweeps of a substep, another sweep runs while some body or
  // triangle contact is violated by more than contact_tolerance times its
  // thickness when the contacts' turn comes in the sweep (before they are
  // projected; rigid::worst_contact_violation) and that violation fell by at
  // least 10% since the sweep before; at most `contact_sweeps` more per
  // substep. The violation counts only contacts the host supplied for the
  // step. Costs one pass over the contacts per sweep when on. Measured in
  // docs/design.md, "Heavy on light": why it is not the default.
  int contact_sweeps = 0;
  Real contact_tolerance = Real(0.1);
  // Contacts that stay complete over the step (off unless both are set).
  // A host finds State::contacts once per step, for each particle within a
  // reach of where it starts; they cover the particle while it stays within
  // contact_margin (m) of the straight path from its start position along
  // its start velocity. The solve can carry a particle farther than that
  // (a cloth whipped by its edges into a body it was not near), and then
  // it has no contact with what it meets. With both set, every substep
  // checks each movable particle's predicted position against its path
  // (one pass over the particles) and passes the particles that left it to
  // refresh_contacts, before the substep's solve, with each such particle
  // at State::x_prev and moving at State::v. The host may append contacts
  // for them to State::contacts (kept for the rest of the step) and bodies
  // to State::bodies (each at its state at the start of this substep). The
  // path of a passed particle restarts there: x_prev + (t - t_sub) * v.
  Real contact_margin = 0;
  std::function<void(std::span<const Index> escaped, int substep)> refresh_contacts;
  // Opt-in per-stage wall-clock breakdown (profile.hpp): when set, step()
  // adds each stage's time to *times. nullptr (default) = no timing. Does not
  // change the result: the trajectory is the same bit for bit.
  StageTimes* times = nullptr;
};

// Advances `state` by cfg.dt:
//   for each substep: predict, solve (iterations x constraint types), update velocities.
// Throws ConfigError for an invalid cfg, or if state does not match model.
// Performs no allocation once the state's arrays have their sizes (but for
// what refresh_contacts adds).
void step(const Model& model, State& state, const StepConfig& cfg);

// Checks that cfg is valid; throws ConfigError naming the field and value.
void validate(const StepConfig& cfg);

// True where step(model, state, cfg) runs an array-order sweep (Distance,
// Tether or both) over the model's levels with the vector kernel
// (StepConfig::levels says where); false where it runs the
// element-by-element kernels or another order. The result is the same bit
// for bit either way (but for the sign of a zero coordinate:
// docs/bench-levels.md).
bool uses_levels(const Model& model, const StepConfig& cfg);

}  // namespace xpbd
