#!/usr/bin/env bash
# Installs the double and the float build side by side into one temporary
# prefix and uses them from outside the source tree, as a user would
# (docs/embedding.md):
#   1. cmake --install of both builds into one prefix; the files the two
#      share (headers, package config) must be identical, each precision's
#      own files present;
#   2. per precision, tests/consumer (find_package(xpbd_bullet CONFIG
#      REQUIRED COMPONENTS <p>)) configured, built and run on
#      demos/hello_cloth.cpp; find_package without a component picks float64;
#   3. pkg-config --cflags --libs for xpbd_bullet and xpbd_bullet-float64, and
#      hello_cloth compiled with the float64 flags and run;
#   4. negative cases: a float application (no BT_USE_DOUBLE_PRECISION) that
#      uses the float64 package, and a double one that uses the float package,
#      must fail to compile with the guard's message.
#
#   scripts/consumer_test.sh [DOUBLE_BUILD FLOAT_BUILD]   (default: build/double build/float,
#                                                          made by scripts/setup.sh double|float)
# Exits non-zero on the first failure, saying what failed.
set -euo pipefail
cd "$(dirname "$0")/.."
src="$PWD"
double_build="${1:-build/double}"
float_build="${2:-build/float}"
start=$SECONDS

fail() { echo "consumer_test: FAILED: $*" >&2; exit 1; }
for b in "$double_build" "$float_build"; do
  [ -f "$b/CMakeCache.txt" ] || fail "no build tree in $b (run scripts/setup.sh double and float first)"
done

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
log="$tmp/log"

# 1. Both installs into one prefix.
shared_sums() {
  (cd "$prefix" && find include/xpbd include/xpbd_bullet lib/cmake/xpbd_bullet/xpbd_bullet-config.cmake \
     lib/cmake/xpbd_bullet/xpbd_bullet-config-version.cmake lib/cmake/xpbd_bullet/xpbd_bullet-bullet.cmake \
     -type f -print0 | sort -z | xargs -0 sha256sum)
}
cmake --install "$double_build" --prefix "$prefix" >"$log" 2>&1 || { cat "$log"; fail "cmake --install $double_build"; }
shared_sums >"$tmp/shared.double"
cmake --install "$float_build" --prefix "$prefix" >"$log" 2>&1 || { cat "$log"; fail "cmake --install $float_build"; }
shared_sums >"$tmp/shared.float"
diff "$tmp/shared.double" "$tmp/shared.float" >/dev/null \
  || fail "the float install changed files the double install had put there: $(diff "$tmp/shared.double" "$tmp/shared.float" | head -5)"
libdir="$(cd "$prefix" && dirname "$(find . -name 'libxpbd-float64.*' | head -1)")"
[ "$libdir" != "." ] || fail "libxpbd-float64 not installed"
libdir="${libdir#./}"  # lib, or lib/<multiarch> for prefix /usr
for f in "$libdir"/libxpbd-float64 "$libdir"/libxpbd_bullet_bridge-float64 "$libdir"/libxpbd "$libdir"/libxpbd_bullet_bridge; do
  compgen -G "$prefix/$f.*" >/dev/null || fail "$f.* not installed"
done
for f in include/xpbd_bullet-float64/xpbd/config.hpp include/xpbd_bullet-float/xpbd/config.hpp \
         "$libdir"/cmake/xpbd_bullet/xpbd_bullet-float64-targets.cmake "$libdir"/cmake/xpbd_bullet/xpbd_bullet-float-targets.cmake \
         "$libdir"/pkgconfig/xpbd_bullet-float64.pc "$libdir"/pkgconfig/xpbd_bullet.pc; do
  [ -f "$prefix/$f" ] || fail "$f not installed"
done
echo "consumer_test: both precisions installed in one prefix ($(find "$prefix" -type f | wc -l) files)"

# 2. find_package, one project per precision.
consumer() {  # consumer <build dir> <cmake -D options...>
  local dir="$1"; shift
  cmake -S "$src/tests/consumer" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
    -DXPBD_CONSUMER_SOURCE="$src/demos/hello_cloth.cpp" "$@"
}
for p in float64 float; do
  consumer "$tmp/consumer-$p" -DXPBD_CONSUMER_PRECISION=$p >"$log" 2>&1 \
    || { cat "$log"; fail "configuring tests/consumer with COMPONENTS $p"; }
  grep -q "xpbd_bullet 0.*($p) from $prefix" "$log" || { cat "$log"; fail "COMPONENTS $p did not load the $p package"; }
  cmake --build "$tmp/consumer-$p" >"$log" 2>&1 || { cat "$log"; fail "building hello_cloth and hello_plugin (a shared library) against the $p package"; }
  rc=0
  "$tmp/consumer-$p/hello_cloth" >"$log" 2>&1 || rc=$?
  if [ $rc -ne 0 ] || ! grep -q "hello_cloth: ok" "$log"; then
    cat "$log"; fail "hello_cloth ($p package): exit status $rc"
  fi
  echo "consumer_test: find_package(xpbd_bullet CONFIG REQUIRED COMPONENTS $p): hello_cloth built and ran, hello_plugin (shared) linked"
done
consumer "$tmp/consumer-default" -DXPBD_CONSUMER_PRECISION= >"$log" 2>&1 \
  || { cat "$log"; fail "configuring tests/consumer without a component"; }
grep -q "(float64) from" "$log" || { cat "$log"; fail "find_package without a component did not pick float64"; }
echo "consumer_test: find_package(xpbd_bullet CONFIG REQUIRED) picks float64"

# 3. pkg-config.
export PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig"
for pc in xpbd_bullet xpbd_bullet-float64; do
  pkg-config --cflags --libs "$pc" >"$log" 2>&1 || { cat "$log"; fail "pkg-config --cflags --libs $pc"; }
done
pkg-config --cflags xpbd_bullet-float64 | grep -q -- -DBT_USE_DOUBLE_PRECISION \
  || fail "pkg-config --cflags xpbd_bullet-float64 lacks -DBT_USE_DOUBLE_PRECISION"
# shellcheck disable=SC2046  # pkg-config's output is a list of words
c++ -std=c++20 -O2 "$src/demos/hello_cloth.cpp" -o "$tmp/hello_cloth_pc" \
  $(pkg-config --cflags --libs xpbd_bullet-float64) >"$log" 2>&1 || { cat "$log"; fail "compiling hello_cloth with pkg-config xpbd_bullet-float64"; }
if ! "$tmp/hello_cloth_pc" >"$log" 2>&1 || ! grep -q "hello_cloth: ok" "$log"; then
  cat "$log"; fail "hello_cloth built with pkg-config xpbd_bullet-float64"
fi
echo "consumer_test: pkg-config xpbd_bullet and xpbd_bullet-float64 work; hello_cloth built with the latter ran"

# 4. The precision guard: a mismatch must not compile, and must say why.
consumer "$tmp/consumer-float-app" -DXPBD_CONSUMER_PRECISION=float64 -DXPBD_CONSUMER_FLOAT_APP=ON >"$log" 2>&1 \
  || { cat "$log"; fail "configuring the float application with COMPONENTS float64"; }
if cmake --build "$tmp/consumer-float-app" >"$log" 2>&1; then
  fail "a float application compiled against the float64 package"
fi
msg="xpbd_bullet: this is the double-precision (float64) package but this file is compiled for float Bullet"
grep -q "$msg" "$log" || { cat "$log"; fail "the float application failed without the guard's message"; }
grep -q "COMPONENTS float" "$log" || { cat "$log"; fail "the guard's message does not name the fix"; }
echo "consumer_test: a float application using the float64 package fails to compile:"
grep -m1 -o "#error .*" "$log" | sed 's/^/  /'
# shellcheck disable=SC2046
if c++ -std=c++20 -fsyntax-only -DBT_USE_DOUBLE_PRECISION "$src/demos/hello_cloth.cpp" \
     $(pkg-config --cflags xpbd_bullet) >"$log" 2>&1; then
  fail "a double application compiled against the float package"
fi
grep -q "xpbd_bullet: this is the float package but this file is compiled for double Bullet" "$log" \
  || { cat "$log"; fail "the double application failed without the guard's message"; }
echo "consumer_test: a double application using the float package fails to compile with the guard's message"

echo "consumer_test: ok ($((SECONDS - start)) s)"
