// Typed ids (world.hpp): a system id, an attachment id and a plain int (a
// particle index, a count) cannot be passed for one another. Checked at
// compile time; the test body checks the values and the printing.
#include <gtest/gtest.h>

#include <sstream>
#include <type_traits>

#include "xpbd_bullet/world.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd_bullet::AttachmentId;
using xpbd_bullet::SystemId;
using xpbd_bullet::XpbdWorld;

static_assert(!std::is_convertible_v<int, SystemId>);
static_assert(!std::is_convertible_v<SystemId, int>);
static_assert(!std::is_convertible_v<AttachmentId, SystemId>);
static_assert(!std::is_convertible_v<SystemId, AttachmentId>);
static_assert(std::is_invocable_v<decltype(&XpbdWorld::remove_attachment), XpbdWorld&, AttachmentId>);
static_assert(!std::is_invocable_v<decltype(&XpbdWorld::remove_attachment), XpbdWorld&, SystemId>);
static_assert(!std::is_invocable_v<decltype(&XpbdWorld::remove_attachment), XpbdWorld&, int>);
static_assert(std::is_invocable_v<decltype(&XpbdWorld::remove_system), XpbdWorld&, SystemId>);
static_assert(!std::is_invocable_v<decltype(&XpbdWorld::remove_system), XpbdWorld&, AttachmentId>);
static_assert(!std::is_invocable_v<decltype(&XpbdWorld::remove_system), XpbdWorld&, int>);
static_assert(std::is_same_v<decltype(std::declval<XpbdWorld&>().add_system({}, {})), SystemId>);

TEST(TypedIds, ValuesCompareAndPrint) {
  EXPECT_EQ(SystemId(3), SystemId(3));
  EXPECT_NE(SystemId(3), SystemId(4));
  EXPECT_LT(SystemId(3), SystemId(4));
  EXPECT_EQ(SystemId().value, -1);
  std::ostringstream o;
  o << SystemId(2) << ", " << AttachmentId(5);
  EXPECT_EQ(o.str(), "system 2, attachment 5");
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
