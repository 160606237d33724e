#!/usr/bin/env bash
# The bar-squeeze application (tests/integration/squeeze_app.hpp, the
# program tests/integration/squeeze_campaign.cpp) over wrinkle seeds 1-32 with 49 bodies at the defaults: one line per seed
# (deepest particle centre inside a body, frames deeper than the contact
# thickness, largest edge strain, sweeps per step, frames with an edge
# stretched over 20 %, such edges over the frames and how many of them pass
# through a body). The figures in
# docs/squeeze.md come from this. About a minute in double.
#
#   scripts/squeeze_seeds.sh                    builds and uses build/double
#   BUILD_DIR=build/float scripts/squeeze_seeds.sh
#   scripts/squeeze_seeds.sh --surface-edges    with ContactSettings::surface_edge_contacts
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${BUILD_DIR:-}" ]; then
  scripts/setup.sh double >/dev/null
fi
build="${BUILD_DIR:-build/double}"
cmake --build "$build" --target xpbd_squeeze_campaign >/dev/null
"$build/tests/xpbd_squeeze_campaign" "$@"
