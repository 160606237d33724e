#!/usr/bin/env bash
# README command (1): installs what is missing, builds, runs the default
# headless demo scene and prints its summary. Extra arguments go to xpbd-demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh double >/dev/null
exec build/double/demos/xpbd-demo "$@"
