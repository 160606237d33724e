#include <gtest/gtest.h>
#include "xpbd/xpbd.hpp"
TEST(Sanity, Builds) {
  xpbd::SceneDesc s;
  xpbd::add_rope(s, {});
  auto m = xpbd::compile(s);
  auto st = xpbd::make_state(m);
  xpbd::step(m, st, {});
  EXPECT_TRUE(st.x[5].allFinite());
}
