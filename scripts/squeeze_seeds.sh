#!/usr/bin/env bash
# The bar-squeeze application (tests/integration/squeeze_app.hpp, the
# program tests/integration/squeeze_campaign.cpp) over wrinkle seeds 1-32 with 49 bodies at the defaults: one line per seed
# (deepest particle centre inside a body, frames deeper than the contact
# thickness, largest edge strain, sweeps per step, frames with an edge
# stretched over 20 %, such edges over the frames and how many of them pass
# through a body: through the bar, and at a particle attached to it). The
# figures in docs/squeeze.md come from this. About a minute in double at the
# defaults; about two with --strain 0.2.
#
#   scripts/squeeze_seeds.sh                    builds and uses build/double
#   BUILD_DIR=build/float scripts/squeeze_seeds.sh
#   scripts/squeeze_seeds.sh --no-surface-edges without ContactSettings::surface_edge_contacts (on by default
#                                               since 2026-11-29; --surface-edges: with it)
#   scripts/squeeze_seeds.sh --strain 0.2       with the tolerance's strain target (SystemSettings::tolerance.strain)
#   scripts/squeeze_seeds.sh --substeps 30      SystemSettings::substeps 30 instead of the default
#   scripts/squeeze_seeds.sh --iterations 2     Gauss-Seidel sweeps per substep (SystemSettings::iterations)
#   scripts/squeeze_seeds.sh --contact-sweeps 8 extra sweeps where contacts need them (SystemSettings::contact_sweeps)
#   scripts/squeeze_seeds.sh --hierarchy        SystemSettings::hierarchy (--alternate-sweeps: alternate_sweeps)
#   scripts/squeeze_seeds.sh --bend 0.1         the cloth's bending edges at 0.1 m/N (--shear C: its shear
#                                               edges; both rigid, 0, by default)
#   scripts/squeeze_seeds.sh --seeds 5-8        wrinkle seeds 5 to 8 only (--seeds 5: one seed)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${BUILD_DIR:-}" ]; then
  scripts/setup.sh double >/dev/null
fi
build="${BUILD_DIR:-build/double}"
cmake --build "$build" --target xpbd_squeeze_campaign >/dev/null
"$build/tests/xpbd_squeeze_campaign" "$@"
